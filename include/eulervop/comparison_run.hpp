// The double-precision comparison runs of the paper (Section 3): one formulation of the problem
// integrated with one explicit Runge-Kutta method at a fixed step, sampled for the Eq. 20 error.
//
// Formulations:
//   euler      the normalized Euler equations, Eq. 5, integrated directly;
//   vop        the paper's variation of parameters, elements (c1, c2, u), Eqs. 12-16 (vop.hpp);
//   vop-theta  the secular-free variant, elements (c1, c2, theta), theta = pi u / (2K) kept in
//              [-pi, pi) with whole turns counted apart (vop.hpp, DESIGN.md section 1.3).
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
// Inside, the run takes direct Euler steps with the same method and step, and leaves when the
// state is outside twice the band (hysteresis), re-deriving the elements, in the other regime if
// the separatrix was crossed. A VOP step whose stages leave the domain (a stage crossed k = 1 or
// c1 = 0 within the step) is redone as a direct step from the step's start, opening a band there.
// Each stretch of direct steps is recorded as (tau entered, tau left) in fixed_run.
#pragma once

#include <eulervop/model.hpp>
#include <eulervop/runge_kutta.hpp>
#include <eulervop/vop.hpp>

#include <algorithm>
#include <array>
#include <utility>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
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

// Fixed step h, n_steps of it; the state is sampled at every step index that is a multiple of
// sample_every, and at the last step. The thresholds apply to the VOP formulations only (see
// the header note; the values are chosen from the measurements in docs/vop-strategies.md).
struct fixed_run_settings {
  double h = 0;
  std::size_t n_steps = 0;
  std::size_t sample_every = 1;
  double separatrix_band = 0.05;         // cap of the band in 1 - min(k, 1/k)
  double separatrix_torque_scale = 0.25; // the band is min(cap, this |G| / (c1 c2))
  double small_k_torque_ratio = 10;      // direct steps while |G| / (c1 c2) exceeds this
};

struct fixed_run {
  formulation form = formulation::euler;
  rk::method method = rk::method::rk4;
  std::vector<std::size_t> sample_steps;  // step indices, increasing; only those reached
  std::vector<vec3<double>> Omega;        // the state there (for vop: converted by Eq. 12)
  std::size_t steps = 0;                  // steps taken
  std::size_t rhs_evals = 0;
  double seconds = 0;                     // wall time of the integration itself
  bool diverged = false;
  std::optional<double> diverged_at;      // tau of the first bad step
  std::string why;                        // why it diverged
  // VOP formulations: the stretches stepped with Eq. 5, (tau entered, tau left); a stretch still
  // open when the run stops ends at the run's last tau. Near the separatrix (min(k, 1/k) > 1/2
  // on entry), and near c1 = 0 (small k).
  std::vector<std::pair<double, double>> separatrix_bands;
  std::vector<std::pair<double, double>> small_k_bands;
  std::size_t direct_steps = 0;           // steps taken with Eq. 5 inside those stretches
  std::size_t regime_changes = 0;         // element re-derivations into the other regime (k <-> 1/k)
  long long phase_turns = 0;              // vop-theta: whole turns of theta at the end
};

