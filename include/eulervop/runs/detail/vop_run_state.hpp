// The state machine of the VOP formulations of the comparison runs (comparison_run.hpp).
//
// Both VOP formulations run in whichever regime the state is in (k < 1 or k > 1, either sign:
// vop_frame::for_state, vop/frame.hpp). Near their singularities, and only when a torque acts
// (without torque the elements are exactly constant), they fall back to Eq. 5
// (docs/vop-strategies.md). With kw = min(k, 1/k), c1, c2 the integrals and |G| the torque's
// norm:
//   separatrix band  1 - kw < min(separatrix_band, separatrix_torque_scale |G| / (c1 c2)):
//                    Eq. 16's torque terms carry 1 / (c1 kc^2) ~ 1 / (2 c1 (1 - kw)); the band
//                    is where they would exceed about twice the free phase rate c2 (capped);
//   small k          |G| / (c1 c2) > small_k_torque_ratio: the torque terms ~ |G| / c1 of
//                    Eq. 16 dominate the free rate c2 (c1 -> 0 is singular; k itself may be
//                    small harmlessly, as in the paper's spin-up where c2 grows).
// Inside, the run takes direct Euler steps with the same method (and step, or controller), and
// leaves when the state is outside twice the band (hysteresis), re-deriving the elements, in the
// other regime if the separatrix was crossed. A VOP step whose stages leave the domain (a stage
// crossed k = 1 or c1 = 0 within the step) is redone as a direct step from the step's start,
// opening a band there. Each stretch of direct steps is recorded as (tau entered, tau left).
//
// A torque of time or state (model/torque.hpp) is never "without torque": the bands are always
// armed, and |G| in the thresholds is the torque's norm near the current state, updated after
// every accepted step: after a direct step |G(tau, Omega)| at the step's end (one evaluation of
// the torque); after an element step |G| of the step's last stage, which the element system
// evaluated anyway (vop/detail/vop_equations.hpp) at a time within the step and a state within
// its truncation error of the step's result (for an FSAL pair, the end itself). The thresholds
// are scales, not sharp limits (docs/vop-strategies.md, section 4): a |G| one step old moves
// them by O(h |dG/dtau|). The element system holds its own copy of the torque, which the run
// pins (vop_fixed_run.hpp, vop_adaptive_run.hpp).
#pragma once

#include <eulervop/core/vec3.hpp>
#include <eulervop/model/torque.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>
#include <eulervop/special/elliptic.hpp>
#include <eulervop/special/jacobi_theta.hpp>
#include <eulervop/vop/frame.hpp>
#include <eulervop/vop/phase.hpp>
#include <eulervop/vop/vop_system.hpp>
#include <eulervop/vop/vop_theta_system.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <type_traits>

namespace eulervop::detail {

// The state machine of a VOP run: elements in a vop_frame while the state is away from k = 1 and
// k = 0, direct Euler steps (Eq. 5) across those bands. The drivers (fixed or adaptive) own the
// Runge-Kutta stepping and keep the state (elements or Omega) and its compensation in locals:
// this class owns the representation, the frame and the records. The state passes by value into
// the functions that change the representation (out of line; they run once per band): a local
// whose address escaped would live in memory, and every step would reload it.
//
// Torque: the problem's torque type. A constant one gives the paper's G to the element system
// once per frame; any other is copied into the element system, which evaluates it at each stage.
template <bool Theta, class Torque = constant_torque<double>>
class vop_run_state {
 public:
  using V = vec3<double>;
  // True for a torque of time or state (evaluated at each stage).
  static constexpr bool varying = !is_constant_torque_v<Torque>;
  using Source = std::conditional_t<varying, Torque, void>;
  using System = std::conditional_t<Theta, vop_theta_system<double, Source>, vop_system<double, Source>>;

