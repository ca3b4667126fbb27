// The reference solution as the subcommands compute it: integrate a scene's problem with the
// Chebyshev-Picard integrator (with a progress line), evaluate it at sample times known in
// advance as the segments are accepted (or keep the dense output, where the times are not known
// in advance), and optionally verify the samples one precision up (--verify). Shared by
// `reference`, `report`, `check` and the grids of `sweep` and `map`.
#pragma once

#include "io/progress_line.hpp"
#include "compute/scene_library.hpp"
#include "compute/with_scalar.hpp"

#include <eulervop/reference/integrate.hpp>
#include <eulervop/model/error_measure.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/core/scalar.hpp>

#include <boost/math/special_functions/fpclassify.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <mpfr.h>

namespace eulervop::app {

template <scalar T>
struct sampled_reference {
  std::vector<vec3<T>> Omega;
  picard_stats stats;
  double wall_seconds = 0;
};

// The dense solution to tau_end, with a progress line labelled `label` (none if it is empty:
// a sweep integrates its reference on a worker thread and draws its own line).
template <scalar T>
struct dense_reference {
  dense_trajectory<T> trajectory;
  picard_stats stats;
  double wall_seconds = 0;
};

// Runs integrate(progress), a function of a progress_callback, under a progress line labelled
// `label` (none when empty) that goes to `total`; returns the wall time.
template <class Integrate>
double run_with_progress(const std::string& label, double total, Integrate&& integrate) {
  const auto start = std::chrono::steady_clock::now();
  std::optional<progress_line> progress;
  if (!label.empty()) progress.emplace(label, total);
  integrate([&](double tau) {
    if (progress) progress->update(tau);
  });
  if (progress) progress->clear();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

template <scalar T>
dense_reference<T> integrate_dense(const euler_problem<T>& problem, const T& tau_end,
                                   const picard_settings& settings, const std::string& label) {
  dense_reference<T> out;
  out.wall_seconds = run_with_progress(label, static_cast<double>(tau_end), [&](const progress_callback& progress) {
    out.trajectory = integrate_reference<T>(problem, tau_end, settings, progress, &out.stats);
  });
  return out;
}

// A sample at `tau`, checked: a non-finite value is a numerical_failure there, so that no NaN is
// ever printed as a result (docs/design.md section 5.3).
template <scalar T>
const vec3<T>& require_finite(const vec3<T>& Om, const T& tau) {
  for (const T& x : Om)
    if (!(boost::math::isfinite)(x))
      throw numerical_failure({outcome_kind::dense_output_non_finite, static_cast<double>(tau)});
  return Om;
}

// The dense output at `tau` (within the integrated span), checked.
template <scalar T>
vec3<T> sample_dense(const dense_trajectory<T>& trajectory, const T& tau) {
  return require_finite(trajectory(tau), tau);
}

// What a run leaves once its samples have gone to a callback.
struct reference_run {
  picard_stats stats;
  double wall_seconds = 0;
};

// Receives sample `index` (of the taus given) and the reference there, in order.
template <scalar T>
using sample_function = std::function<void(std::size_t index, const vec3<T>& Omega)>;

// Integrates the problem to tau_end and evaluates the dense output at every tau (non-decreasing,
// each within [tau0, tau_end]) as the segments are accepted, handing each sample to `on_sample`
// and keeping nothing (only the latest segment): memory beyond the caller's times grows with
// neither the span nor the samples. A non-finite sample is a numerical_failure at its tau. The
// wall time includes `on_sample`.
template <scalar T>
reference_run integrate_streaming(const euler_problem<T>& problem, const T& tau_end, const std::vector<T>& taus,
                                  const picard_settings& settings, const std::string& label,
                                  const sample_function<T>& on_sample, const segment_sink<T>& after_segment = {}) {
  reference_run out;
  out.wall_seconds = run_with_progress(label, static_cast<double>(tau_end), [&](const progress_callback& progress) {
    integrate_reference_samples<T>(
        problem, tau_end, taus,
        [&](std::size_t index, const T& tau, const vec3<T>& Om) { on_sample(index, require_finite(Om, tau)); },
        settings, progress, &out.stats, after_segment);
  });
  return out;
}

// The same, keeping the samples: memory grows with the samples, not with the span.
template <scalar T>
sampled_reference<T> integrate_and_sample(const euler_problem<T>& problem, const T& tau_end,
                                          const std::vector<T>& taus, const picard_settings& settings,
                                          const std::string& label) {
  sampled_reference<T> out;
  out.Omega.reserve(taus.size());
  const reference_run run = integrate_streaming<T>(problem, tau_end, taus, settings, label,
                                                   [&](std::size_t, const vec3<T>& Om) { out.Omega.push_back(Om); });
  out.stats = run.stats;
  out.wall_seconds = run.wall_seconds;
  return out;
}

// The same for times in any order: streamed when they do not decrease, else evaluated from the
// dense output, which keeps every segment (memory grows with the span).
template <scalar T>
reference_run integrate_at(const euler_problem<T>& problem, const T& tau_end, const std::vector<T>& taus,
                           const picard_settings& settings, const std::string& label,
                           const sample_function<T>& on_sample) {
  if (std::is_sorted(taus.begin(), taus.end()))
    return integrate_streaming<T>(problem, tau_end, taus, settings, label, on_sample);
  const dense_reference<T> ref = integrate_dense<T>(problem, tau_end, settings, label);
  for (std::size_t i = 0; i < taus.size(); ++i) on_sample(i, sample_dense(ref.trajectory, taus[i]));
  return {ref.stats, ref.wall_seconds};
}

// A value of the narrower type, exactly, in the wider one (created at the current precision).
template <scalar Hi, scalar Lo>
Hi widen(const Lo& x) {
  if constexpr (std::is_same_v<Hi, mpfr_real> && std::is_same_v<Lo, mpfr_real>) {
    Hi r;  // thread default precision, which is the wider one inside the verify scope
    mpfr_set(r.backend().data(), x.backend().data(), MPFR_RNDN);
    return r;
  } else {
    return Hi(x);  // double -> quad, quad -> mpfr: exact
  }
}

// "1.23e-30": three significant digits, in the wide type (an MPFR error can underflow double).
template <scalar T>
std::string three_digits(const T& x) {
  if constexpr (std::is_same_v<T, double>)
    return fmt::format("{:.2e}", x);
  else
    return x.str(2, std::ios_base::scientific);
}

// The settings the integrator actually used (it derives degree and tolerance from the
// precision when they are left at 0).
inline std::string method_text(const picard_settings& settings, const picard_stats& stats) {
  const unsigned degree = stats.degree ? stats.degree : settings.degree;
  const double tolerance = stats.tolerance > 0 ? stats.tolerance : settings.tolerance;
  return fmt::format("chebyshev-picard degree={} tolerance={:.3g} segments={} rejected={}", degree, tolerance,
                     stats.segments, stats.rejected);
}

// The verification (--verify): the same samples, recomputed one precision up with the
// integrator's default (stricter) settings, from the scene's decimals converted directly into
// the wider type. Evaluated at the narrow run's tau values (widened exactly), so the difference
// measures the narrow run's error at the rows it prints, input rounding included.
struct verify_result {
  decimal max_error;  // three significant digits, as the metadata prints it
  eulervop::precision precision;
  std::string method;
  double wall_seconds = 0;
};

template <scalar Hi, scalar Lo>
verify_result verify_in(const scene& s, const Lo& tau_end, const std::vector<Lo>& taus,
                        const std::vector<vec3<Lo>>& Omega, const eulervop::precision& wide) {
  std::vector<Hi> wide_taus;
  wide_taus.reserve(taus.size());
  for (const Lo& t : taus) wide_taus.push_back(widen<Hi>(t));
  // Compared as they come: the wide samples are not kept.
  Hi worst = 0;
  const reference_run run = integrate_streaming<Hi>(
      to_problem<Hi>(s), widen<Hi>(tau_end), wide_taus, picard_settings{}, "verify",
      [&](std::size_t i, const vec3<Hi>& ref) {
        const vec3<Hi> narrow = {widen<Hi>(Omega[i][0]), widen<Hi>(Omega[i][1]), widen<Hi>(Omega[i][2])};
        const Hi err = eq20_error(ref, narrow);
        if (err > worst) worst = err;
      });
  return {decimal{three_digits(worst), static_cast<double>(worst)}, wide, method_text(picard_settings{}, run.stats),
          run.wall_seconds};
}

// One precision up: double -> quad -> mpfr:(113+64) ; mpfr:B -> mpfr:(B+64). `narrow` is the
// precision of Lo (its bits matter for MPFR).
template <scalar Lo>
verify_result verify(const scene& s, const Lo& tau_end, const std::vector<Lo>& taus,
                     const std::vector<vec3<Lo>>& Omega, const eulervop::precision& narrow) {
  constexpr unsigned extra_bits = 64;
  const eulervop::precision wide =
      std::is_same_v<Lo, double>
          ? eulervop::precision::binary128()
          : eulervop::precision::mpfr((std::is_same_v<Lo, quad> ? 113u : narrow.bits) + extra_bits);
  return with_scalar(wide, [&](auto zero) -> verify_result {
    using Hi = decltype(zero);
    if constexpr (std::is_same_v<Hi, double> || (std::is_same_v<Hi, quad> && !std::is_same_v<Lo, double>))
      throw std::logic_error("verify: the precision is not wider");
    else
      return verify_in<Hi>(s, tau_end, taus, Omega, wide);
  });
}

}  // namespace eulervop::app
