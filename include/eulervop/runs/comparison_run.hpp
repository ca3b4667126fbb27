// The double-precision comparison runs of the paper (Section 3): one formulation of the problem
// integrated with one explicit Runge-Kutta method, at a fixed step or under error control,
// sampled for the Eq. 20 error.
//
// Formulations:
//   euler      the normalized Euler equations, Eq. 5, integrated directly;
//   vop        the paper's variation of parameters, elements (c1, c2, u), Eqs. 12-16 (vop/);
//   vop-theta  the secular-free variant, elements (c1, c2, theta), theta = pi u / (2K) kept in
//              [-pi, pi) with whole turns counted apart (vop/, docs/vop-strategies.md).
//
// Both VOP formulations run in whichever regime the state is in (k < 1 or k > 1, either sign:
// vop_frame::for_state). Near their singularities, and only when a torque acts (without torque
// the elements are exactly constant), they fall back to Eq. 5 (docs/vop-strategies.md). With
// kw = min(k, 1/k), c1, c2 the integrals and |G| the torque's norm:
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
// Adaptive runs (run_adaptive) use the embedded pairs of rk/embedded_pairs.hpp (rkf45, dp45,
// dop853) with atol/rtol and a maximum step. Error measure:
//   euler      Hairer's norm of the Omega estimate, sc_i = atol + rtol max(|Omega_i|) (before
//              and after the step);
//   vop        the elements' estimate in scaled elements: (dc1, dc2, c1 du) over (atol + rtol c1,
//              atol + rtol c2, atol + rtol c1), c1 and c2 at their larger value before and after
//              the step. c1 du bounds the displacement of Omega that a phase error du causes:
//              |dOmega/du| = c1 sqrt(1 - k^2 sn^4) lies in [c1 kc, c1] (Eq. 12). So the three
//              components are in units of Omega, relative to the size of the components they
//              move (Omega1, Omega2 ~ c1, Omega3 ~ c2), as Hairer's scale is for Eq. 5. For
//              theta, du = dtheta 2K / pi;
//   direct stretches of the VOP runs use the Euler measure.
// Without torque every VOP stage agrees, the estimate is exactly zero, and the run takes its
// maximum step everywhere, exactly as the fixed-step runs stay exact to rounding.
#pragma once

#include <eulervop/rk/adaptive_driver.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/core/outcome.hpp>
#include <eulervop/rk/embedded_pairs.hpp>
#include <eulervop/rk/explicit_rk.hpp>
#include <eulervop/rk/fixed_step.hpp>
#include <eulervop/vop/frame.hpp>
#include <eulervop/vop/phase.hpp>
#include <eulervop/vop/vop_system.hpp>
#include <eulervop/vop/vop_theta_system.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <utility>
#include <vector>

