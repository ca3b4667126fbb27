// Euler's equations with a constant body-frame torque: the normalized form (paper Eq. 5) and the
// direct form (Eq. 1 divided by the moments), their integrals c1, c2 (Eqs. 7-9), and the
// conversion from physical units (Eqs. 2-4).
#pragma once

#include <eulervop/model/principal_axes.hpp>
#include <eulervop/core/scalar.hpp>

#include <algorithm>
#include <array>
#include <optional>
#include <stdexcept>
#include <string>

namespace eulervop {

template <class T>
using vec3 = std::array<T, 3>;

// Eq. 5: Omega1' = -Omega2 Omega3 + G1, Omega2' = Omega1 Omega3 + G2, Omega3' = -Omega1 Omega2 + G3.
// Any arithmetic T, not only a `scalar`: the benchmarks' Boost.Odeint peers evaluate it on their own
// number types (benchmarks/bench_reference.cpp).
template <class T>
inline void euler_rhs(const vec3<T>& Om, const vec3<T>& G, vec3<T>& dOm) {
  dOm[0] = G[0] - Om[1] * Om[2];
  dOm[1] = G[1] + Om[0] * Om[2];
  dOm[2] = G[2] - Om[0] * Om[1];
}

// Eq. 1 divided by I_i: omega_i' = a_i omega_j omega_k + M_i / I_i, (i, j, k) cyclic, with
// a_i = (I_j - I_k) / I_i. It holds in any right-handed frame of principal axes, whatever the
// order of the moments, and for equal moments (a_i = 0 on the symmetry axis); Eq. 5 is the case
// a = (-1, 1, -1) in the normalized variables.
template <class T>
inline void direct_rhs(const vec3<T>& a, const vec3<T>& w, const vec3<T>& g, vec3<T>& dw) {
  dw[0] = g[0] + a[0] * (w[1] * w[2]);
  dw[1] = g[1] + a[1] * (w[2] * w[0]);
  dw[2] = g[2] + a[2] * (w[0] * w[1]);
}

// One problem of Euler's equations: Omega' = f(Omega) + G on [tau0, ...], Omega(tau0) = Omega0.
// Normalized (Eq. 5, the paper's variables) unless `direct` holds the coefficients a of Eq. 1:
// then Omega is omega in rad/s, tau is t in s and G is M_i / I_i (physical_scaling::direct).
template <scalar T>
struct euler_problem {
  vec3<T> G{};       // constant torque term
  vec3<T> Omega0{};  // state at tau0
  T tau0 = 0;
  std::optional<vec3<T>> direct;  // a_i = (I_j - I_k) / I_i of Eq. 1; absent: Eq. 5

  bool normalized() const { return !direct.has_value(); }
  // f(Omega) + G.
  void rhs(const vec3<T>& Om, vec3<T>& dOm) const {
    if (direct)
      direct_rhs(*direct, Om, G, dOm);
    else
      euler_rhs(Om, G, dOm);
  }
};

// Eq. 7: c1^2 = Omega1^2 + Omega2^2, c2^2 = Omega2^2 + Omega3^2, constant when G = 0.
template <scalar T>
T c1_squared(const vec3<T>& Om) { return Om[0] * Om[0] + Om[1] * Om[1]; }
template <scalar T>
T c2_squared(const vec3<T>& Om) { return Om[1] * Om[1] + Om[2] * Om[2]; }

// The variables the integrators use for a body given in physical units, in one of two forms.
//
// Normalized (the paper's): Eqs. 3-4 and the torque mapping derived in docs/design.md section 1.1:
//   A1 = (I3-I2)/I1, A2 = (I3-I1)/I2, A3 = (I2-I1)/I3,
//   Omega_i = omega_i / sqrt(A_i),  dtau/dt = sqrt(A1 A2 A3),
//   G_i = M_i / (I_i sqrt(A_i) sqrt(A1 A2 A3)),
// with Omega and G in the principal order (principal_axes maps the body's axes onto it). It needs
// three distinct moments.
//
// Direct (direct()): no change of variables. The problem is Eq. 1 itself in the body's axes as
// given, Omega = omega, tau = t and G_i = M_i / I_i, with the coefficients a of direct_rhs. It
// takes any rigid body: for equal moments, where the normalization divides by zero, and for
// nearly equal ones, where the normalized components differ in size by the ratio of the sqrt(A_i)
// and the integrator's tolerance, relative to the largest, is loose for the smallest
// (docs/design.md section 1.7).
//
// Rates and torques are in the body's axes as the scene gives them.
template <scalar T>
class physical_scaling;

// A body is integrated in the direct form when two of its moments are equal or closer than this,
// relative to the larger: the normalization breaks at equality, and near it the normalized
// components differ in size by about gap^-1/2, so the smallest are resolved only to the
// tolerance of the largest (docs/design.md section 1.7).
inline constexpr double direct_form_gap = 1e-3;

template <class T>
bool needs_direct_form(std::array<T, 3> I) {
  std::sort(I.begin(), I.end());
  return (I[1] - I[0]) < direct_form_gap * I[1] || (I[2] - I[1]) < direct_form_gap * I[2];
}

template <scalar T>
class physical_scaling {
 public:
  explicit physical_scaling(const inertia<T>& I) : physical_scaling(principal_axes<T>(I)) {
    if (!(I.I1 > 0 && I.I1 < I.I2 && I.I2 < I.I3))
      throw std::domain_error("inertia must satisfy 0 < I1 < I2 < I3");
  }
  explicit physical_scaling(const principal_axes<T>& axes) : axes_(axes), I_(axes.moments()) {
    using std::sqrt;
    const inertia<T>& I = I_;
    A_ = {(I.I3 - I.I2) / I.I1, (I.I3 - I.I1) / I.I2, (I.I2 - I.I1) / I.I3};
    for (int i = 0; i < 3; ++i) sqrtA_[i] = sqrt(A_[i]);
    rate_ = sqrt(A_[0] * A_[1] * A_[2]);
  }

