// The gravity-gradient torque on a circular orbit (docs/attitude.md, "The orbit's convention").
//
// The orbit lies in the inertial x-y plane with mean motion n: at time t the body's position
// direction is r = (cos n t, sin n t, 0). In the body's axes r_b = R(q)^T r, R(q) the rotation of
// the attitude q (body to inertial), and the torque is 3 n^2 r_b x (I r_b) (Hughes, "Spacecraft
// Attitude Dynamics", 2004, section 8.2; Wie, "Space Vehicle Dynamics and Control", 2008,
// section 6.3). In components, with I diagonal in the listed axes,
//   M_1 = 3 n^2 (I_3 - I_2) b_2 b_3,  M_2 = 3 n^2 (I_1 - I_3) b_3 b_1,  M_3 = 3 n^2 (I_2 - I_1) b_1 b_2.
// R(q) is written for a unit q (its entries 1 - 2(q_j^2 + q_k^2) on the diagonal): the integrated
// q keeps its unit norm to the rounding of the run, and the metadata records its drift.
#pragma once

#include <eulervop/core/vec3.hpp>

#include <array>
#include <cmath>

namespace eulervop {

template <class T>
struct gravity_gradient {
  T mean_motion{};              // n, rad per unit of the scene's time
  vec3<T> moments{};            // I in the listed axes
  using attitude_values = std::array<T, 4>;

  // r_b and its partials by q at time t: db[j][m] = d b_j / d q_m.
  void direction(const T& t, const attitude_values& q, vec3<T>& b, std::array<std::array<T, 4>, 3>* db) const {
    using std::cos;
    using std::sin;
    const T c = cos(mean_motion * t), s = sin(mean_motion * t);
    const T &q0 = q[0], &q1 = q[1], &q2 = q[2], &q3 = q[3];
    // b_j = R_0j c + R_1j s (r has no z component).
    b[0] = (1 - 2 * (q2 * q2 + q3 * q3)) * c + 2 * (q1 * q2 + q0 * q3) * s;
    b[1] = 2 * (q1 * q2 - q0 * q3) * c + (1 - 2 * (q1 * q1 + q3 * q3)) * s;
    b[2] = 2 * (q1 * q3 + q0 * q2) * c + 2 * (q2 * q3 - q0 * q1) * s;
    if (!db) return;
    *db = {{{2 * q3 * s, 2 * q2 * s, 2 * q1 * s - 4 * q2 * c, 2 * q0 * s - 4 * q3 * c},
            {-2 * q3 * c, 2 * q2 * c - 4 * q1 * s, 2 * q1 * c, -2 * q0 * c - 4 * q3 * s},
            {2 * q2 * c - 2 * q1 * s, 2 * q3 * c - 2 * q0 * s, 2 * q0 * c + 2 * q3 * s, 2 * q1 * c + 2 * q2 * s}}};
  }

  // The torque at time t and attitude q, in the listed axes; with dM, also its partials by q.
  vec3<T> value(const T& t, const attitude_values& q, std::array<std::array<T, 4>, 3>* dM = nullptr) const {
    vec3<T> b;
    std::array<std::array<T, 4>, 3> db;
    direction(t, q, b, dM ? &db : nullptr);
    const T k = 3 * mean_motion * mean_motion;
    vec3<T> M;
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, l = (i + 2) % 3;
      const T coefficient = k * (moments[l] - moments[j]);
      M[i] = coefficient * b[j] * b[l];
      if (dM)
        for (int m = 0; m < 4; ++m) (*dM)[i][m] = coefficient * (db[j][m] * b[l] + b[j] * db[l][m]);
    }
    return M;
  }

  template <class U>
  gravity_gradient<U> to() const {
    return {static_cast<U>(mean_motion),
            {static_cast<U>(moments[0]), static_cast<U>(moments[1]), static_cast<U>(moments[2])}};
  }
};

}  // namespace eulervop