namespace eulervop {

enum class formulation { euler, vop, vop_theta };

inline constexpr std::array<formulation, 3> all_formulations = {formulation::euler, formulation::vop,
                                                                formulation::vop_theta};

constexpr std::string_view formulation_name(formulation f) {
  switch (f) {
    case formulation::euler: return "euler";
    case formulation::vop: return "vop";
    case formulation::vop_theta: return "vop-theta";
  }
  return "?";
}

constexpr std::optional<formulation> formulation_from_name(std::string_view text) {
  for (formulation f : all_formulations)
    if (formulation_name(f) == text) return f;
  return std::nullopt;
}

// Where the VOP formulations step with Eq. 5 instead (see the header note; the values are chosen
// from the measurements in docs/vop-strategies.md).
struct vop_band_thresholds {
  double separatrix_band = 0.05;         // cap of the band in 1 - min(k, 1/k)
  double separatrix_torque_scale = 0.25; // the band is min(cap, this |G| / (c1 c2))
  double small_k_torque_ratio = 10;      // direct steps while |G| / (c1 c2) exceeds this
};

// Fixed step h, n_steps of it; the state is sampled at every step index that is a multiple of
// sample_every, and at the last step.
struct fixed_run_settings {
  double h = 0;
  std::size_t n_steps = 0;
  std::size_t sample_every = 1;
  vop_band_thresholds bands{};
};

// Error control to tau_end: atol, rtol (rk/error_norm.hpp), steps no longer than h_max.
// About `samples` states are kept (every m-th accepted step, m doubling as the run grows), and
// the last one.
struct adaptive_run_settings {
  double tau_end = 0;
  double atol = 0;
  double rtol = 0;
  double h_max = 0;
  std::size_t samples = 200;
  vop_band_thresholds bands{};
};

// One run's outcome.
struct run_result {
  formulation form = formulation::euler;
  rk::method method = rk::method::rk4;
  bool adaptive = false;
  // The samples, in time order: the step index (fixed: tau = tau0 + n h; adaptive: the accepted
  // step's index), and for adaptive runs the time as an unevaluated sum tau_hi + tau_lo.
  std::vector<std::size_t> sample_steps;
  std::vector<double> sample_tau, sample_tau_lo;  // adaptive runs only
  std::vector<vec3<double>> Omega;                // the state there (for vop: converted by Eq. 12)
  std::size_t steps = 0;                          // accepted steps
  std::size_t rejected = 0;                       // rejected steps (adaptive runs)
  std::size_t rhs_evals = 0;
  double seconds = 0;                             // wall time of the integration itself
  outcome status;                                 // success, or why the run stopped and the
                                                  // tau of the first bad step
  // VOP formulations: the stretches stepped with Eq. 5, (tau entered, tau left); a stretch still
  // open when the run stops ends at the run's last tau. Near the separatrix (min(k, 1/k) > 1/2
  // on entry), and near c1 = 0 (small k).
  std::vector<std::pair<double, double>> separatrix_bands;
  std::vector<std::pair<double, double>> small_k_bands;
  std::size_t direct_steps = 0;                   // steps taken with Eq. 5 inside those stretches
  std::size_t regime_changes = 0;                 // element re-derivations into the other regime (k <-> 1/k)
  long long phase_turns = 0;                      // vop-theta: whole turns of theta at the end

  bool diverged() const { return !status.ok(); }
  std::optional<double> diverged_at() const { return status.tau; }
};

namespace detail {

using V = vec3<double>;

// The problem's equations (Eq. 5, or Eq. 1 in the direct form) as a system of the Runge-Kutta
// drivers.
struct euler_system {
  euler_problem<double> p;
  void operator()(const V& Om, V& dOm, double t) const { p.rhs(t, Om, dOm); }
};

// The paper's VOP (Eqs. 12-16) is built on Eq. 5's elements: no direct form.
inline void require_normalized(formulation f, const euler_problem<double>& p) {
  if (f != formulation::euler && !p.normalized())
    throw std::domain_error("the paper's VOP needs the normalized Eq. 5, and this body is integrated in the direct "
                            "form of Eq. 1 (two moments equal or nearly so)");
}

// Beyond this max-norm a run has "exploded": a thousand times the largest |Omega| a bounded
// torque can produce over the span, |Omega0| + |G| tau_end (and the VOP phase u up to that times
// tau_end).
inline double explosion_bound(const euler_problem<double>& p, double tau_end, bool phase) {
  double s = 1;
  for (int i = 0; i < 3; ++i) s += std::abs(p.Omega0[i]) + std::abs(p.torque.G[i]) * tau_end;
  return 1e3 * s * (phase ? 1 + tau_end : 1.0);
}

inline bool finite_within(const V& v, double bound) {
  for (double c : v)
    if (!std::isfinite(c) || std::abs(c) > bound) return false;
  return true;
}

// How a state that is not finite_within the bound failed.
inline outcome_kind divergence_kind(const V& v) {
  return std::isfinite(v[0] + v[1] + v[2]) ? outcome_kind::norm_bound : outcome_kind::non_finite;
}

// Keeps about `target` samples of an adaptive run: every m-th accepted step, m doubling (and the
// kept samples thinned to every other one) whenever twice the target is reached. wants(step) is
// one comparison, so a run asks it after every step and converts a VOP state to Omega only for
// the steps it keeps.
class sample_thinner {
 public:
  sample_thinner(run_result& out, std::size_t target) : out_(out), target_(std::max<std::size_t>(target, 2)) {}

