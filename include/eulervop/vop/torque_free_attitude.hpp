// The exact torque-free motion of a rigid body: body rates AND attitude, in closed form, in any
// scalar type (docs/attitude-closed-form.md).
//
//   torque_free_attitude<T> body(moments, omega0, q0);   // moments > 0 in any order, equal allowed
//   vec3<T> w = body.omega(t);          // rad/s in the body axes as listed
//   quaternion<T> q = body.attitude(t); // body -> inertial, v_i = q v_b q* (core/quaternion.hpp)
//   vec3<T> L = body.angular_momentum();// inertial q (I omega) q*, constant
//
// t = 0 is the time of omega0 and q0; any real t may be asked for, in any order. q0 is used as
// given (not renormalized), so |q(t)| = |q0|. For MPFR, construct and evaluate under one
// mpfr_precision_scope.
//
// Accuracy: omega(t) and attitude(t) are evaluated directly at t (no stepping), so nothing
// accumulates; the phases (w, h t / I_p, 2 j Pi(n)) carry a relative rounding of a few eps, and the
// error grows like eps times the angle turned (quad: 3e-31 rad after 100 rate periods of a generic
// body). This is backward stable: near the separatrix, where one ulp of an input changes the
// period by ~eps / (kappa kc^2 K), the error grows accordingly (quad, kappa = 1 - 1e-6, 100 periods:
// 3e-26 rad, what one ulp of one input causes); evaluate one precision up for more
// (tests/test_torque_free_attitude.cpp). Cost per call: omega 0.1 / 4 / 19 us and attitude
// 2 / 52 / 220 us in double / quad / mpfr:256, the latter nearly all Boost.Math's ellint_3.
//
// Method (after Landau & Lifshitz, Mechanics, section 37; Celledoni, Fasso, Safstrom & Zanna,
// SIAM J. Sci. Comput. 30 (2008); van Zon & Schofield, J. Comput. Phys. 225 (2007)):
//
// * Three distinct moments. The body axes are mapped onto the principal order I1 < I2 < I3 by the
//   proper rotation of principal_axes.hpp; the rates follow Eq. 12 of the paper in the frame of
//   vop/frame.hpp, W = (d1 cn w, d1 sn w, d2 dn w), w = w0 + d2 sqrt(A1 A2 A3) t, modulus
//   kappa = d1/d2 < 1 (design.md 1.3): d = (c1, c2) for k < 1, (c2, c1) for k > 1. The principal
//   axes are renamed (x, y, p): x carries cn, y carries sn, and p, the polar axis, carries dn,
//   whose rate never changes sign: (x, y, p) = (1, 2, 3) for k < 1 and (3, 2, 1) for k > 1. With
//   sigma the frame's sign, m = I omega has m_x = alpha cn, m_y = sigma beta sn,
//   m_p = sigma gamma dn, alpha = I_x sqrt(A_x) d1, beta = I_y sqrt(A_y) d1, gamma = I_p sqrt(A_p) d2.
//   The attitude is written with z-x-z Euler angles about an inertial frame F whose third axis is
//   L/h, in a right-handed principal frame (a, b, p): (1, 2, 3) for k < 1, (2, 3, 1) for k > 1:
//     body(a,b,p) -> F = R_z(phi) R_x(theta) R_z(psi),  m = h (sin theta sin psi,
//                                                             sin theta cos psi, cos theta),
//   so theta and psi follow from m(t). psi is taken continuous in t through the amplitude
//   am w = j pi + a_r (|a_r| <= pi/2, cn(a_r) >= 0):
//     k < 1:  psi = pi/2 - sigma (j pi + atan2(beta sn, alpha cn)),
//     k > 1:  psi = sigma (j pi + atan2(beta sn, alpha cn)),
//   with sn, cn of the reduced argument; the j pi turn is applied as an exact quaternion.
//   phi' = h (I_a w_a^2 + I_b w_b^2) / (I_a^2 w_a^2 + I_b^2 w_b^2), which on the solution is
//     phi' = h / I_p + h (1/I_x - 1/I_p) / (1 - n sn^2 w),   n = -I_p (I_y - I_x) / (I_x (I_p - I_y)) < 0,
//   (n depends on the moments only; at sn = 0 phi' = h/I_x, at sn = +-1 phi' = h/I_y), so that
//     phi(t) - phi(0) = h t / I_p + h (1/I_x - 1/I_p) [Pi(n; am w) - Pi(n; am w0)] / (d2 sqrt(A1A2A3)),
//   Pi(n; phi | kappa) = int_0^phi dt / ((1 - n sin^2 t) sqrt(1 - kappa^2 sin^2 t)) (Boost.Math's
//   ellint_3(kappa, n, phi) convention), Pi(n; j pi + a_r) = 2 j Pi(n) + Pi(n; a_r).
//   Then q(t) = q_F (x) qz(phi(t) - phi(0)) (x) qx(theta(t)) (x) qz(psi(t)) (x) q_B, with q_B the
//   quaternion of the map from the listed axes to (a, b, p) and q_F fixed by q(0) = q0.
//   k = 1 exactly (the separatrix: a heteroclinic orbit) throws std::domain_error.
// * Two equal moments I_a = I_b = I_perp != I_p (axisymmetric): with Omega = (I_p - I_perp) w_p / I_perp,
//   (w_a, w_b) turns by Omega t about the symmetry axis e_p, and
//     q(t) = axis_angle(L/h, h t / I_perp) (x) q0 (x) axis_angle(e_p, -Omega t).
// * Steady rotation (a sphere, omega = 0, or omega along a principal axis of distinct moments):
//   omega constant and q(t) = q0 (x) axis_angle(omega/|omega|, |omega| t).
#pragma once