  // Starts at Omega0 (at tau0), under the problem's torque (Eq. 5): `state` becomes its
  // elements, or Omega0 inside a band. A torque of time or state is copied, never evaluated here
  // through the caller's object (a run evaluates only its own copy).
  vop_run_state(run_result& out, const V& Omega0, double tau0, const Torque& torque, const vop_band_thresholds& b,
                V& state)
      : out_(out), b_(b), G_(initial_G(torque, tau0, Omega0)), sys_(first_system(torque)) {
    if constexpr (varying) {
      // G at the start, from the system's own copy (its interval the one of tau0).
      G_ = sys_.torque().value(tau0, Omega0);
      torque_ = true;
    } else {
      torque_ = G_[0] != 0 || G_[1] != 0 || G_[2] != 0;
    }
    gnorm_ = std::sqrt(G_[0] * G_[0] + G_[1] * G_[1] + G_[2] * G_[2]);
    if (const auto y = try_elements(Omega0, 1.0)) {
      state = *y;
    } else {
      state = Omega0;
      open_band(tau0, ratio(std::hypot(state[0], state[1]), std::hypot(state[1], state[2])));
    }
  }

  bool in_elements() const { return elements_; }
  System& system() { return sys_; }
  // The element system's own copy of a varying torque (the drivers pin its interval).
  const Torque& torque() const
    requires varying
  {
    return sys_.torque();
  }

  // Omega of the state (for vop: converted by Eq. 12).
  [[gnu::noinline]] V Omega(V state) const {
    if (!elements_) return state;
    if constexpr (Theta) return frame_.Omega_of_theta(state);
    else return frame_.Omega_of(state);
  }

  // Omega of a stage's elements y in the current frame (Eq. 12), for the attitude beside the
  // elements (detail/attitude.hpp): sn, cn, dn by the theta route in double where the element
  // system takes it (k <= theta_max_k), else by the AGM; NaN outside 0 <= c1 < c2, where the
  // element system flags the step anyway (it is then redone with Eq. 5).
  V stage_Omega(const V& y) const {
    const double c1 = y[0], c2 = y[1];
    if (!(c1 >= 0 && c1 < c2)) [[unlikely]] {
      const double nan = std::numeric_limits<double>::quiet_NaN();
      return V{nan, nan, nan};
    }
    const double k = c1 / c2;
    const double kc2 = (c2 - c1) * (c2 + c1) / (c2 * c2);
    jacobi_values<double> j;
    if (k <= theta_max_k) [[likely]] {
      const theta_constants m = theta_constants_of(k, kc2);
      if constexpr (Theta) theta_values_at_phase(y[2], m, j);
      else theta_values_at_u(y[2], m, j);
    } else {
      const elliptic_modulus<double> m(k);
      if constexpr (Theta) j = jacobi_eval(double(y[2] / pi_over_2K(m)), m);
      else j = jacobi_eval(y[2], m);
    }
    return frame_.unrotate(V{c1 * j.cn, c1 * j.sn, c2 * j.dn});
  }

  // A finished element step's result (candidate yn): true if it stays in the elements' domain
  // (0 < c1 < c2, c1 = 0 allowed without torque) and no stage left it.
  bool element_step_in_domain(const V& yn) const {
    const bool in_domain = yn[0] < yn[1] && (yn[0] > 0 || (!torque_ && yn[0] == 0));
    const bool finite = std::isfinite(yn[0] + yn[1] + yn[2]);
    return !sys_.left_domain() && (!finite || in_domain);
  }
  // A stage, or the step's result, crossed k = 1 or c1 = 0: the caller redoes the step from the
  // step's start (elements y at tau) with Eq. 5, from the returned Omega (compensation zero).
  [[gnu::noinline]] V leave_elements(double tau, V y) {
    sys_.reset_domain();
    return to_direct(tau, y);
  }

  // After an accepted step ending at tau: phase reduction, band entry or exit. Returns true if
  // the representation changed (state and comp are then the new one's; a caller with FSAL must
  // re-prime).
  bool after_step(double tau, V& state, V& comp) {
    if (elements_) {
      if constexpr (Theta) reduce_phase(state[2], turns_);
      if constexpr (varying) gnorm_ = norm(sys_.last_torque());  // the step's last stage (header note)
      if (!in_band(state[0], state[1], 1.0)) [[likely]]
        return false;
      state = to_direct(tau, state);
      comp = zero_;
      return true;
    }
    ++out_.direct_steps;
    if constexpr (varying) gnorm_ = norm(sys_.torque().value(tau, state));  // at the step's end
    if (const auto y = try_elements_at(tau, state)) {
      state = *y;
      comp = zero_;
      return true;
    }
    return false;
  }

  // The run ended at tau.
  void finish(double tau) {
    if (open_) close_band(tau);
    out_.phase_turns = turns_;
  }

