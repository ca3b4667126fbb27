#include "reference_command.hpp"

#include "atomic_file.hpp"
#include "decimal.hpp"
#include "input_error.hpp"
#include "progress_line.hpp"
#include "scene.hpp"
#include "scene_problem.hpp"

#include <eulervop/chebyshev_picard.hpp>
#include <eulervop/model.hpp>
#include <eulervop/scalar.hpp>

#include <boost/math/special_functions/fpclassify.hpp>
#include <fmt/format.h>

#include <charconv>
#include <chrono>
#include <cstdint>
#include <memory>
#include <sstream>
#include <vector>

#include <mpfr.h>

namespace eulervop::app {

namespace {

// ---- flags -> an effective scene and settings ------------------------------------------------

// Everything a run needs, validated.
struct reference_job {
  scene scn;                         // the scene with --tau-end/--t-end/--samples/--times applied
  eulervop::precision precision;     // --precision, else [reference] precision
  picard_settings settings;          // --degree/--tolerance, else [reference], else automatic
  bool verify = false;
  std::string overrides;             // the flags that changed the scene, for the metadata
};

decimal flag_number(std::string_view flag, const std::string& text) {
  const auto parsed = parse_decimal(text);
  if (!parsed.number) throw input_error(fmt::format("{} {}: {}", flag, text, describe(parsed.problem)));
  return *parsed.number;
}

decimal positive_flag_number(std::string_view flag, const std::string& text) {
  decimal d = flag_number(flag, text);
  if (!(d.value > 0)) throw input_error(fmt::format("{} {}: must be positive", flag, text));
  return d;
}

std::int64_t flag_integer(std::string_view flag, const std::string& text, std::int64_t lo, std::int64_t hi) {
  std::int64_t n = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
  if (ec != std::errc{} || end != text.data() + text.size() || n < lo || n > hi)
    throw input_error(fmt::format("{} {}: must be a whole number between {} and {}", flag, text, lo, hi));
  return n;
}

// --times t1,t2,...: strictly increasing, in [0, span end].
std::vector<decimal> flag_times(const std::string& text, const decimal& span_end, std::string_view span_name) {
  std::vector<decimal> times;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = text.find(',', begin);
    const std::string item = text.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin);
    const auto parsed = parse_decimal(item);
    if (!parsed.number)
      throw input_error(fmt::format("--times {}: \"{}\" is {}", text, item,
                                    parsed.problem == decimal_problem::not_a_number ? "not a decimal number"
                                                                                    : describe(parsed.problem)));
    const decimal& t = *parsed.number;
    if (t.value < 0) throw input_error(fmt::format("--times {}: {} must be >= 0", text, item));
    if (t.value > span_end.value)
      throw input_error(fmt::format("--times {}: {} is beyond {} = {}", text, item, span_name, span_end.text));
    if (!times.empty() && !(t.value > times.back().value))
      throw input_error(fmt::format("--times {}: must be strictly increasing ({} follows {})", text, item,
                                    times.back().text));
    times.push_back(t);
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  return times;
}

reference_job make_job(const reference_options& o) {
  reference_job job;
  job.scn = o.scene_path ? load_scene_file(*o.scene_path) : load_default_scene();
  scene& s = job.scn;
  std::vector<std::string> overrides;

  // Span end: --tau-end for normalized scenes, --t-end for physical ones.
  if (o.tau_end && s.is_physical())
    throw input_error(fmt::format("--tau-end {}: scene {} is physical (has [body]); give --t-end in s", *o.tau_end,
                                  s.name));
  if (o.t_end && !s.is_physical())
    throw input_error(fmt::format("--t-end {}: scene {} is normalized (no [body]); give --tau-end", *o.t_end, s.name));
  const std::optional<std::string>& end_flag = s.is_physical() ? o.t_end : o.tau_end;
  const std::string end_name = s.is_physical() ? "--t-end" : "--tau-end";
  if (end_flag) {
    s.span_end = positive_flag_number(end_name, *end_flag);
    overrides.push_back(fmt::format("{}={}", end_name, *end_flag));
  }

  // Samples: --samples or --times replace the scene's choice; the scene's own times must still
  // fit in a shortened span.
  if (o.samples && o.times) throw input_error("--samples and --times: give one or the other");
  if (o.samples) {
    s.samples = flag_integer("--samples", *o.samples, scene_limits::min_samples, scene_limits::max_samples);
    s.times.clear();
    overrides.push_back(fmt::format("--samples={}", *o.samples));
  } else if (o.times) {
    s.times = flag_times(*o.times, s.span_end, s.span_key());
    s.samples.reset();
    overrides.push_back(fmt::format("--times={}", *o.times));
  } else if (end_flag && !s.times.empty() && s.times.back().value > s.span_end.value) {
    throw input_error(fmt::format("{} {}: the scene's times go up to {}; shorten them with --times", end_name,
                                  *end_flag, s.times.back().text));
  }

  job.precision = s.reference_precision;
  if (o.precision) {
    auto p = eulervop::precision::parse(*o.precision);
    if (!p)
      throw input_error(fmt::format("--precision {}: expected double, quad or mpfr:BITS with {} <= BITS <= {}",
                                    *o.precision, eulervop::precision::min_mpfr_bits,
                                    eulervop::precision::max_mpfr_bits));
    job.precision = *p;
    overrides.push_back(fmt::format("--precision={}", *o.precision));
  }

  if (o.degree) {
    job.settings.degree = static_cast<unsigned>(
        flag_integer("--degree", *o.degree, scene_limits::min_degree, scene_limits::max_degree));
    overrides.push_back(fmt::format("--degree={}", *o.degree));
  } else if (s.degree) {
    job.settings.degree = *s.degree;
  }
  if (o.tolerance) {
    const decimal tol = positive_flag_number("--tolerance", *o.tolerance);
    if (!(tol.value < 1)) throw input_error(fmt::format("--tolerance {}: must be below 1 (it is relative)", *o.tolerance));
    job.settings.tolerance = tol.value;
    overrides.push_back(fmt::format("--tolerance={}", *o.tolerance));
  } else if (s.tolerance) {
    job.settings.tolerance = s.tolerance->value;
  }
  job.verify = o.verify;
  job.overrides = fmt::format("{}", fmt::join(overrides, " "));
  return job;
}

// ---- computing -------------------------------------------------------------------------------

template <scalar T>
struct sampled_reference {
  std::vector<vec3<T>> Omega;
  picard_stats stats;
  double wall_seconds = 0;
};

// Integrates the problem to tau_end and evaluates the dense output at every tau.
template <scalar T>
sampled_reference<T> integrate_and_sample(const normalized_problem<T>& problem, const T& tau_end,
                                          const std::vector<T>& taus, const picard_settings& settings,
                                          const std::string& label) {
  const auto start = std::chrono::steady_clock::now();
  sampled_reference<T> out;
  progress_line progress(label, static_cast<double>(tau_end));
  const dense_trajectory<T> trajectory = integrate_reference<T>(
      problem, tau_end, settings, [&](double tau) { progress.update(tau); }, &out.stats);
  progress.clear();
  out.Omega.reserve(taus.size());
  for (const T& tau : taus) {
    vec3<T> Om = trajectory(tau);
    for (const T& x : Om)
      // No NaN is ever printed as a result (issue 5): a non-finite sample is a numerical failure.
      if (!(boost::math::isfinite)(x)) throw numerical_failure(static_cast<double>(tau), "non-finite state in the dense output");
    out.Omega.push_back(std::move(Om));
  }
  out.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
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
std::string method_text(const picard_settings& settings, const picard_stats& stats) {
  const unsigned degree = stats.degree ? stats.degree : settings.degree;
  const double tolerance = stats.tolerance > 0 ? stats.tolerance : settings.tolerance;
  return fmt::format("chebyshev-picard degree={} tolerance={:.3g} segments={} rejected={}", degree, tolerance,
                     stats.segments, stats.rejected);
}

std::string precision_text(const eulervop::precision& p) {
  if (p.type == eulervop::precision::kind::mpfr)
    return fmt::format("{} (effective_bits={})", p.name(), eulervop::mpfr_effective_bits(p.bits));
  return p.name();
}

// The verification (--verify): the same samples, recomputed one precision up with the
// integrator's default (stricter) settings, from the scene's decimals converted directly into
// the wider type. Evaluated at the narrow run's tau values (widened exactly), so the difference
// measures the narrow run's error at the rows it prints, input rounding included.
struct verify_result {
  std::string max_error;
  std::string precision;
  std::string method;
  double wall_seconds = 0;
};

template <scalar Hi, scalar Lo>
verify_result verify_in(const scene& s, const Lo& tau_end, const std::vector<Lo>& taus,
                        const std::vector<vec3<Lo>>& Omega, const eulervop::precision& wide) {
  std::vector<Hi> wide_taus;
  wide_taus.reserve(taus.size());
  for (const Lo& t : taus) wide_taus.push_back(widen<Hi>(t));
  const sampled_reference<Hi> ref =
      integrate_and_sample<Hi>(to_problem<Hi>(s), widen<Hi>(tau_end), wide_taus, picard_settings{}, "verify");
  Hi worst = 0;
  for (std::size_t i = 0; i < Omega.size(); ++i) {
    Hi sum = 0;
    for (int c = 0; c < 3; ++c) {
      const Hi d = ref.Omega[i][c] - widen<Hi>(Omega[i][c]);
      sum += d * d;
    }
    using std::sqrt;
    const Hi err = sqrt(sum);  // Eq. 20
    if (err > worst) worst = err;
  }
  return {three_digits(worst), precision_text(wide), method_text(picard_settings{}, ref.stats), ref.wall_seconds};
}

template <scalar Lo>
verify_result verify(const scene& s, const Lo& tau_end, const std::vector<Lo>& taus,
                     const std::vector<vec3<Lo>>& Omega, const eulervop::precision& narrow) {
  // One precision up: double -> quad -> mpfr:(113+64) ; mpfr:B -> mpfr:(B+64).
  constexpr unsigned extra_bits = 64;
  if constexpr (std::is_same_v<Lo, double>) {
    return verify_in<quad>(s, tau_end, taus, Omega, eulervop::precision::binary128());
  } else {
    const unsigned bits = (std::is_same_v<Lo, quad> ? 113u : narrow.bits) + extra_bits;
    const mpfr_precision_scope scope(bits);
    return verify_in<mpfr_real>(s, tau_end, taus, Omega, eulervop::precision::mpfr(bits));
  }
}

// The whole CSV (issue 2, section 6) of a run in T.
template <scalar T>
std::string run_in(const reference_job& job) {
  const scene& s = job.scn;
  const normalized_problem<T> problem = to_problem<T>(s);
  const T tau_end = tau_end_of<T>(s);
  const sample_times<T> times = sample_times_of<T>(s);
  const sampled_reference<T> ref = integrate_and_sample<T>(problem, tau_end, times.tau, job.settings, "reference");

  std::optional<verify_result> check;
  if (job.verify) check = verify<T>(s, tau_end, times.tau, ref.Omega, job.precision);

  fmt::memory_buffer out;
  auto line = [&]<class... Args>(fmt::format_string<Args...> format, Args&&... args) {
    fmt::format_to(std::back_inserter(out), format, std::forward<Args>(args)...);
    out.push_back('\n');
  };
  line("# eulervop {}", EULERVOP_VERSION);
  line("# scene: {}", s.name);
  line("# scene_source: {}", s.origin);
  if (!job.overrides.empty()) line("# overrides: {}", job.overrides);
  line("# precision: {}", precision_text(job.precision));
  line("# method: {}", method_text(job.settings, ref.stats));
  line("# wall_seconds: {:.3f}", ref.wall_seconds);
  if (check) {
    line("# estimated_max_error: {}", check->max_error);
    line("# verify_precision: {}", check->precision);
    line("# verify_method: {}", check->method);
    line("# wall_seconds_verify: {:.3f}", check->wall_seconds);
  }
  std::istringstream scene_lines(s.source_text);
  for (std::string l; std::getline(scene_lines, l);) {
    if (!l.empty() && l.back() == '\r') l.pop_back();
    line("# scene_text: {}", l);
  }

  if (s.is_physical()) {
    line("tau,Omega1,Omega2,Omega3,t,omega1,omega2,omega3");
    const physical_scaling<T> scale = scaling_of<T>(s);
    for (std::size_t i = 0; i < times.tau.size(); ++i) {
      const vec3<T>& Om = ref.Omega[i];
      const vec3<T> om = scale.omega_of_Omega(Om);
      line("{},{},{},{},{},{},{},{}", to_text(times.tau[i]), to_text(Om[0]), to_text(Om[1]), to_text(Om[2]),
           to_text(times.t[i]), to_text(om[0]), to_text(om[1]), to_text(om[2]));
    }
  } else {
    line("tau,Omega1,Omega2,Omega3");
    for (std::size_t i = 0; i < times.tau.size(); ++i) {
      const vec3<T>& Om = ref.Omega[i];
      line("{},{},{},{}", to_text(times.tau[i]), to_text(Om[0]), to_text(Om[1]), to_text(Om[2]));
    }
  }
  return fmt::to_string(out);
}

std::string run_job(const reference_job& job) {
  switch (job.precision.type) {
    case eulervop::precision::kind::binary64: return run_in<double>(job);
    case eulervop::precision::kind::binary128: return run_in<quad>(job);
    case eulervop::precision::kind::mpfr: {
      // Every MPFR value of the run is created (and destroyed) inside this scope.
      const mpfr_precision_scope scope(job.precision.bits);
      return run_in<mpfr_real>(job);
    }
  }
  throw std::logic_error("unknown precision kind");
}

}  // namespace

CLI::App* add_reference_command(CLI::App& app, reference_options& o) {
  CLI::App* sub = app.add_subcommand("reference", "Compute the high-precision reference solution as CSV");
  auto bind = [&](const std::string& name, std::optional<std::string>& target, const std::string& help) {
    return sub->add_option_function<std::string>(name, [&target](const std::string& v) { target = v; }, help);
  };
  bind("scene", o.scene_path, "Scene file (TOML); default: the embedded paper scene")->type_name("SCENE");
  bind("--precision", o.precision, "double | quad | mpfr:BITS (overrides [reference] precision)")
      ->type_name("P");
  bind("--tau-end", o.tau_end, "End of the span in tau (normalized scenes)")->type_name("T");
  bind("--t-end", o.t_end, "End of the span in s (physical scenes)")->type_name("T");
  bind("--samples", o.samples, "Number of equally spaced samples, endpoints included")->type_name("N");
  bind("--times", o.times, "Exact sample times t1,t2,... (tau, or t for physical scenes)")->type_name("LIST");
  bind("--out", o.out, "Output file (default: standard output)")->type_name("FILE");
  bind("--degree", o.degree, "Chebyshev degree (default: from the precision)")->type_name("N");
  bind("--tolerance", o.tolerance, "Relative tolerance per segment (default: from the precision)")
      ->type_name("X");
  sub->add_flag("--verify", o.verify, "Recompute one precision up and report # estimated_max_error");
  return sub;
}

void run_reference(const reference_options& options, std::ostream& standard_output) {
  const reference_job job = make_job(options);
  // Open the output first, so an unwritable path fails before any computation.
  std::unique_ptr<atomic_file> file;
  if (options.out) file = std::make_unique<atomic_file>(*options.out);
  const std::string csv = run_job(job);
  if (file) {
    file->write(csv);
    file->commit();
  } else {
    standard_output << csv << std::flush;
  }
}

}  // namespace eulervop::app