  // The direct form for moments in the body's axes as given: positive, any order, equal or not.
  // The conversions below then reduce exactly to the identity (axes unmapped, every sqrt(A_i)
  // and dtau/dt equal to 1) and to G_i = M_i / I_i.
  static physical_scaling direct(const std::array<T, 3>& user) { return physical_scaling(user); }

  bool is_direct() const { return a_.has_value(); }

  // The problem of the body with torque M and omega(0) = omega0 (in the body's axes), tau0 = 0.
  euler_problem<T> problem(const vec3<T>& M, const vec3<T>& omega0) const {
    euler_problem<T> p;
    p.G = G_of_M(M);
    p.Omega0 = Omega_of_omega(omega0);
    p.tau0 = T(0);
    p.direct = a_;
    return p;
  }

  // Normalized form: I1 < I2 < I3. Direct form: the moments as given.
  const inertia<T>& moments() const { return I_; }
  const principal_axes<T>& axes() const { return axes_; }
  // dtau/dt (Eq. 4); 1 in the direct form.
  const T& tau_rate() const { return rate_; }

  T tau_of_t(const T& t) const { return t * rate_; }
  T t_of_tau(const T& tau) const { return tau / rate_; }

  vec3<T> Omega_of_omega(const vec3<T>& w_user) const {
    const vec3<T> w = axes_.to_principal(w_user);
    return {w[0] / sqrtA_[0], w[1] / sqrtA_[1], w[2] / sqrtA_[2]};
  }
  vec3<T> omega_of_Omega(const vec3<T>& Om) const {
    return axes_.to_user({Om[0] * sqrtA_[0], Om[1] * sqrtA_[1], Om[2] * sqrtA_[2]});
  }
  vec3<T> G_of_M(const vec3<T>& M_user) const {
    const vec3<T> M = axes_.to_principal(M_user);
    const T I[3] = {I_.I1, I_.I2, I_.I3};
    vec3<T> G;
    for (int i = 0; i < 3; ++i) G[i] = M[i] / (I[i] * sqrtA_[i] * rate_);
    return G;
  }
  vec3<T> M_of_G(const vec3<T>& G) const {
    const T I[3] = {I_.I1, I_.I2, I_.I3};
    vec3<T> M;
    for (int i = 0; i < 3; ++i) M[i] = G[i] * I[i] * sqrtA_[i] * rate_;
    return axes_.to_user(M);
  }

  // Eqs. 8-9 from the kinetic energy T = (1/2) sum I_i w_i^2 and H^2 = sum (I_i w_i)^2 (normalized
  // form only).
  // Eq. 9 as printed has the denominator (I2-I1)(I2-I1); the right one is (I3-I1)(I2-I1)
  // (docs/design.md section 1.2).
  T c1_squared_from_energy(const vec3<T>& w) const {
    const auto [twoT, H2] = energy_and_momentum(axes_.to_principal(w));
    return (twoT * I_.I3 - H2) / ((I_.I3 - I_.I1) * (I_.I3 - I_.I2));
  }
  T c2_squared_from_energy(const vec3<T>& w) const {
    const auto [twoT, H2] = energy_and_momentum(axes_.to_principal(w));
    return (H2 - twoT * I_.I1) / ((I_.I3 - I_.I1) * (I_.I2 - I_.I1));
  }

 private:
  explicit physical_scaling(const std::array<T, 3>& user)
      : axes_(principal_axes<T>::unmapped()), I_{user[0], user[1], user[2]}, A_{T(1), T(1), T(1)},
        sqrtA_{T(1), T(1), T(1)}, rate_(T(1)), a_(vec3<T>{}) {
    if (!(user[0] > 0 && user[1] > 0 && user[2] > 0))
      throw std::domain_error("physical_scaling: the moments of inertia must be positive");
    for (int i = 0; i < 3; ++i) (*a_)[i] = (user[(i + 1) % 3] - user[(i + 2) % 3]) / user[i];
  }

  std::array<T, 2> energy_and_momentum(const vec3<T>& w) const {
    const T I[3] = {I_.I1, I_.I2, I_.I3};
    T twoT = 0, H2 = 0;
    for (int i = 0; i < 3; ++i) {
      twoT += I[i] * w[i] * w[i];
      H2 += I[i] * I[i] * w[i] * w[i];
    }
    return {twoT, H2};
  }

  principal_axes<T> axes_;
  inertia<T> I_;
  vec3<T> A_{}, sqrtA_{};
  T rate_ = 0;
  std::optional<vec3<T>> a_;  // the direct form's coefficients
};

}  // namespace eulervop
