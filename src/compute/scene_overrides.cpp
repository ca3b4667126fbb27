#include "compute/scene_overrides.hpp"

#include "compute/scene_library.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <charconv>
#include <cmath>

namespace eulervop::app {

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

std::vector<std::string> flag_list(std::string_view flag, const std::string& text) {
  std::vector<std::string> items;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = text.find(',', begin);
    std::string item = text.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin);
    if (item.empty()) throw input_error(fmt::format("{} {}: empty item in the list", flag, text));
    items.push_back(std::move(item));
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  return items;
}

std::vector<decimal> flag_ladder(std::string_view flag, const std::string& text) {
  std::vector<decimal> out;
  for (const std::string& item : flag_list(flag, text)) {
    const auto parsed = parse_decimal(item);
    if (!parsed.number)
      throw input_error(fmt::format("{} {}: \"{}\" is {}", flag, text, item,
                                    parsed.problem == decimal_problem::not_a_number ? "not a number"
                                                                                    : describe(parsed.problem)));
    if (!(parsed.number->value > 0) || !std::isfinite(parsed.number->value))
      throw input_error(fmt::format("{} {}: {} is not a positive finite number", flag, text, item));
    out.push_back(*parsed.number);
  }
  if (out.size() >= 2) {
    const bool up = out[1].value > out[0].value;
    for (std::size_t i = 1; i < out.size(); ++i)
      if (up ? !(out[i].value > out[i - 1].value) : !(out[i].value < out[i - 1].value))
        throw input_error(fmt::format("{} {}: not sorted at {} (give the values in increasing or decreasing order, "
                                      "each once)",
                                      flag, text, out[i].text));
  }
  return out;
}

namespace {

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

}  // namespace

std::string applied_overrides::text() const { return fmt::format("{}", fmt::join(flags, " ")); }

CLI::Option* add_text_option(CLI::App& sub, const std::string& name, std::optional<std::string>& target,
                             const std::string& help) {
  return sub.add_option_function<std::string>(name, [&target](const std::string& v) { target = v; }, help);
}

void add_output_flags(CLI::App& sub, std::optional<std::string>& out_dir, bool& no_plot, std::string_view command,
                      std::string_view figure) {
  add_text_option(sub, "--out-dir", out_dir,
                  fmt::format("Output directory (default: ./eulervop-{}/, created if missing)", command))
      ->type_name("DIR");
  sub.add_flag("--no-plot", no_plot, fmt::format("Do not draw {0}.png/{0}.svg", figure));
}

void add_scene_override_options(CLI::App& sub, scene_override_flags& o, scene_override_set which,
                                const std::string& samples_help) {
  auto bind = [&](const std::string& name, std::optional<std::string>& target, const std::string& help) {
    return add_text_option(sub, name, target, help);
  };
  if (which.reference)
    bind("--precision", o.precision, "double | quad | mpfr:BITS (overrides [reference] precision)")->type_name("P");
  if (which.span) {
    bind("--tau-end", o.tau_end, "End of the span in tau (normalized scenes)")->type_name("T");
    bind("--t-end", o.t_end, "End of the span in s (physical scenes)")->type_name("T");
  }
  if (which.samples) bind("--samples", o.samples, samples_help)->type_name("N");
  if (which.times)
    bind("--times", o.times, "Exact sample times t1,t2,... (tau, or t for physical scenes)")->type_name("LIST");
  if (which.reference) {
    bind("--degree", o.degree, "Chebyshev degree (default: from the precision)")->type_name("N");
    bind("--tolerance", o.tolerance,
         "Relative tolerance; each segment's truncation is held to a sixteenth of it (default: from the precision)")
        ->type_name("X");
  }
}

applied_overrides apply_scene_overrides(scene& s, const scene_override_flags& o) {
  applied_overrides out;
  std::vector<std::string>& overrides = out.flags;

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

  out.precision = s.reference_precision;
  if (o.precision) {
    auto p = eulervop::precision::parse(*o.precision);
    if (!p)
      throw input_error(fmt::format("--precision {}: expected double, quad or mpfr:BITS with {} <= BITS <= {}",
                                    *o.precision, eulervop::precision::min_mpfr_bits,
                                    eulervop::precision::max_mpfr_bits));
    out.precision = *p;
    overrides.push_back(fmt::format("--precision={}", *o.precision));
  }

  if (o.degree) {
    out.settings.degree = static_cast<unsigned>(
        flag_integer("--degree", *o.degree, scene_limits::min_degree, scene_limits::max_degree));
    overrides.push_back(fmt::format("--degree={}", *o.degree));
  } else if (s.degree) {
    out.settings.degree = *s.degree;
  }
  if (o.tolerance) {
    const decimal tol = positive_flag_number("--tolerance", *o.tolerance);
    if (!(tol.value < 1)) throw input_error(fmt::format("--tolerance {}: must be below 1 (it is relative)", *o.tolerance));
    out.settings.tolerance = tol.value;
    overrides.push_back(fmt::format("--tolerance={}", *o.tolerance));
  } else if (s.tolerance) {
    out.settings.tolerance = s.tolerance->value;
  }
  return out;
}

}  // namespace eulervop::app
