// Hamilton quaternions for attitude (docs/attitude.md): scalar first, q = (w, x, y, z), the
// product of Hamilton's convention (i j = k), and the attitude q mapping body axes to inertial
// ones, v_inertial = q v_body q*, so that q' = 1/2 q (x) (0, omega) with omega in body axes.
// Generic in the number type (`using std::sqrt` lookup, constants built in T).
#pragma once

#include <eulervop/core/vec3.hpp>

#include <cmath>

namespace eulervop {

template <class T>
struct quaternion {
  T w{}, x{}, y{}, z{};

  friend bool operator==(const quaternion&, const quaternion&) = default;
};

// a (x) b, Hamilton's product.
template <class T>
quaternion<T> operator*(const quaternion<T>& a, const quaternion<T>& b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

template <class T>
quaternion<T> conjugate(const quaternion<T>& q) {
  return {q.w, -q.x, -q.y, -q.z};
}

template <class T>
T norm(const quaternion<T>& q) {
  using std::sqrt;
  return sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
}

template <class T>
quaternion<T> normalized(const quaternion<T>& q) {
  const T n = norm(q);
  return {q.w / n, q.x / n, q.y / n, q.z / n};
}

// q v q* for a unit q: v from the body axes to the inertial ones.
template <class T>
vec3<T> rotate(const quaternion<T>& q, const vec3<T>& v) {
  const quaternion<T> r = q * quaternion<T>{T(0), v[0], v[1], v[2]} * conjugate(q);
  return {r.x, r.y, r.z};
}

// The rotation by `angle` about the unit vector `axis`.
template <class T>
quaternion<T> axis_angle(const vec3<T>& axis, const T& angle) {
  using std::cos;
  using std::sin;
  const T h = angle / 2, s = sin(h);
  return {cos(h), axis[0] * s, axis[1] * s, axis[2] * s};
}

// 1/2 q (x) (0, omega): the attitude's derivative for body rates omega.
template <class T>
quaternion<T> attitude_rate(const quaternion<T>& q, const vec3<T>& omega) {
  const quaternion<T> d = q * quaternion<T>{T(0), omega[0], omega[1], omega[2]};
  return {d.w / 2, d.x / 2, d.y / 2, d.z / 2};
}

// The angle of the rotation from p to q, 2 atan2(|vec(p* q)|, |scalar(p* q)|), in [0, pi]: the
// same for q and -q, which are the same attitude.
template <class T>
T rotation_angle(const quaternion<T>& p, const quaternion<T>& q) {
  using std::abs;
  using std::atan2;
  using std::sqrt;
  const quaternion<T> d = conjugate(p) * q;
  return 2 * atan2(sqrt(d.x * d.x + d.y * d.y + d.z * d.z), abs(d.w));
}

}  // namespace eulervop
