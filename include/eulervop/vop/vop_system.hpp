// The equations of motion of the paper's elements (c1, c2, u) under torque: Eqs. 13 and 16, in
// the frame of the elements' regime (frame.hpp, where the minor-axis regime's form is derived).
#pragma once

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/special/elliptic.hpp>
#include <eulervop/vop/detail/vop_equations.hpp>
#include <eulervop/vop/frame.hpp>

#include <utility>

namespace eulervop {

// Right-hand side of the elements (c1, c2, u) under the torque G (given in the vop_frame):
//   c1' = cn G1 + sn G2                                                             (Eq. 13)
//   c2' = k sn G2 + dn G3                                                           (Eq. 13)
//   u'  = [k (c2^2 - c1^2) - sn dn G1 + kc^2 cn dn G2 + k^3 sn cn G3
//          + (E(u) - kc^2 u)(cn G1 + kc^2 sn G2 - k dn G3)] / (c1 kc^2)             (Eq. 16)
// with E(u) = integral_0^u dn^2 Jacobi's epsilon function (E(am u | k)). In double the
// functions come from the theta route with every constant in registers; otherwise from the AGM,
// whose modulus data (K, E, the sequence) is recomputed only when k changes.
//
// Outside 0 < k < 1 the equations are singular. The system then returns NaN derivatives, which
// stops the fixed-step driver, and records the first tau where it happened and why. Without
// torque, c1 = 0 is allowed (u' = c2 exactly).
//
// Torque = void: the constant G (given in the vop_frame). Torque a torque type of time or state
// (model/torque.hpp): G(tau, Omega) at each stage, Omega by Eq. 12 from the stage's elements
// (detail/vop_equations.hpp); the system holds its frame and its own copy of the torque.
template <scalar T, class Torque = void>
class vop_system : public detail::vop_equations<T, Torque> {
  using base = detail::vop_equations<T, Torque>;

 public:
  explicit vop_system(const vec3<T>& G)
    requires(!base::varying)
      : base(G) {}
  vop_system(const vop_frame<T>& frame, typename base::torque_type torque)
    requires base::varying
      : base(frame, std::move(torque)) {}

  // Eqs. 13 and 16; for a torque of time or state with G(tau, Omega) of the stage, which is never
  // torque-free.
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
    if (torque_free) {  // Eq. 13 and 16 with G = 0, also at c1 = 0
      dy = {T(0), T(0), c2};
      return;
    }
    const T k = c1 / c2;
    // kc^2 = (c2 - c1)(c2 + c1) / c2^2 keeps its digits near k = 1, unlike 1 - k^2.
    const T kc2 = (c2 - c1) * (c2 + c1) / (c2 * c2);
    // The divisor of Eq. 16, inverted while the elliptic functions are evaluated (off the path).
    const T inv_c1_kc2 = 1 / (c1 * kc2);
    this->template with_functions<false>(k, kc2, y[2], [&](const jacobi_values<T>& j, const T&) __attribute__((always_inline)) {
      if constexpr (base::varying) this->stage_torque(j, c1, c2, tau);
      const T secular = j.E - kc2 * y[2];  // E(u) - kc^2 u
      // The torque-free term k (c2^2 - c1^2) / (c1 kc^2) of Eq. 16 is exactly c2 (k = c1/c2,
      // c2^2 - c1^2 = c2^2 kc^2): written so, torque-free motion advances u by exactly c2 tau.
      T du = c2 + this->torque_bracket(j, k, kc2, secular) * inv_c1_kc2;
      this->element_rates(j, k, dy);
      dy[2] = std::move(du);
    });
  }
};

}  // namespace eulervop