#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/model/principal_axes.hpp>
#include <eulervop/special/elliptic.hpp>
#include <eulervop/vop/frame.hpp>

#include <boost/math/constants/constants.hpp>
#include <boost/math/special_functions/ellint_3.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace eulervop {

namespace detail {

// The rotation by `angle` about the third (first) axis of the frame it acts in.
template <scalar T>
quaternion<T> quaternion_z(const T& angle) {
  using std::cos;
  using std::sin;
  const T h = angle / 2;
  return {cos(h), T(0), T(0), sin(h)};
}

// The quaternion of a proper rotation matrix R (v -> R v), Shepperd's choice of the largest
// pivot; exact up to one square root for the signed permutation matrices used here.
template <scalar T>
quaternion<T> quaternion_of_matrix(const std::array<std::array<int, 3>, 3>& R) {
  using std::sqrt;
  const int tr = R[0][0] + R[1][1] + R[2][2];
  quaternion<T> q;
  if (tr >= R[0][0] && tr >= R[1][1] && tr >= R[2][2]) {
    q.w = sqrt(T(1 + tr)) / 2;
    const T f = 4 * q.w;
    q.x = T(R[2][1] - R[1][2]) / f;
    q.y = T(R[0][2] - R[2][0]) / f;
    q.z = T(R[1][0] - R[0][1]) / f;
  } else if (R[0][0] >= R[1][1] && R[0][0] >= R[2][2]) {
    q.x = sqrt(T(1 + R[0][0] - R[1][1] - R[2][2])) / 2;
    const T f = 4 * q.x;
    q.w = T(R[2][1] - R[1][2]) / f;
    q.y = T(R[0][1] + R[1][0]) / f;
    q.z = T(R[0][2] + R[2][0]) / f;
  } else if (R[1][1] >= R[2][2]) {
    q.y = sqrt(T(1 + R[1][1] - R[0][0] - R[2][2])) / 2;
    const T f = 4 * q.y;
    q.w = T(R[0][2] - R[2][0]) / f;
    q.x = T(R[0][1] + R[1][0]) / f;
    q.z = T(R[1][2] + R[2][1]) / f;
  } else {
    q.z = sqrt(T(1 + R[2][2] - R[0][0] - R[1][1])) / 2;
    const T f = 4 * q.z;
    q.w = T(R[1][0] - R[0][1]) / f;
    q.x = T(R[0][2] + R[2][0]) / f;
    q.y = T(R[1][2] + R[2][1]) / f;
  }
  return q;
}

// The matrix of v -> to_principal(v) of an axis permutation: row i has sign(i) in column axis(i).
inline std::array<std::array<int, 3>, 3> matrix_of(const axis_permutation& p) {
  std::array<std::array<int, 3>, 3> R{};
  for (int i = 0; i < 3; ++i) R[i][p.axis(i)] = p.sign(i);
  return R;
}

inline std::array<std::array<int, 3>, 3> matrix_product(const std::array<std::array<int, 3>, 3>& A,
                                                       const std::array<std::array<int, 3>, 3>& B) {
  std::array<std::array<int, 3>, 3> C{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) C[i][j] += A[i][k] * B[k][j];
  return C;
}

}  // namespace detail