namespace detail {

// Beyond this max-norm a run has "exploded": a thousand times the largest |Omega| a bounded
// torque can produce over the span, |Omega0| + |G| tau_end (and the VOP phase u up to that times
// tau_end).
inline double explosion_bound(const normalized_problem<double>& p, double tau_end, bool phase) {
  double s = 1;
  for (int i = 0; i < 3; ++i) s += std::abs(p.Omega0[i]) + std::abs(p.G[i]) * tau_end;
  return 1e3 * s * (phase ? 1 + tau_end : 1.0);
}

template <class Sys, class ToOmega>
void run_with(fixed_run& out, Sys&& sys, vec3<double> x, const normalized_problem<double>& p,
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
  out.diverged = r.diverged;
  if (r.diverged) {
    out.diverged_at = r.diverged_at;
    out.why = r.stop == rk::stop_reason::non_finite ? "state became non-finite"
                                                     : "state exploded beyond the bound";
  }
}

// The VOP formulations: elements in a vop_frame while the state is away from k = 1 and k = 0,
// direct Euler steps (Eq. 5) across those bands. One explicit_rk stepper (the same tableau and
// compensated summation as rk::integrate_fixed) serves both, so the method and step never change.
template <class Tableau, bool Theta>
void run_vop(fixed_run& out, const normalized_problem<double>& p, const fixed_run_settings& s,
             double bound) {
  using V = vec3<double>;
  using System = std::conditional_t<Theta, vop_theta_system<double>, vop_system<double>>;
  const V& G = p.G;
  const bool torque = G[0] != 0 || G[1] != 0 || G[2] != 0;
  const std::size_t every = std::max<std::size_t>(s.sample_every, 1);
  out.sample_steps.reserve(s.n_steps / every + 2);
  out.Omega.reserve(s.n_steps / every + 2);

  rk::explicit_rk<Tableau, V> stepper;
  V zero{0, 0, 0};
  bool elements = false;
  vop_frame<double> frame;
  bool have_frame = false;
  System sys(zero);
  V y{}, cy{}, yn{}, cyn{};  // elements (and their compensation)
  V x{}, cx{}, xn{}, cxn{};  // Omega in the direct stretches
  long long turns = 0;
  bool open = false;         // a direct stretch is open
  bool open_separatrix = true;
  double open_at = 0;

  auto ratio = [](double a, double b) {  // min(k, 1/k) from c1, c2 (or d1, d2)
    const double lo = std::min(a, b), hi = std::max(a, b);
    return hi > 0 ? lo / hi : 0.0;
  };
  const double gnorm = std::sqrt(G[0] * G[0] + G[1] * G[1] + G[2] * G[2]);
  // Inside a band (widen = 1 to enter, 2 to stay), from the integrals (either order).
  auto in_band = [&](double a, double b, double widen) {
    if (!torque) return false;
    const double ab = a * b;
    if (!(ab > 0)) return true;
    const double q = gnorm / ab;  // |G| / (c1 c2)
    const double kw = ratio(a, b);
    return 1 - kw < widen * std::min(s.separatrix_band, s.separatrix_torque_scale * q) ||
           q * widen > s.small_k_torque_ratio;
  };
  auto Omega_now = [&]() -> V {
    if (!elements) return x;
    if constexpr (Theta) return frame.Omega_of_theta(y);
    else return frame.Omega_of(y);
  };
  // Into the elements from Omega, if the state is outside the bands (widened by `widen`).
  auto try_elements = [&](const V& Om, double widen) {
    if (in_band(std::hypot(Om[0], Om[1]), std::hypot(Om[1], Om[2]), widen)) return false;
    vop_frame<double> f;
    try {
      f = vop_frame<double>::for_state(Om);
    } catch (const std::domain_error&) {
      return false;  // on the separatrix c1 = c2 exactly
    }
    if (have_frame && f.minor_axis() != frame.minor_axis()) ++out.regime_changes;
    have_frame = true;
    frame = f;
    if constexpr (Theta) y = frame.theta_elements_of(Om);
    else y = frame.elements_of(Om);
    cy = zero;
    sys = System(frame.rotate(G));
    elements = true;
    return true;
  };
  auto open_band = [&](double tau, double kw) {
    const auto& list = kw > 0.5 ? out.separatrix_bands : out.small_k_bands;
    // A stretch that opens where the last one closed continues it.
    if (!list.empty() && list.back().second == tau && (kw > 0.5) == open_separatrix) {
      open_at = list.back().first;
      (kw > 0.5 ? out.separatrix_bands : out.small_k_bands).pop_back();
    } else {
      open_at = tau;
    }
    open_separatrix = kw > 0.5;
    open = true;
  };
  auto close_band = [&](double tau) {
    (open_separatrix ? out.separatrix_bands : out.small_k_bands).emplace_back(open_at, tau);
    open = false;
  };
  auto to_direct = [&](double tau) {
    x = Omega_now();
    cx = zero;
    open_band(tau, ratio(y[0], y[1]));
    elements = false;
  };
  auto euler_sys = [&G](const V& Om, V& dOm, double) { euler_rhs(Om, G, dOm); };
  auto finite_in = [bound](const V& v) {
    for (double c : v)
      if (!std::isfinite(c) || std::abs(c) > bound) return false;
    return true;
  };

  x = p.Omega0;
  if (!try_elements(p.Omega0, 1.0)) {
    open_band(p.tau0, ratio(std::hypot(x[0], x[1]), std::hypot(x[1], x[2])));
  }
  out.sample_steps.push_back(0);
  out.Omega.push_back(Omega_now());

  const auto start = std::chrono::steady_clock::now();
  double t = p.tau0;
  std::size_t n = 0;
  while (n < s.n_steps) {
    const double t_next = p.tau0 + s.h * static_cast<double>(n + 1);
    if (elements) {
      cyn = cy;
      stepper.do_step(sys, y, t, s.h, yn, cyn);
      const bool finite = std::isfinite(yn[0] + yn[1] + yn[2]);
      const bool in_domain = yn[0] < yn[1] && (yn[0] > 0 || (!torque && yn[0] == 0));
      if (sys.left_domain() || (finite && !in_domain)) {
        // A stage, or the step's result, crossed k = 1 or c1 = 0: redo the step directly.
        sys.reset_domain();
        to_direct(t);
        continue;
      }
      if (!finite) {
        out.diverged = true;
        out.diverged_at = t_next;
        out.why = "state became non-finite";
        break;
      }
      if (!finite_in(yn)) {
        out.diverged = true;
        out.diverged_at = t_next;
        out.why = "state exploded beyond the bound";
        break;
      }
      std::swap(y, yn);
      std::swap(cy, cyn);
      if constexpr (Theta) reduce_phase(y[2], turns);
      ++n;
      t = t_next;
      out.steps = n;
      if (in_band(y[0], y[1], 1.0)) to_direct(t);
    } else {
      cxn = cx;
      stepper.do_step(euler_sys, x, t, s.h, xn, cxn);
      if (!finite_in(xn)) {
        out.diverged = true;
        out.diverged_at = t_next;
        out.why = std::isfinite(xn[0] + xn[1] + xn[2]) ? "state exploded beyond the bound"
                                                        : "state became non-finite";
        break;
      }
      std::swap(x, xn);
      std::swap(cx, cxn);
      ++n;
      t = t_next;
      out.steps = n;
      ++out.direct_steps;
      if (try_elements(x, 2.0)) close_band(t);
    }
    if (n % every == 0 || n == s.n_steps) {
      out.sample_steps.push_back(n);
      out.Omega.push_back(Omega_now());
    }
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.rhs_evals = stepper.rhs_evaluations();
  if (open) close_band(t);
  out.phase_turns = turns;
}

}  // namespace detail

// Integrates the problem with formulation `f` and method `m` at fixed step in double.
inline fixed_run run_fixed(formulation f, rk::method m, const normalized_problem<double>& p,
                           const fixed_run_settings& s) {
  fixed_run out;
  out.form = f;
  out.method = m;
  const double tau_end = p.tau0 + s.h * static_cast<double>(s.n_steps);
  switch (f) {
    case formulation::euler: {
      auto sys = [G = p.G](const vec3<double>& x, vec3<double>& dx, double) { euler_rhs(x, G, dx); };
      detail::run_with(out, sys, p.Omega0, p, s, detail::explosion_bound(p, tau_end, false),
                       [](const vec3<double>& x) { return x; });
      break;
    }
    case formulation::vop:
    case formulation::vop_theta: {
      const double bound = detail::explosion_bound(p, tau_end, f == formulation::vop);
      rk::dispatch_method(m, [&](auto tag) {
        if (f == formulation::vop)
          detail::run_vop<decltype(tag), false>(out, p, s, bound);
        else
          detail::run_vop<decltype(tag), true>(out, p, s, bound);
      });
      break;
    }
  }
  return out;
}

}  // namespace eulervop