  bool wants(std::size_t step) const { return step == next_; }

  void put(std::size_t step, double tau, double tau_lo, const V& Omega) {
    out_.sample_steps.push_back(step);
    out_.sample_tau.push_back(tau);
    out_.sample_tau_lo.push_back(tau_lo);
    out_.Omega.push_back(Omega);
    next_ = step + stride_;
    if (out_.sample_steps.size() < 2 * target_) return;
    stride_ *= 2;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < out_.sample_steps.size(); ++i) {
      if (out_.sample_steps[i] % stride_ != 0) continue;
      out_.sample_steps[kept] = out_.sample_steps[i];
      out_.sample_tau[kept] = out_.sample_tau[i];
      out_.sample_tau_lo[kept] = out_.sample_tau_lo[i];
      out_.Omega[kept] = out_.Omega[i];
      ++kept;
    }
    out_.sample_steps.resize(kept);
    out_.sample_tau.resize(kept);
    out_.sample_tau_lo.resize(kept);
    out_.Omega.resize(kept);
    next_ = (step / stride_ + 1) * stride_;
  }
  // Whether the run's last state (at `step`) still needs to be put.
  bool lacks_last(std::size_t step) const { return out_.sample_steps.empty() || out_.sample_steps.back() != step; }

 private:
  run_result& out_;
  std::size_t target_;
  std::size_t stride_ = 1;
  std::size_t next_ = 0;
};

// Euler at a fixed step.
template <class Sys, class ToOmega>
void run_with(run_result& out, Sys&& sys, vec3<double> x, const euler_problem<double>& p,
              const fixed_run_settings& s, double bound, ToOmega&& to_Omega) {
  const std::size_t expected = s.n_steps / std::max<std::size_t>(s.sample_every, 1) + 2;
  out.sample_steps.reserve(expected);
  out.Omega.reserve(expected);
  // The observer runs after every step and must stay inline (an out-of-line call spills every
  // register the step keeps): a countdown instead of step % sample_every, and the recording of a
  // sample out of line.
  const std::size_t every = std::max<std::size_t>(s.sample_every, 1);
  std::size_t until_sample = 0;
  const auto record = [&](std::size_t step, const vec3<double>& y) [[gnu::noinline]] {
    out.sample_steps.push_back(step);
    out.Omega.push_back(to_Omega(y));
    until_sample = every;
  };
  auto observer = [&](std::size_t step, double, const vec3<double>& y) {
    if (until_sample == 0 || step == s.n_steps) [[unlikely]]
      record(step, y);
    --until_sample;
  };
  rk::fixed_step_options<double> options;
  options.max_norm = bound;
  const auto start = std::chrono::steady_clock::now();
  const auto r = rk::integrate_fixed(out.method, sys, x, p.tau0, s.h, s.n_steps, observer, options);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.steps = r.steps;
  out.rhs_evals = r.rhs_evals;
  if (r.diverged()) out.status = {r.stop, r.failed_at};
}

// Euler under error control.
template <class Pair>
void run_euler_adaptive(run_result& out, const euler_problem<double>& p, const adaptive_run_settings& s,
                        double bound) {
  const euler_system sys{p};
  sample_thinner samples(out, s.samples);
  std::size_t last_step = 0;
  double last_tau = p.tau0, last_lo = 0;
  V last_x = p.Omega0;
  auto observer = [&](std::size_t step, double tau, double lo, const V& x) {
    if (samples.wants(step)) [[unlikely]]
      samples.put(step, tau, lo, x);
    last_step = step;
    last_tau = tau;
    last_lo = lo;
    last_x = x;
  };
  rk::adaptive_options<double> o;
  o.atol = s.atol;
  o.rtol = s.rtol;
  o.h_max = s.h_max;
  o.max_norm = bound;
  V x = p.Omega0;
  const auto start = std::chrono::steady_clock::now();
  const auto r = rk::integrate_adaptive<Pair>(sys, x, p.tau0, s.tau_end, o, observer);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (samples.lacks_last(last_step)) samples.put(last_step, last_tau, last_lo, last_x);
  out.steps = r.accepted;
  out.rejected = r.rejected;
  out.rhs_evals = r.rhs_evals;
  if (r.stop != outcome_kind::success) out.status = {r.stop, r.failed_at ? *r.failed_at : last_tau};
}

// The state machine of a VOP run: elements in a vop_frame while the state is away from k = 1 and
// k = 0, direct Euler steps (Eq. 5) across those bands. The drivers (fixed or adaptive) own the
// Runge-Kutta stepping and keep the state (elements or Omega) and its compensation in locals:
// this class owns the representation, the frame and the records. The state passes by value into
// the functions that change the representation (out of line; they run once per band): a local
// whose address escaped would live in memory, and every step would reload it.
template <bool Theta>
class vop_run_state {
 public:
  using System = std::conditional_t<Theta, vop_theta_system<double>, vop_system<double>>;

