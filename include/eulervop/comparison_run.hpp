// The double-precision comparison runs of the paper (Section 3): one formulation of the problem
// integrated with one explicit Runge-Kutta method at a fixed step, sampled for the Eq. 20 error.
//
// Formulations:
//   euler  the normalized Euler equations, Eq. 5, integrated directly;
//   vop    the paper's variation of parameters, elements (c1, c2, u), Eqs. 12-16 (vop.hpp).
#pragma once

#include <eulervop/model.hpp>
#include <eulervop/runge_kutta.hpp>
#include <eulervop/vop.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace eulervop {

enum class formulation { euler, vop };

inline constexpr std::array<formulation, 2> all_formulations = {formulation::euler, formulation::vop};

constexpr std::string_view formulation_name(formulation f) {
  switch (f) {
    case formulation::euler: return "euler";
    case formulation::vop: return "vop";
  }
  return "?";
}

constexpr std::optional<formulation> formulation_from_name(std::string_view text) {
  for (formulation f : all_formulations)
    if (formulation_name(f) == text) return f;
  return std::nullopt;
}

// Fixed step h, n_steps of it; the state is sampled at every step index that is a multiple of
// sample_every, and at the last step.
struct fixed_run_settings {
  double h = 0;
  std::size_t n_steps = 0;
  std::size_t sample_every = 1;
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
  auto observer = [&](std::size_t step, double, const vec3<double>& y) {
    if (step % s.sample_every == 0 || step == s.n_steps) {
      out.sample_steps.push_back(step);
      out.Omega.push_back(to_Omega(y));
    }
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
    case formulation::vop: {
      const vop_frame<double> frame = vop_frame<double>::of(p.Omega0);
      vop_system<double> sys(frame.rotate(p.G));
      detail::run_with(out, sys, frame.elements_of(p.Omega0), p, s,
                       detail::explosion_bound(p, tau_end, true),
                       [&](const vec3<double>& y) { return frame.Omega_of(y); });
      if (sys.left_domain()) {
        out.diverged = true;
        out.diverged_at = sys.left_domain_at();
        out.why = sys.domain_message();
      }
      break;
    }
  }
  return out;
}

}  // namespace eulervop
