#include "cli/scene_overrides.hpp"

#include "cli/flags.hpp"
#include "compute/scene_library.hpp"

#include <eulervop/model/expression.hpp>
#include <eulervop/model/torque_law.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <iostream>

namespace eulervop::app {

namespace {

// The rounding unit of a precision: what no tolerance can go below.
double epsilon_of(const eulervop::precision& p) {
  switch (p.type) {
    case eulervop::precision::kind::binary64: return std::ldexp(1.0, -52);
    case eulervop::precision::kind::binary128: return std::ldexp(1.0, -112);
    case eulervop::precision::kind::mpfr: break;
  }
  return std::ldexp(1.0, 1 - static_cast<int>(eulervop::mpfr_effective_bits(p.bits)));
}

// A tolerance below the precision's rounding: one note, and the run holds itself to epsilon
// (chebyshev_picard), which its method line then states.
void note_unreachable_tolerance(double tolerance, const eulervop::precision& p, const char* field) {
  const double eps = epsilon_of(p);
  if (tolerance > 0 && tolerance < eps)
    std::cerr << fmt::format("note: {} {:.3g} is below what {} can reach (its rounding, {:.3g}); the run stops "
                             "there, and its method line says tolerance={:.3g}\n",
                             field, tolerance, p.name(), eps, eps);
}

// A torque piece that lies outside the span never applies: most likely a window in the wrong
// units or a span too short, so it is said (one note, also in the reference's metadata), but the
// run goes on. The bounds are compared as doubles, which is all a note needs.
void note_pieces_outside_span(scene& s) {
  if (!s.torque_law) return;
  const double end = s.span_end.value;
  const std::string time = s.torque_law->time_name;
  for (const eulervop::torque_piece& p : s.torque_law->pieces) {
    const auto value = [](const eulervop::expression& e) {
      return eulervop::compiled_expression<double>(e)(0.0, eulervop::vec3<double>{0.0, 0.0, 0.0});
    };
    std::string why;
    if (value(p.from) >= end)
      why = fmt::format("starts at or after the end of the span, {} = {}", s.span_key(), s.span_end.text);
    else if (value(p.to) <= 0)
      why = fmt::format("ends at or before {} = 0", time);
    if (why.empty()) continue;
    const std::string note = fmt::format("[[torque.piece]] from = {} to = {} {}: it never applies", p.from.text,
                                         p.to.text, why);
    std::cerr << fmt::format("note: scene {}: {}\n", s.name, note);
    s.notes.push_back(note);
  }
}

}  // namespace

std::string applied_overrides::text() const { return fmt::format("{}", fmt::join(flags, " ")); }

applied_overrides apply_scene_overrides(scene& s, const scene_override_flags& o) {
  applied_overrides out;
  // The span end in the scene's own time: --tau-end for normalized scenes, --t-end for physical
  // ones (s) and for the coefficient form (t).
  const bool normalized = s.units == eulervop::scene::scene_units::normalized;
  if (o.tau_end && s.is_physical())
    throw input_error(fmt::format("--tau-end {}: scene {} is physical (has [body]); give --t-end in s", *o.tau_end,
                                  s.name));
  if (o.tau_end && s.is_coefficient_form())
    throw input_error(fmt::format("--tau-end {}: scene {} is in the coefficient form ([equations]), whose time is t; "
                                  "give --t-end",
                                  *o.tau_end, s.name));
  if (o.t_end && normalized)
    throw input_error(fmt::format("--t-end {}: scene {} is normalized (no [body] or [equations]), whose time is tau; "
                                  "give --tau-end",
                                  *o.t_end, s.name));
  const std::optional<std::string>& end_flag = normalized ? o.tau_end : o.t_end;
  const std::string end_name = normalized ? "--tau-end" : "--t-end";
  if (end_flag) {
    s.span_end = positive_flag_number(end_name, *end_flag);
    out.flags.push_back(fmt::format("{}={}", end_name, *end_flag));
  }
  // The samples: --samples or --times replace the scene's choice; the scene's own times must
  // still fit in a shortened span.
  if (o.samples && o.times) throw input_error("--samples and --times: give one or the other");
  if (o.samples) {
    s.samples = flag_integer("--samples", *o.samples, scene_limits::min_samples, scene_limits::max_samples);
    s.times.clear();
    out.flags.push_back(fmt::format("--samples={}", *o.samples));
  } else if (o.times) {
    s.times = flag_times(*o.times, s.span_end, s.span_key());
    s.samples.reset();
    out.flags.push_back(fmt::format("--times={}", *o.times));
  } else if (end_flag && !s.times.empty() && s.times.back().value > s.span_end.value) {
    throw input_error(fmt::format("{} {}: the scene's times go up to {}; shorten them with --times", end_name,
                                  *end_flag, s.times.back().text));
  }
  note_pieces_outside_span(s);
  // The reference integrator: --precision, --degree and --tolerance, else the scene's [reference].
  out.precision = o.precision ? flag_precision(*o.precision) : s.reference_precision;
  if (o.precision) out.flags.push_back(fmt::format("--precision={}", *o.precision));
  if (o.degree) {
    out.settings.degree =
        static_cast<unsigned>(flag_integer("--degree", *o.degree, scene_limits::min_degree, scene_limits::max_degree));
    out.flags.push_back(fmt::format("--degree={}", *o.degree));
  } else if (s.degree) {
    out.settings.degree = *s.degree;
  }
  if (o.tolerance) {
    out.settings.tolerance = flag_tolerance(*o.tolerance);
    out.flags.push_back(fmt::format("--tolerance={}", *o.tolerance));
  } else if (s.tolerance) {
    out.settings.tolerance = s.tolerance->value;
  }
  note_unreachable_tolerance(out.settings.tolerance, out.precision, o.tolerance ? "--tolerance" : "[reference] tolerance");
  return out;
}

}  // namespace eulervop::app