  // The phase weight of the scaled-element error measure (vop_adaptive_run.hpp): c1 for u,
  // c1 2K / pi for theta (2K / pi from the modulus the system evaluated last).
  double phase_weight(double c1) const {
    if constexpr (Theta) return c1 / sys_.last_pi_over_2K();
    else return c1;
  }

 private:
  static double norm(const V& g) { return std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]); }
  // The constant G, or for a varying torque a placeholder until the system's copy gives G(tau0).
  static V initial_G(const Torque& torque, double tau0, const V& Omega0) {
    if constexpr (varying) return V{0, 0, 0};
    else return torque.value(tau0, Omega0);
  }
  // The element system before the first frame: without torque (constant), or holding the copy.
  static System first_system(const Torque& torque) {
    if constexpr (varying) return System(vop_frame<double>{}, torque);
    else return System(V{0, 0, 0});
  }
  static double ratio(double a, double b) {  // min(k, 1/k) from c1, c2 (or d1, d2)
    const double lo = std::min(a, b), hi = std::max(a, b);
    return hi > 0 ? lo / hi : 0.0;
  }
  // Inside a band (widen = 1 to enter, 2 to stay), from the integrals (either order).
  bool in_band(double a, double b, double widen) const {
    if (!torque_) return false;
    const double ab = a * b;
    if (!(ab > 0)) return true;
    const double q = gnorm_ / ab;  // |G| / (c1 c2)
    const double kw = ratio(a, b);
    return 1 - kw < widen * std::min(b_.separatrix_band, b_.separatrix_torque_scale * q) ||
           q * widen > b_.small_k_torque_ratio;
  }
  // The elements of Omega, if the state is outside the bands (widened by `widen`); switches the
  // frame and the system to them.
  std::optional<V> try_elements(const V& Om, double widen) {
    if (in_band(std::hypot(Om[0], Om[1]), std::hypot(Om[1], Om[2]), widen)) return std::nullopt;
    vop_frame<double> f;
    try {
      f = vop_frame<double>::for_state(Om);
    } catch (const std::domain_error&) {
      return std::nullopt;  // on the separatrix c1 = c2 exactly
    }
    if (have_frame_ && f.minor_axis() != frame_.minor_axis()) ++out_.regime_changes;
    have_frame_ = true;
    frame_ = f;
    if constexpr (varying) sys_.set_frame(frame_);  // keeps the torque's copy and its pinned interval
    else sys_ = System(frame_.rotate(G_));
    elements_ = true;
    if constexpr (Theta) return frame_.theta_elements_of(Om);
    else return frame_.elements_of(Om);
  }
  // Back into the elements from a direct step's Omega at tau (hysteresis: twice the band).
  [[gnu::noinline]] std::optional<V> try_elements_at(double tau, V Om) {
    auto y = try_elements(Om, 2.0);
    if (y) close_band(tau);
    return y;
  }
  void open_band(double tau, double kw) {
    const auto& list = kw > 0.5 ? out_.separatrix_bands : out_.small_k_bands;
    // A stretch that opens where the last one closed continues it.
    if (!list.empty() && list.back().second == tau && (kw > 0.5) == open_separatrix_) {
      open_at_ = list.back().first;
      (kw > 0.5 ? out_.separatrix_bands : out_.small_k_bands).pop_back();
    } else {
      open_at_ = tau;
    }
    open_separatrix_ = kw > 0.5;
    open_ = true;
  }
  void close_band(double tau) {
    (open_separatrix_ ? out_.separatrix_bands : out_.small_k_bands).emplace_back(open_at_, tau);
    open_ = false;
  }
  // Omega of the elements y; opens a band at tau.
  [[gnu::noinline]] V to_direct(double tau, V y) {
    const V x = Omega(y);
    open_band(tau, ratio(y[0], y[1]));
    elements_ = false;
    return x;
  }

  run_result& out_;
  vop_band_thresholds b_;
  V G_;  // the constant torque; a varying one's value at the start
  V zero_{0, 0, 0};
  bool torque_ = false;
  double gnorm_ = 0;  // |G| of the band thresholds (header note)
  bool elements_ = false;
  vop_frame<double> frame_;
  bool have_frame_ = false;
  System sys_;
  long long turns_ = 0;
  bool open_ = false;  // a direct stretch is open
  bool open_separatrix_ = true;
  double open_at_ = 0;
};

}  // namespace eulervop::detail