template <scalar T>
class torque_free_attitude {
 public:
  enum class motion {
    steady,        // omega constant: a sphere, omega = 0, or omega along a principal axis
    axisymmetric,  // two equal moments
    triaxial,      // three distinct moments, elliptic functions
  };

  // moments: positive, in any order, equal allowed; omega0 (rad/s) in the same body axes; q0 a
  // unit quaternion, body -> inertial, at t = 0. std::domain_error for a moment <= 0, a value that
  // is not finite, and on the separatrix (three distinct moments and k = 1 exactly, unless omega0
  // lies along the intermediate axis, a steady rotation).
  torque_free_attitude(const vec3<T>& moments, const vec3<T>& omega0, const quaternion<T>& q0)
      : moments_(moments), omega0_(omega0), q0_(q0) {
    using std::isfinite;
    for (int i = 0; i < 3; ++i) {
      if (!(moments[i] > 0) || !isfinite(moments[i]))
        throw std::domain_error("torque_free_attitude: the moments of inertia must be positive and finite");
      if (!isfinite(omega0[i])) throw std::domain_error("torque_free_attitude: omega0 must be finite");
    }
    if (!isfinite(q0.w) || !isfinite(q0.x) || !isfinite(q0.y) || !isfinite(q0.z))
      throw std::domain_error("torque_free_attitude: q0 must be finite");
    vec3<T> m;
    for (int i = 0; i < 3; ++i) m[i] = moments[i] * omega0[i];
    L_ = rotate(q0, m);
    const bool e01 = moments[0] == moments[1], e12 = moments[1] == moments[2], e02 = moments[0] == moments[2];
    const bool at_rest = omega0[0] == 0 && omega0[1] == 0 && omega0[2] == 0;
    if (at_rest || (e01 && e12)) {
      init_steady();
    } else if (e01 || e12 || e02) {
      init_axisymmetric(e01 ? 2 : e12 ? 0 : 1);
    } else {
      init_triaxial();
    }
  }

  // The body rates at t, rad/s in the body axes as listed.
  vec3<T> omega(const T& t) const {
    switch (kind_) {
      case motion::steady: return omega0_;
      case motion::axisymmetric: return axi_omega(t);
      case motion::triaxial: break;
    }
    const phase ph = phase_at(t, false);
    const T& d1 = tri_->d1;
    const T& d2 = tri_->d2;
    const vec3<T> W = {d1 * ph.cn, d1 * ph.sn, d2 * ph.dn};
    return tri_->scaling.omega_of_Omega(tri_->frame.unrotate(W));
  }

  // The attitude at t: body -> inertial, v_i = q v_b q*, continuous in t with q(0) = q0.
  quaternion<T> attitude(const T& t) const {
    switch (kind_) {
      case motion::steady: return q0_ * axis_angle(steady_axis_, T(steady_rate_ * t));
      case motion::axisymmetric:
        return axis_angle(axi_->Lhat, T(axi_->precession_rate * t)) * q0_ *
               axis_angle(axi_->e_p, T(-(axi_->spin_rate * t)));
      case motion::triaxial: break;
    }
    const tri_data& d = *tri_;
    const phase ph = phase_at(t);
    const T dphi = d.h_over_Ip * t + d.phi_coef * (2 * (ph.j - d.j0) * d.Pi_complete + (ph.Pi_r - d.Pi_r0));
    return d.qF * detail::quaternion_z(dphi) * euler_body(ph) * d.qB;
  }

