// The equations of motion of the secular-free elements (c1, c2, theta) under torque
// (docs/vop-strategies.md), in the frame of the elements' regime (frame.hpp).
#pragma once

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/special/elliptic.hpp>
#include <eulervop/vop/detail/vop_equations.hpp>
#include <eulervop/vop/frame.hpp>
#include <eulervop/vop/phase.hpp>

#include <utility>

namespace eulervop {

// Right-hand side of the secular-free elements (c1, c2, theta), theta = pi u / (2K(k)), under the
// torque G (in the vop_frame). c1', c2' are Eq. 13 at u = 2K theta / pi, and
//   theta' = pi/(2K) u' - (pi u / (2K^2)) dK/dk k',   dK/dk = (E - kc^2 K) / (k kc^2)  (A&S 17.3.11)
// With k' = P / c2 (Eq. 15, P = cn G1 + kc^2 sn G2 - k dn G3) and k c2 = c1, the second term is
// pi/(2K) u (E/K - kc^2) P / (c1 kc^2); subtracted from the secular term of Eq. 16 it leaves
// E(u) - kc^2 u - (E/K) u + kc^2 u = Z(u), the Jacobi zeta function:
//   theta' = pi/(2K) [c2 + (- sn dn G1 + kc^2 cn dn G2 + k^3 sn cn G3 + Z(u) P) / (c1 kc^2)].
// Every term has period 2 pi in theta (sn, cn: 4K in u; dn, Z: 2K), so the run keeps theta in
// [-pi, pi) and counts whole turns apart (reduce_phase). pi/(2K) is a_N, the AGM mean, and
// torque-free motion advances theta by exactly a_N c2 per unit tau (c2 in Eq. 16, times a_N).
//
// Torque = void: the constant G (given in the vop_frame). Torque a torque type of time or state
// (model/torque.hpp): G(tau, Omega) at each stage, Omega by Eq. 12 at u = theta / a_N from the
// stage's elements (detail/vop_equations.hpp); the derivation above holds at every instant, so
// only G changes.
template <scalar T, class Torque = void>
class vop_theta_system : public detail::vop_equations<T, Torque> {
  using base = detail::vop_equations<T, Torque>;

 public:
  explicit vop_theta_system(const vec3<T>& G)
    requires(!base::varying)
      : base(G) {}
  vop_theta_system(const vop_frame<T>& frame, typename base::torque_type torque)
    requires base::varying
      : base(frame, std::move(torque)) {}

  // theta' and Eq. 13; for a torque of time or state with G(tau, Omega) of the stage, which is
  // never torque-free.
  [[gnu::always_inline]] void operator()(const vec3<T>& y, vec3<T>& dy, const T& tau)
    requires(!base::varying)
  {
    rates(y, dy, tau);
  }
  // Out of line under a torque of time or state: its evaluation (a formula's program, behind a
  // call already) outweighs one more call, and one copy serves every stage of every method.
  [[gnu::noinline]] void operator()(const vec3<T>& y, vec3<T>& dy, const T& tau)
    requires base::varying
  {
    rates(y, dy, tau);
  }

 private:
  [[gnu::always_inline]] void rates(const vec3<T>& y, vec3<T>& dy, const T& tau) {
    const T& c1 = y[0];
    const T& c2 = y[1];
    const bool torque_free = !base::varying && this->torque_free_;
    if (this->outside(c1, c2, tau, torque_free, dy)) return;
    const T k = c1 / c2;
    const T kc2 = (c2 - c1) * (c2 + c1) / (c2 * c2);
    if (torque_free) {
      dy = {T(0), T(0), this->rate_of(k, kc2) * c2};
      return;
    }
    // The divisor of Eq. 16, inverted while the elliptic functions are evaluated (off the path).
    const T inv_c1_kc2 = 1 / (c1 * kc2);
    this->template with_functions<true>(k, kc2, y[2], [&](const jacobi_values<T>& j, const T& rate) __attribute__((always_inline)) {
      if constexpr (base::varying) this->stage_torque(j, c1, c2, tau);
      T dtheta = rate * c2 + rate * (this->torque_bracket(j, k, kc2, j.Z) * inv_c1_kc2);
      this->element_rates(j, k, dy);
      dy[2] = std::move(dtheta);
    });
  }
};

}  // namespace eulervop
