// The normalized Euler equations (paper Eqs. 1-5) with a constant body-frame torque, their
// integrals c1, c2 (Eqs. 7-9), and the conversion from physical units (Eqs. 2-4).
#pragma once

#include <eulervop/principal_axes.hpp>
#include <eulervop/scalar.hpp>

#include <array>
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

// A normalized problem: Omega' = f(Omega) + G on [tau0, ...], Omega(tau0) = Omega0 (Eq. 5).
template <scalar T>
struct normalized_problem {
  vec3<T> G{};       // constant normalized torque
  vec3<T> Omega0{};  // state at tau0
  T tau0 = 0;
};

// Eq. 7: c1^2 = Omega1^2 + Omega2^2, c2^2 = Omega2^2 + Omega3^2, constant when G = 0.
template <scalar T>
T c1_squared(const vec3<T>& Om) { return Om[0] * Om[0] + Om[1] * Om[1]; }
template <scalar T>
T c2_squared(const vec3<T>& Om) { return Om[1] * Om[1] + Om[2] * Om[2]; }

// Eqs. 3-4 (the change of variables) and the torque mapping derived in docs/design.md section 1.1:
//   A1 = (I3-I2)/I1, A2 = (I3-I1)/I2, A3 = (I2-I1)/I3,
//   Omega_i = omega_i / sqrt(A_i),  dtau/dt = sqrt(A1 A2 A3),
//   G_i = M_i / (I_i sqrt(A_i) sqrt(A1 A2 A3)).
// Rates and torques are in the body's axes as given (principal_axes maps them onto the principal
// order); Omega and G are in the principal order.
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

  const inertia<T>& moments() const { return I_; }
  const principal_axes<T>& axes() const { return axes_; }
  const vec3<T>& A() const { return A_; }
  // dtau/dt (Eq. 4).
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

  // Eqs. 8-9 from the kinetic energy T = (1/2) sum I_i w_i^2 and H^2 = sum (I_i w_i)^2.
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
};

}  // namespace eulervop