  // The inertial angular momentum q (I omega) q*, constant.
  const vec3<T>& angular_momentum() const { return L_; }

  motion kind() const { return kind_; }

  // The period of the body rates omega(t): 4K(kappa) / (d2 sqrt(A1 A2 A3)) (three distinct
  // moments), 2 pi / |Omega| (axisymmetric); infinity when omega is constant.
  T rates_period() const {
    switch (kind_) {
      case motion::steady: return std::numeric_limits<T>::infinity();
      case motion::axisymmetric: {
        using std::abs;
        if (axi_->spin_rate == 0) return std::numeric_limits<T>::infinity();
        return 2 * boost::math::constants::pi<T>() / abs(axi_->spin_rate);
      }
      case motion::triaxial: break;
    }
    return 2 * tri_->modulus.two_K() / tri_->freq;
  }

  // Three distinct moments: the modulus kappa = d1/d2 < 1 of the elliptic functions, and whether
  // the body turns about its minor axis (k = c1/c2 > 1, kappa = 1/k). std::logic_error otherwise.
  const T& modulus() const { return tri().modulus.k(); }
  bool minor_axis() const { return tri().frame.minor_axis(); }

 private:
  // Everything the elliptic functions give at one t: w = w0 + freq t reduced as w = 2 j K + r,
  // |r| <= K; sn, cn, dn of w; sn, cn of r (am r = a_r in [-pi/2, pi/2]); Pi(n; a_r).
  struct phase {
    T j;
    T sn, cn, dn;
    T sn_r, cn_r;
    T Pi_r;
  };

  struct tri_data {
    physical_scaling<T> scaling;
    vop_frame<T> frame;
    elliptic_modulus<T> modulus;
    T d1, d2, w0, freq;          // elements and dw/dt
    T alpha, beta, gamma;        // m_x = alpha cn, m_y = sigma beta sn, m_p = sigma gamma dn
    T h_over_Ip, phi_coef, n, Pi_complete;
    T j0, Pi_r0;                 // the phase at t = 0
    quaternion<T> qB, qF;
  };

  struct axi_data {
    int p;                          // the symmetry axis (listed order); (p+1, p+2, p) is right-handed
    vec3<T> e_p, Lhat;
    T precession_rate, spin_rate;  // h / I_perp and Omega = (I_p - I_perp) w_p / I_perp
  };

  const tri_data& tri() const {
    if (!tri_) throw std::logic_error("torque_free_attitude: modulus and regime exist for three distinct moments only");
    return *tri_;
  }

  void init_steady() {
    using std::sqrt;
    kind_ = motion::steady;
    const T n2 = omega0_[0] * omega0_[0] + omega0_[1] * omega0_[1] + omega0_[2] * omega0_[2];
    steady_rate_ = sqrt(n2);
    if (steady_rate_ > 0)
      steady_axis_ = {omega0_[0] / steady_rate_, omega0_[1] / steady_rate_, omega0_[2] / steady_rate_};
    else
      steady_axis_ = {T(1), T(0), T(0)};
  }

  void init_axisymmetric(int p) {
    using std::sqrt;
    kind_ = motion::axisymmetric;
    axi_data a;
    a.p = p;
    const int ia = (p + 1) % 3;
    const T& Iperp = moments_[ia];
    const T& Ip = moments_[p];
    a.e_p = {T(0), T(0), T(0)};
    a.e_p[p] = 1;
    const T L2 = L_[0] * L_[0] + L_[1] * L_[1] + L_[2] * L_[2];
    const T Lnorm = sqrt(L2);
    a.Lhat = {L_[0] / Lnorm, L_[1] / Lnorm, L_[2] / Lnorm};
    // h from the body components (|q0| = 1): the same h whatever the rounding of q0.
    T m2 = 0;
    for (int i = 0; i < 3; ++i) m2 += (moments_[i] * omega0_[i]) * (moments_[i] * omega0_[i]);
    a.precession_rate = sqrt(m2) / Iperp;
    a.spin_rate = (Ip - Iperp) * omega0_[p] / Iperp;
    axi_ = a;
  }

