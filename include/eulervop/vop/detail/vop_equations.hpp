// What the two element systems (vop_system.hpp, vop_theta_system.hpp) share: the torque in the
// element frame (frame.hpp), the elliptic functions at the current modulus, Eq. 13 and the torque
// bracket of Eq. 16.
//
// The torque comes in two forms, chosen at compile time by the template parameter Torque:
//   void         the paper's constant G (Eqs. 13-16 as printed), rotated into the vop_frame once;
//   a torque type of time or state (model/torque.hpp): Eqs. 13-16 hold at every instant with
//                G = G(tau, Omega), since their derivation only uses Eq. 5 at that instant
//                (docs/design.md, section 1.4). Each stage evaluates it at its own time tau and
//                its own Omega, Eq. 12 from the stage's elements in the frame,
//                W = (d1 cn u, d1 sn u, d2 dn u), mapped back by P^-1 (frame.hpp), and rotates the
//                value into the frame: G_W = P G(tau, P^-1 W). sn, cn, dn are those the stage
//                computes anyway for Eqs. 13-16.
// The constant form keeps its code exactly as before (its outputs are byte-identical).
#pragma once

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/special/elliptic.hpp>
#include <eulervop/special/jacobi_theta.hpp>
#include <eulervop/vop/detail/agm_cache.hpp>
#include <eulervop/vop/detail/vop_domain.hpp>
#include <eulervop/vop/frame.hpp>

#include <type_traits>
#include <utility>

namespace eulervop::detail {

// What a varying-torque element system holds: its frame and its own copy of the torque. The
// constant form holds nothing more than G.
template <scalar T, class Torque>
struct stage_torque_source {
  vop_frame<T> frame;
  Torque torque;
};
struct no_stage_torque {};

// What the two element systems share: the torque (in the vop_frame), the elliptic functions of
// Eqs. 13-16 at the current modulus, Eq. 13 and the torque bracket of Eq. 16.
template <scalar T, class Torque = void>
class vop_equations : public vop_domain<T> {
 public:
  // True when the torque is evaluated at every stage (a torque of time or state).
  static constexpr bool varying = !std::is_void_v<Torque>;
  // The torque type a varying system holds (a placeholder for the constant form, which has none).
  using torque_type = std::conditional_t<varying, Torque, no_stage_torque>;

  // pi / (2K) of the modulus of the last evaluation (the adaptive runs' error weight).
  const T& last_pi_over_2K() const { return last_rate_; }

  // A varying torque: the system's own copy (a torque given by formulas keeps scratch space and
  // its pinned interval, so a run pins and evaluates only its own), its frame, and the torque of
  // the last stage evaluated, in the frame (|G| is the same in every frame).
  const auto& torque() const
    requires varying
  {
    return source_.torque;
  }
  const vop_frame<T>& frame() const
    requires varying
  {
    return source_.frame;
  }
  // The elements are now those of `f` (the run re-derived them, vop_run_state.hpp).
  void set_frame(const vop_frame<T>& f)
    requires varying
  {
    source_.frame = f;
    this->reset_domain();
  }
  const vec3<T>& last_torque() const
    requires varying
  {
    return G_;
  }

 protected:
  explicit vop_equations(const vec3<T>& G)
    requires(!varying)
      : G_(G), torque_free_(G[0] == 0 && G[1] == 0 && G[2] == 0) {}
  // A torque of time or state is never torque-free, even where it vanishes: the shortcut of the
  // constant form (u' = c2 exactly) would skip it.
  vop_equations(const vop_frame<T>& frame, torque_type torque)
    requires varying
      : G_{T(0), T(0), T(0)}, torque_free_(false), source_{frame, std::move(torque)} {}

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

  // The torque of a stage at time tau whose elements are (d1, d2, .) with sn, cn, dn in j, in the
  // frame: G_W = P G(tau, P^-1 W), W = (d1 cn, d1 sn, d2 dn) (Eq. 12 in the frame). Kept as the
  // last stage's torque.
  [[gnu::always_inline]] const vec3<T>& stage_torque(const jacobi_values<T>& j, const T& d1, const T& d2, const T& tau)
    requires varying
  {
    const vec3<T> Omega = source_.frame.unrotate(vec3<T>{d1 * j.cn, d1 * j.sn, d2 * j.dn});
    G_ = source_.frame.rotate(source_.torque.value(tau, Omega));
    return G_;
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

  // The constant form: G itself. A varying torque: the torque of the stage being evaluated
  // (stage_torque, which element_rates and torque_bracket then read).
  vec3<T> G_;
  bool torque_free_;
  agm_cache<T> agm_;
  T last_rate_ = T(1);

 private:
  [[no_unique_address]] std::conditional_t<varying, stage_torque_source<T, Torque>, no_stage_torque> source_;
};

}  // namespace eulervop::detail