  // Starts at Omega0 (p.tau0): `state` becomes its elements, or Omega0 inside a band.
  vop_run_state(run_result& out, const euler_problem<double>& p, const vop_band_thresholds& b, V& state)
      : out_(out), b_(b), G_(p.torque.G), sys_(zero_) {
    torque_ = G_[0] != 0 || G_[1] != 0 || G_[2] != 0;
    gnorm_ = std::sqrt(G_[0] * G_[0] + G_[1] * G_[1] + G_[2] * G_[2]);
    if (const auto y = try_elements(p.Omega0, 1.0)) {
      state = *y;
    } else {
      state = p.Omega0;
      open_band(p.tau0, ratio(std::hypot(state[0], state[1]), std::hypot(state[1], state[2])));
    }
  }

  bool in_elements() const { return elements_; }
  System& system() { return sys_; }

  // Omega of the state (for vop: converted by Eq. 12).
  [[gnu::noinline]] V Omega(V state) const {
    if (!elements_) return state;
    if constexpr (Theta) return frame_.Omega_of_theta(state);
    else return frame_.Omega_of(state);
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
  [[gnu::always_inline]] bool after_step(double tau, V& state, V& comp) {
    if (elements_) {
      if constexpr (Theta) reduce_phase(state[2], turns_);
      if (!in_band(state[0], state[1], 1.0)) [[likely]]
        return false;
      state = to_direct(tau, state);
      comp = zero_;
      return true;
    }
    ++out_.direct_steps;
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

  // The phase weight of the scaled-element error measure (see the header note): c1 for u,
  // c1 2K / pi for theta (2K / pi from the modulus the system evaluated last).
  double phase_weight(double c1) const {
    if constexpr (Theta) return c1 / sys_.last_pi_over_2K();
    else return c1;
  }

 private:
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
    sys_ = System(frame_.rotate(G_));
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
  V G_;
  V zero_{0, 0, 0};
  bool torque_ = false;
  double gnorm_ = 0;
  bool elements_ = false;
  vop_frame<double> frame_;
  bool have_frame_ = false;
  System sys_;
  long long turns_ = 0;
  bool open_ = false;  // a direct stretch is open
  bool open_separatrix_ = true;
  double open_at_ = 0;
};

// The VOP formulations at a fixed step: vop_run_state's representations stepped with one
// explicit_rk stepper (the same tableau and compensated summation as rk::integrate_fixed), so
// the method and step never change.
template <class Tableau, bool Theta>
class vop_fixed_run {
 public:
  vop_fixed_run(run_result& out, const euler_problem<double>& p, const fixed_run_settings& s, double bound)
      : out_(out), s_(s), tau0_(p.tau0), bound_(bound), every_(std::max<std::size_t>(s.sample_every, 1)),
        run_(out, p, s.bands, first_), euler_{p} {}

  void operator()() {
    out_.sample_steps.reserve(s_.n_steps / every_ + 2);
    out_.Omega.reserve(s_.n_steps / every_ + 2);
    V state = first_, comp{0, 0, 0};
    sample(0, state);
    const auto start = std::chrono::steady_clock::now();
    // The loop reads its constants from locals, not through `this` (which it would reload).
    const double tau0 = tau0_, h = s_.h, bound = bound_;
    const std::size_t n_steps = s_.n_steps, every = every_;
    double t = tau0;
    std::size_t n = 0;
    V next{}, comp_next{};
    while (n < n_steps) {
      const double t_next = tau0 + h * static_cast<double>(n + 1);
      comp_next = comp;
      if (!step(state, t, h, next, comp_next)) [[unlikely]] {
        state = run_.leave_elements(t, state);
        comp = V{0, 0, 0};
        continue;
      }
      if (!finite_within(next, bound)) [[unlikely]] {
        out_.status = {divergence_kind(next), t_next};
        break;
      }
      state = next;
      comp = comp_next;
      ++n;
      t = t_next;
      run_.after_step(t, state, comp);
      if (n % every == 0 || n == n_steps) [[unlikely]]
        sample(n, state);
    }
    out_.steps = n;
    out_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out_.rhs_evals = stepper_.rhs_evaluations();
    run_.finish(t);
  }

 private:
  // One step of h of the current representation from (t, state). False when an element step left
  // the elements' domain: the caller redoes it with Eq. 5.
  [[gnu::always_inline]] bool step(const V& state, double t, double h, V& next, V& comp_next) {
    if (run_.in_elements()) {
      stepper_.do_step(run_.system(), state, t, h, next, comp_next);
      return run_.element_step_in_domain(next);
    }
    stepper_.do_step(euler_, state, t, h, next, comp_next);
    return true;
  }
  void sample(std::size_t n, V state) {
    out_.sample_steps.push_back(n);
    out_.Omega.push_back(run_.Omega(state));
  }

  run_result& out_;
  const fixed_run_settings& s_;
  double tau0_, bound_;
  std::size_t every_;  // sample_every, at least 1
  V first_{};          // the starting state, in the representation vop_run_state chose
  vop_run_state<Theta> run_;
  rk::explicit_rk<Tableau, V> stepper_;
  euler_system euler_;
};

// The error scale of the element steps: the scaled elements of the header note.
template <bool Theta>
struct element_scale {
  double atol, rtol;
  const vop_run_state<Theta>* run;
  void operator()(const V& y0, const V& y1, V& sc) const {
    const double c1 = std::max(std::abs(y0[0]), std::abs(y1[0]));
    sc[0] = atol + rtol * c1;
    sc[1] = atol + rtol * std::max(std::abs(y0[1]), std::abs(y1[1]));
    const double w = run->phase_weight(c1);
    sc[2] = w > 0 ? sc[0] / w : std::numeric_limits<double>::infinity();
  }
};

// The VOP formulations under error control: vop_run_state's representations stepped with one
// embedded pair, whose PI controller carries over between them (the derivative is re-evaluated
// after a change).
template <class Pair, bool Theta>
class vop_adaptive_run {
 public:
  vop_adaptive_run(run_result& out, const euler_problem<double>& p, const adaptive_run_settings& s,
                   double bound)
      : out_(out), s_(s), tau0_(p.tau0), bound_(bound), span_(s.tau_end - p.tau0),
        h_max_(s.h_max > 0 ? std::min(s.h_max, span_) : span_), run_(out, p, s.bands, first_),
        euler_{p}, omega_scale_{s.atol, s.rtol}, element_scale_{s.atol, s.rtol, &run_},
        samples_(out, s.samples) {}

  void operator()() {
    V state = first_, comp{0, 0, 0};
    step_clock at{tau0_, 0, 0};
    samples_.put(0, at.t, at.t_lo, run_.Omega(state));
    const auto start = std::chrono::steady_clock::now();
    prime(state, at.t);
    double h = first_step(state, at.t);
    while (span_ > 0) {
      const double left = (s_.tau_end - at.t) - at.t_lo;
      if (!(left > 0)) break;
      const bool last = h >= left;
      const attempt_result r = advance(state, comp, at, h, last ? left : h, last);
      if (r == attempt_result::stopped || (r == attempt_result::accepted && last)) break;
    }
    out_.steps = at.n;
    out_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (samples_.lacks_last(at.n)) samples_.put(at.n, at.t, at.t_lo, run_.Omega(state));
    out_.rhs_evals = stepper_.rhs_evaluations() + extra_evals_;
    run_.finish(at.t);
  }

 private:
  // The time reached, t + t_lo, after n accepted steps. Apart from the state and its
  // compensation (elements or Omega), whose addresses the stepper takes: kept together, all
  // five would live in memory.
  struct step_clock {
    double t, t_lo;
    std::size_t n;
  };
  enum class attempt_result { accepted, retry, stopped };

  // One attempt of a step of h_try (the last one if `last`): accepted (state and clock advanced,
  // h the next step), retry (h shorter, or the representation changed) or stopped (out_.status).
  [[gnu::always_inline]] attempt_result advance(V& state, V& comp, step_clock& at, double& h, double h_try,
                                                bool last) {
    if (!(h_try > 16 * std::numeric_limits<double>::epsilon() * std::abs(at.t)) || !std::isfinite(h_try)) {
      out_.status = {std::isfinite(h_try) ? outcome_kind::step_underflow : outcome_kind::non_finite, at.t};
      return attempt_result::stopped;
    }
    V next{}, comp_next = comp;
    double err = 0;
    if (!attempt(state, comp, at.t, h_try, next, comp_next, err)) [[unlikely]] {
      leave_elements(state, comp, at.t);
      return attempt_result::retry;
    }
    const bool finite = std::isfinite(next[0] + next[1] + next[2]);
    if (!(err <= 1) || !finite) [[unlikely]] {
      ++out_.rejected;
      h = h_try * controller_.rejected(finite ? err : std::numeric_limits<double>::infinity());
      return attempt_result::retry;
    }
    if (!finite_within(next, bound_)) [[unlikely]] {
      out_.status = {divergence_kind(next), at.t + h_try};
      return attempt_result::stopped;
    }
    state = next;
    comp = comp_next;
    if (last) {
      at.t = s_.tau_end;
      at.t_lo = 0;
    } else {
      rk::detail::advance_time(at.t, at.t_lo, h_try);
    }
    ++at.n;
    h = std::min(h_try * controller_.accepted(err), h_max_);
    accept(state, comp, at);
    return attempt_result::accepted;
  }

  // The embedded step of h of the current representation from (t, state) (error norm in err).
  // False when an element step left the elements' domain.
  [[gnu::always_inline]] bool attempt(const V& state, const V& comp, double t, double h, V& next, V& comp_next,
                                      double& err) {
    if (run_.in_elements()) {
      err = stepper_.attempt(run_.system(), state, t, h, next, comp, comp_next, element_scale_);
      return run_.element_step_in_domain(next);
    }
    err = stepper_.attempt(euler_, state, t, h, next, comp, comp_next, omega_scale_);
    return true;
  }
  // After an accepted step: band entry or exit (a new representation is primed afresh), the
  // derivative at the new state (FSAL), the sample.
  [[gnu::always_inline]] void accept(V& state, V& comp, const step_clock& at) {
    const bool was_elements = run_.in_elements();
    if (run_.after_step(at.t, state, comp)) [[unlikely]] {
      controller_.reset();
      prime(state, at.t);
    } else if (was_elements) {
      stepper_.accept(run_.system(), state, at.t);
    } else {
      stepper_.accept(euler_, state, at.t);
    }
    if (samples_.wants(at.n)) [[unlikely]]
      samples_.put(at.n, at.t, at.t_lo, run_.Omega(state));
  }
  // A stage left the elements' domain: the step is redone directly from its start (t, state).
  void leave_elements(V& state, V& comp, double t) {
    state = run_.leave_elements(t, state);
    comp = V{0, 0, 0};
    controller_.reset();
    prime(state, t);
  }
  void prime(const V& state, double t) {
    if (run_.in_elements()) stepper_.prime(run_.system(), state, t);
    else stepper_.prime(euler_, state, t);
  }
  double first_step(const V& state, double t) {
    if (run_.in_elements())
      return rk::initial_step<Pair>(run_.system(), state, t, stepper_.derivative(), h_max_, element_scale_,
                                    extra_evals_);
    return rk::initial_step<Pair>(euler_, state, t, stepper_.derivative(), h_max_, omega_scale_, extra_evals_);
  }

  run_result& out_;
  const adaptive_run_settings& s_;
  double tau0_, bound_;
  double span_, h_max_;  // tau_end - tau0; the largest step
  V first_{};            // the starting state, in the representation vop_run_state chose
  vop_run_state<Theta> run_;
  rk::embedded_rk<Pair, V> stepper_;
  rk::pi_controller controller_{Pair::estimate_order + 1};
  euler_system euler_;
  rk::hairer_scale<double> omega_scale_;
  element_scale<Theta> element_scale_;
  sample_thinner samples_;
  std::size_t extra_evals_ = 0;  // those of the starting-step estimate
};

}  // namespace detail

// Integrates the problem with formulation `f` and method `m` at fixed step in double.
inline run_result run_fixed(formulation f, rk::method m, const euler_problem<double>& p,
                            const fixed_run_settings& s) {
  run_result out;
  out.form = f;
  out.method = m;
  detail::require_normalized(f, p);
  const double tau_end = p.tau0 + s.h * static_cast<double>(s.n_steps);
  switch (f) {
    case formulation::euler: {
      detail::run_with(out, detail::euler_system{p}, p.Omega0, p, s, detail::explosion_bound(p, tau_end, false),
                       [](const vec3<double>& x) { return x; });
      break;
    }
    case formulation::vop:
    case formulation::vop_theta: {
      const double bound = detail::explosion_bound(p, tau_end, f == formulation::vop);
      rk::dispatch_method(m, [&](auto tag) {
        if (f == formulation::vop)
          detail::vop_fixed_run<decltype(tag), false>(out, p, s, bound)();
        else
          detail::vop_fixed_run<decltype(tag), true>(out, p, s, bound)();
      });
      break;
    }
  }
  return out;
}

// Integrates the problem with formulation `f` under error control with the embedded pair of `m`
// (rkf45, dp45 or dop853; std::invalid_argument otherwise), from tau0 to s.tau_end.
inline run_result run_adaptive(formulation f, rk::method m, const euler_problem<double>& p,
                               const adaptive_run_settings& s) {
  run_result out;
  out.form = f;
  out.method = m;
  out.adaptive = true;
  detail::require_normalized(f, p);
  const double bound = detail::explosion_bound(p, s.tau_end, f == formulation::vop);
  rk::dispatch_pair(m, [&](auto pair) {
    using Pair = decltype(pair);
    switch (f) {
      case formulation::euler: detail::run_euler_adaptive<Pair>(out, p, s, bound); break;
      case formulation::vop: detail::vop_adaptive_run<Pair, false>(out, p, s, bound)(); break;
      case formulation::vop_theta: detail::vop_adaptive_run<Pair, true>(out, p, s, bound)(); break;
    }
  });
  return out;
}

}  // namespace eulervop