  vec3<T> axi_omega(const T& t) const {
    using std::cos;
    using std::sin;
    const axi_data& a = *axi_;
    const int ia = (a.p + 1) % 3, ib = (a.p + 2) % 3;
    const T angle = a.spin_rate * t;
    const T c = cos(angle), s = sin(angle);
    vec3<T> w;
    w[a.p] = omega0_[a.p];
    w[ia] = omega0_[ia] * c - omega0_[ib] * s;
    w[ib] = omega0_[ia] * s + omega0_[ib] * c;
    return w;
  }

  void init_triaxial() {
    using std::sqrt;
    const principal_axes<T> axes(moments_);
    physical_scaling<T> scaling(axes);
    const vec3<T> Omega0 = scaling.Omega_of_omega(omega0_);
    const int nonzero = (Omega0[0] != 0) + (Omega0[1] != 0) + (Omega0[2] != 0);
    if (nonzero <= 1) {  // along a principal axis (the intermediate one included): steady
      init_steady();
      return;
    }
    {
      using std::hypot;
      const T c1 = hypot(Omega0[0], Omega0[1]), c2 = hypot(Omega0[1], Omega0[2]);
      if (c1 == c2)
        throw std::domain_error("torque_free_attitude: k = c1/c2 = 1 exactly, the separatrix (a heteroclinic orbit, "
                                "not a periodic motion): out of scope");
    }
    const vop_frame<T> frame = vop_frame<T>::for_state(Omega0);
    const vec3<T> el = frame.elements_of(Omega0);
    const T kappa = el[0] / el[1];
    if (!(kappa < 1))  // c1 != c2, but their ratio rounds to 1
      throw std::domain_error("torque_free_attitude: k = c1/c2 is 1 to working precision (the separatrix): out of scope");
    kind_ = motion::triaxial;
    const bool minor = frame.minor_axis();
    // (x, y, p): the principal axes (0-based) carrying cn, sn, dn.
    const int ix = minor ? 2 : 0, iy = 1, ip = minor ? 0 : 2;
    const inertia<T>& In = scaling.moments();
    const T I[3] = {In.I1, In.I2, In.I3};
    const vec3<T>& sA = scaling.sqrt_A();
    tri_data d{scaling, frame, elliptic_modulus<T>(kappa), el[0], el[1], el[2], T(el[1] * scaling.tau_rate()),
               T(I[ix] * sA[ix] * el[0]), T(I[iy] * sA[iy] * el[0]), T(I[ip] * sA[ip] * el[1]),
               T(0), T(0), T(0), T(0), T(0), T(0), quaternion<T>{}, quaternion<T>{}};
    T m2 = 0;
    for (int i = 0; i < 3; ++i) m2 += (moments_[i] * omega0_[i]) * (moments_[i] * omega0_[i]);
    const T h = sqrt(m2);
    d.h_over_Ip = h / I[ip];
    d.phi_coef = h * (I[ip] - I[ix]) / (I[ix] * I[ip] * d.freq);
    d.n = -(I[ip] * (I[iy] - I[ix])) / (I[ix] * (I[ip] - I[iy]));
    d.Pi_complete = boost::math::ellint_3(d.modulus.k(), d.n);
    // q_B: listed axes -> principal (P) -> (a, b, p) (C: identity, or v -> (v2, v3, v1)).
    std::array<std::array<int, 3>, 3> C{};
    if (minor)
      C = {{{0, 1, 0}, {0, 0, 1}, {1, 0, 0}}};
    else
      C = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    d.qB = detail::quaternion_of_matrix<T>(detail::matrix_product(C, detail::matrix_of(axes)));
    tri_ = d;
    const phase ph0 = phase_of(d.w0);
    tri_->j0 = ph0.j;
    tri_->Pi_r0 = ph0.Pi_r;
    tri_->qF = q0_ * conjugate(tri_->qB) * conjugate(euler_body(ph0));
  }

