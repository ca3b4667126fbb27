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
// Rates and torques are in the body's axes as the scene gives them. The number type N is a
// scalar (core/scalar.hpp) or, for the certificate, a ball (certify/ball_value.hpp): these are the
// only statement of Eqs. 2-4 and 8-9.
#pragma once

#include <eulervop/core/vec3.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/principal_axes.hpp>

#include <algorithm>
#include <array>
#include <optional>
#include <stdexcept>

namespace eulervop {

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

template <class N>
class physical_scaling {
 public:
  // Principal moments I1 < I2 < I3 (std::domain_error otherwise).
  explicit physical_scaling(const inertia<N>& I) : physical_scaling(principal_axes<N>(I)) {
    if (!(I.I1 > 0 && I.I1 < I.I2 && I.I2 < I.I3))
      throw std::domain_error("inertia must satisfy 0 < I1 < I2 < I3");
  }
  explicit physical_scaling(const principal_axes<N>& axes) : physical_scaling(axes, axes.moments()) {}
  // The normalized form for moments already in the principal order of `axes` (which need not
  // have been sorted in N: a ball's order is that of its decimals' doubles).
  physical_scaling(const axis_permutation& axes, const inertia<N>& principal) : axes_(axes), I_(principal) {
    using std::sqrt;
    const inertia<N>& I = I_;
    const vec3<N> A = {(I.I3 - I.I2) / I.I1, (I.I3 - I.I1) / I.I2, (I.I2 - I.I1) / I.I3};
    for (int i = 0; i < 3; ++i) sqrtA_[i] = sqrt(A[i]);
    rate_ = sqrt(A[0] * A[1] * A[2]);
  }

  // The direct form for moments in the body's axes as given: positive, any order, equal or not.
  // The conversions below then reduce exactly to the identity (axes unmapped, every sqrt(A_i)
  // and dtau/dt equal to 1) and to G_i = M_i / I_i.
  static physical_scaling direct(const std::array<N, 3>& user) { return physical_scaling(user); }

  bool is_direct() const { return a_.has_value(); }

  // The problem of the body with torque M and omega(0) = omega0 (in the body's axes), tau0 = 0.
  euler_problem<N> problem(const vec3<N>& M, const vec3<N>& omega0) const {
    euler_problem<N> p;
    p.torque.G = G_of_M(M);
    p.Omega0 = Omega_of_omega(omega0);
    p.tau0 = N(0);
    if (a_) {
      p.form = equation_form::direct;
      p.a = *a_;
    }
    return p;
  }

  // Normalized form: I1 < I2 < I3. Direct form: the moments as given.
  const inertia<N>& moments() const { return I_; }
  const axis_permutation& axes() const { return axes_; }
  // sqrt(A_i) (Eq. 3), in the principal order; 1 in the direct form.
  const vec3<N>& sqrt_A() const { return sqrtA_; }
  // dtau/dt (Eq. 4); 1 in the direct form.
  const N& tau_rate() const { return rate_; }

  N tau_of_t(const N& t) const { return t * rate_; }
  N t_of_tau(const N& tau) const { return tau / rate_; }

  vec3<N> Omega_of_omega(const vec3<N>& w_user) const {
    const vec3<N> w = axes_.to_principal(w_user);
    return {w[0] / sqrtA_[0], w[1] / sqrtA_[1], w[2] / sqrtA_[2]};
  }
  vec3<N> omega_of_Omega(const vec3<N>& Om) const {
    return axes_.to_user(vec3<N>{Om[0] * sqrtA_[0], Om[1] * sqrtA_[1], Om[2] * sqrtA_[2]});
  }
  vec3<N> G_of_M(const vec3<N>& M_user) const {
    const vec3<N> M = axes_.to_principal(M_user);
    const N I[3] = {I_.I1, I_.I2, I_.I3};
    vec3<N> G;
    for (int i = 0; i < 3; ++i) G[i] = M[i] / (I[i] * sqrtA_[i] * rate_);
    return G;
  }
  vec3<N> M_of_G(const vec3<N>& G) const {
    const N I[3] = {I_.I1, I_.I2, I_.I3};
    vec3<N> M;
    for (int i = 0; i < 3; ++i) M[i] = G[i] * I[i] * sqrtA_[i] * rate_;
    return axes_.to_user(M);
  }

  // Eqs. 8-9 from the kinetic energy T = (1/2) sum I_i w_i^2 and H^2 = sum (I_i w_i)^2 (normalized
  // form only).
  // Eq. 9 as printed has the denominator (I2-I1)(I2-I1); the right one is (I3-I1)(I2-I1)
  // (docs/design.md section 1.2).
  N c1_squared_from_energy(const vec3<N>& w) const {
    const auto [twoT, H2] = energy_and_momentum(axes_.to_principal(w));
    return (twoT * I_.I3 - H2) / ((I_.I3 - I_.I1) * (I_.I3 - I_.I2));
  }
  N c2_squared_from_energy(const vec3<N>& w) const {
    const auto [twoT, H2] = energy_and_momentum(axes_.to_principal(w));
    return (H2 - twoT * I_.I1) / ((I_.I3 - I_.I1) * (I_.I2 - I_.I1));
  }

 private:
  explicit physical_scaling(const std::array<N, 3>& user)
      : I_{user[0], user[1], user[2]}, sqrtA_{N(1), N(1), N(1)}, rate_(N(1)), a_(vec3<N>{}) {
    if (!(user[0] > 0 && user[1] > 0 && user[2] > 0))
      throw std::domain_error("physical_scaling: the moments of inertia must be positive");
    for (int i = 0; i < 3; ++i) (*a_)[i] = (user[(i + 1) % 3] - user[(i + 2) % 3]) / user[i];
  }

  std::array<N, 2> energy_and_momentum(const vec3<N>& w) const {
    const N I[3] = {I_.I1, I_.I2, I_.I3};
    N twoT = N(0), H2 = N(0);
    for (int i = 0; i < 3; ++i) {
      twoT += I[i] * w[i] * w[i];
      H2 += I[i] * I[i] * w[i] * w[i];
    }
    return {twoT, H2};
  }

  axis_permutation axes_;
  inertia<N> I_;
  vec3<N> sqrtA_{};
  N rate_ = N(0);
  std::optional<vec3<N>> a_;  // the direct form's coefficients
};

}  // namespace eulervop
