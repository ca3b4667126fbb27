// What the two element systems (vop_system.hpp, vop_theta_system.hpp) share: the torque in the
// element frame (frame.hpp), the elliptic functions at the current modulus, Eq. 13 and the torque
// bracket of Eq. 16.
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/special/elliptic.hpp>
#include <eulervop/special/jacobi_theta.hpp>
#include <eulervop/vop/detail/agm_cache.hpp>
#include <eulervop/vop/detail/vop_domain.hpp>

#include <type_traits>

namespace eulervop::detail {

// What the two element systems share: the torque (in the vop_frame), the elliptic functions of
// Eqs. 13-16 at the current modulus, Eq. 13 and the torque bracket of Eq. 16.
template <scalar T>
class vop_equations : public vop_domain<T> {
 public:
  // pi / (2K) of the modulus of the last evaluation (the adaptive runs' error weight).
  const T& last_pi_over_2K() const { return last_rate_; }

 protected:
  explicit vop_equations(const vec3<T>& G) : G_(G), torque_free_(G[0] == 0 && G[1] == 0 && G[2] == 0) {}

  // Calls tail(j, rate) with sn, cn, dn, Z (and E(u) for Theta = false) at the modulus k
  // (kc2 = 1 - k^2 to full relative accuracy) and rate = pi/(2K). The argument is u, or with
  // Theta the phase theta = pi u / (2K) itself. In double, for k <= theta_max_k, through the nome
  // and theta functions with every constant in a local (jacobi_theta.hpp: the modulus and the
  // evaluation fused, so nothing goes through memory between them); otherwise, and in every
  // other type, through the AGM (elliptic.hpp), cached per modulus.
  template <bool Theta, class Tail>
  [[gnu::always_inline]] void with_functions(const T& k, const T& kc2, const T& arg, Tail&& tail) {
    if constexpr (std::is_same_v<T, double>) {
      if (k >= 0 && k <= theta_max_k) [[likely]] {
        const theta_constants m = theta_constants_of(k, kc2);
        jacobi_values<double> j;
        if constexpr (Theta) theta_values_at_phase(arg, m, j);
        else theta_values_at_u(arg, m, j);
        last_rate_ = m.rate;
        tail(static_cast<const jacobi_values<double>&>(j), m.rate);
        return;
      }
    }
    agm_.set(k);
    const T& rate = agm_.pi_over_2K();
    last_rate_ = rate;
    if constexpr (Theta) tail(agm_.eval(T(arg / rate)), rate);
    else tail(agm_.eval(arg), rate);
  }

  // pi / (2K) alone (torque-free motion needs no more).
  T rate_of(const T& k, const T& kc2) {
    if constexpr (std::is_same_v<T, double>)
      if (k >= 0 && k <= theta_max_k) return last_rate_ = theta_constants_of(k, kc2).rate;
    agm_.set(k);
    return last_rate_ = agm_.pi_over_2K();
  }

  // c1' = cn G1 + sn G2,  c2' = k sn G2 + dn G3                                       (Eq. 13)
  [[gnu::always_inline]] void element_rates(const jacobi_values<T>& j, const T& k, vec3<T>& dy) const {
    dy[0] = j.cn * G_[0] + j.sn * G_[1];
    dy[1] = k * j.sn * G_[1] + j.dn * G_[2];
  }
  // - sn dn G1 + kc^2 cn dn G2 + k^3 sn cn G3 + w (cn G1 + kc^2 sn G2 - k dn G3), the torque
  // part of the bracket of Eq. 16; w = E(u) - kc^2 u for u, Z(u) for theta.
  [[gnu::always_inline]] T torque_bracket(const jacobi_values<T>& j, const T& k, const T& kc2, const T& w) const {
    const T& G1 = G_[0];
    const T& G2 = G_[1];
    const T& G3 = G_[2];
    return -j.sn * j.dn * G1 + kc2 * j.cn * j.dn * G2 + k * k * k * j.sn * j.cn * G3 +
           w * (j.cn * G1 + kc2 * j.sn * G2 - k * j.dn * G3);
  }

  vec3<T> G_;
  bool torque_free_;
  agm_cache<T> agm_;
  T last_rate_ = T(1);
};

}  // namespace eulervop::detail