  phase phase_at(const T& t, bool with_Pi = true) const { return phase_of(T(tri_->w0 + tri_->freq * t), with_Pi); }

  // with_Pi = false leaves Pi_r unset (the rates do not need it).
  phase phase_of(const T& w, bool with_Pi = true) const {
    const tri_data& d = *tri_;
    const elliptic_modulus<T>& m = d.modulus;
    phase ph;
    ph.j = detail::elliptic_nearest<T>(w * m.inv_two_K());
    const T r = w - ph.j * m.two_K();
    const jacobi_values<T> jv = jacobi_eval(r, m);
    ph.sn_r = jv.sn;
    ph.cn_r = jv.cn;
    const bool odd = detail::elliptic_is_odd(ph.j);
    ph.sn = odd ? T(-jv.sn) : jv.sn;
    ph.cn = odd ? T(-jv.cn) : jv.cn;
    ph.dn = jv.dn;
    if (with_Pi) ph.Pi_r = boost::math::ellint_3(m.k(), d.n, jv.am);
    return ph;
  }

  // qx(theta) (x) qz(psi) at a phase: the rotation from (a, b, p) to F without its phi.
  quaternion<T> euler_body(const phase& ph) const {
    using std::atan2;
    using std::fmod;
    using std::sqrt;
    const tri_data& d = *tri_;
    const int sigma = d.frame.sigma();
    // theta from m: rho = |(m_a, m_b)| = sin theta h, m_p = cos theta h; half angles without
    // cancellation.
    const T mx = d.alpha * ph.cn_r, my = d.beta * ph.sn_r;
    const T rho = sqrt(mx * mx + my * my);
    const T mp = sigma > 0 ? T(d.gamma * ph.dn) : T(-(d.gamma * ph.dn));
    const T N = sqrt(rho * rho + mp * mp);
    T ch, sh;  // cos(theta/2), sin(theta/2)
    if (mp >= 0) {
      ch = sqrt((N + mp) / (2 * N));
      sh = rho / sqrt(2 * N * (N + mp));
    } else {
      sh = sqrt((N - mp) / (2 * N));
      ch = rho / sqrt(2 * N * (N - mp));
    }
    const quaternion<T> qx{ch, sh, T(0), T(0)};
    // psi = c + s j pi + s' a, a = atan2(beta sn_r, alpha cn_r) in about [-pi/2, pi/2].
    const bool minor = d.frame.minor_axis();
    const T a = atan2(d.beta * ph.sn_r, d.alpha * ph.cn_r);
    const T psi_fine = (minor ? sigma : -sigma) > 0 ? a : T(-a);
    quaternion<T> qpsi = detail::quaternion_z(psi_fine);
    // The turn s j pi exactly: qz(j' pi) = cos(j' pi/2) + k sin(j' pi/2), j' = s j.
    T jm = fmod(d.frame.sigma() * (minor ? 1 : -1) * ph.j, T(4));
    if (jm < 0) jm += 4;
    const int turn = static_cast<int>(static_cast<double>(jm));
    const quaternion<T> quarter[4] = {{T(1), T(0), T(0), T(0)},
                                      {T(0), T(0), T(0), T(1)},
                                      {T(-1), T(0), T(0), T(0)},
                                      {T(0), T(0), T(0), T(-1)}};
    qpsi = quarter[turn] * qpsi;
    if (!minor) qpsi = detail::quaternion_z(boost::math::constants::half_pi<T>()) * qpsi;
    return qx * qpsi;
  }

  vec3<T> moments_, omega0_;
  quaternion<T> q0_;
  vec3<T> L_;
  motion kind_ = motion::steady;
  vec3<T> steady_axis_{};
  T steady_rate_ = T(0);
  std::optional<axi_data> axi_;
  std::optional<tri_data> tri_;
};

}  // namespace eulervop
