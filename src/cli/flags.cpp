#include "cli/flags.hpp"

#include "compute/run_names.hpp"
#include "compute/scene_library.hpp"
#include "io/csv_rows.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>

namespace eulervop::app {

// ---- numbers and choices ---------------------------------------------------------------------

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

std::optional<double> non_negative_flag(std::string_view flag, const std::optional<std::string>& text) {
  if (!text) return std::nullopt;
  const decimal d = flag_number(flag, *text);
  if (d.value < 0) throw input_error(fmt::format("{} {}: must be >= 0", flag, *text));
  return d.value;
}

std::int64_t flag_integer(std::string_view flag, const std::string& text, std::int64_t lo, std::int64_t hi) {
  std::int64_t n = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
  if (ec != std::errc{} || end != text.data() + text.size() || n < lo || n > hi)
    throw input_error(fmt::format("{} {}: must be a whole number between {} and {}", flag, text, lo, hi));
  return n;
}

eulervop::precision flag_precision(const std::string& text) {
  const auto p = eulervop::precision::parse(text);
  if (!p)
    throw input_error(fmt::format("--precision {}: expected double, quad or mpfr:BITS with {} <= BITS <= {}", text,
                                  eulervop::precision::min_mpfr_bits, eulervop::precision::max_mpfr_bits));
  return *p;
}

double flag_tolerance(const std::string& text) {
  const decimal tol = positive_flag_number("--tolerance", text);
  if (!(tol.value < 1)) throw input_error(fmt::format("--tolerance {}: must be below 1 (it is relative)", text));
  return tol.value;
}

bool flag_json_format(const std::optional<std::string>& text) {
  const std::string format = text.value_or("table");
  if (format != "table" && format != "json")
    throw input_error(fmt::format("--format {}: expected table or json", format));
  return format == "json";
}

// ---- lists and ladders -------------------------------------------------------------------------

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

std::vector<ladder_tol> tol_ladder(const std::string& flag, const std::string& text) {
  std::vector<ladder_tol> out;
  for (const decimal& d : flag_ladder(flag, text)) {
    if (!(d.value < 1))
      throw input_error(fmt::format("{} {}: {} is not below 1 (the tolerances are relative and absolute errors per "
                                    "step)",
                                    flag, text, d.text));
    out.push_back({d.text, d.value});
  }
  return out;
}

std::vector<double> level_ladder(const std::string& text) {
  std::vector<double> out;
  for (const decimal& d : flag_ladder("--levels", text)) {
    if (!(d.value < 1))
      throw input_error(fmt::format("--levels {}: {} is not below 1 (a level is a max Eq. 20 error)", text, d.text));
    out.push_back(d.value);
  }
  return out;
}

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

// ---- formulations and methods ----------------------------------------------------------------------

namespace {

// Names -> values by `from_name`; input_error naming `where` ("--formulations euler,foo",
// "[run] formulations") for an unknown or repeated name, followed by `hint`; `kind`
// ("formulation", "method") and `available` for the message.
template <class V, class FromName>
std::vector<V> values_of(const std::vector<std::string>& names, const std::string& where, const std::string& hint,
                         std::string_view kind, FromName from_name, const std::vector<std::string>& available) {
  std::vector<V> out;
  for (const std::string& name : names) {
    const std::optional<V> v = from_name(name);
    if (!v)
      throw input_error(
          fmt::format("{}: {} `{}` is unknown (available: {}){}", where, kind, name, joined(available), hint));
    if (std::find(out.begin(), out.end(), *v) != out.end())
      throw input_error(fmt::format("{}: {} `{}` is listed twice", where, kind, name));
    out.push_back(*v);
  }
  return out;
}

std::vector<formulation> formulations_of(const std::vector<std::string>& names, const std::string& where,
                                         const std::string& hint) {
  return values_of<formulation>(names, where, hint, "formulation", formulation_from_name, available_formulations());
}

std::vector<rk::method> methods_of(const std::vector<std::string>& names, const std::string& where,
                                   const std::string& hint) {
  return values_of<rk::method>(names, where, hint, "method", rk::method_from_name, available_methods());
}

// Each method must run on at least one of the ladders present; input_error naming `where`.
void check_methods_for_ladders(const std::vector<rk::method>& methods, bool steps, bool tols,
                               const std::string& where) {
  for (rk::method m : methods) {
    if ((steps && rk::is_fixed_step(m)) || (tols && rk::is_adaptive(m))) continue;
    const std::string name(rk::method_name(m));
    if (!tols)
      throw input_error(fmt::format("{}: {} is run under error control and needs --tols (at a fixed step it is rk8)",
                                    where, name));
    throw input_error(fmt::format("{}: {} has no embedded error estimate, so it cannot run with --tols (adaptive "
                                  "methods: rkf45, dp45, dop853)",
                                  where, name));
  }
}

}  // namespace

std::vector<formulation> chosen_formulations(const std::optional<std::string>& flag,
                                             const std::vector<std::string>& scene_list,
                                             std::vector<formulation> fallback) {
  if (flag) return formulations_of(flag_list("--formulations", *flag), "--formulations " + *flag, "");
  if (!scene_list.empty()) return formulations_of(scene_list, "[run] formulations", "; override with --formulations");
  return fallback;
}

std::vector<rk::method> chosen_methods(const std::optional<std::string>& flag,
                                       const std::vector<std::string>& scene_list, std::vector<rk::method> fallback,
                                       bool steps, bool tols) {
  if (flag) {
    const std::string where = "--methods " + *flag;
    std::vector<rk::method> methods = methods_of(flag_list("--methods", *flag), where, "");
    check_methods_for_ladders(methods, steps, tols, where);
    return methods;
  }
  if (scene_list.empty()) return fallback;
  std::vector<rk::method> methods = methods_of(scene_list, "[run] methods", "; override with --methods");
  check_methods_for_ladders(methods, steps, tols, "[run] methods");
  return methods;
}

// ---- steps ---------------------------------------------------------------------------------------

step_spec flag_step(const std::string& flag, const std::string& text) {
  step_spec spec;
  if (text.starts_with("K/")) {
    std::int64_t n = 0;
    const char* digits = text.data() + 2;
    auto [ptr, ec] = std::from_chars(digits, text.data() + text.size(), n);
    if (ec != std::errc{} || ptr != text.data() + text.size() || n < 1)
      throw input_error(
          fmt::format("{} {}: expected K/N with a whole number N >= 1, or a positive number", flag, text));
    spec.K_divisor = n;
  } else {
    spec.value = positive_flag_number(flag, text);
  }
  return spec;
}

fixed_step_choice fixed_step_of(const scene& s, const std::optional<std::string>& flag,
                                std::int64_t default_K_divisor) {
  if (flag) return resolve_step(s, flag_step("--step", *flag), "--step " + *flag);
  if (s.step) return resolve_step(s, *s.step, "[run] step (override with --step)");
  step_spec spec;
  spec.K_divisor = default_K_divisor;
  return resolve_step(s, spec, fmt::format("the default step K/{} (give --step)", default_K_divisor));
}

std::vector<ladder_step> step_ladder(const scene& s, const std::vector<std::string>& texts, const std::string& flag,
                                     bool from_default, std::size_t samples) {
  std::vector<ladder_step> out;
  for (const std::string& text : texts) {
    if (std::any_of(out.begin(), out.end(), [&](const ladder_step& st) { return st.text == text; }))
      throw input_error(fmt::format("{}: step {} is listed twice", flag, text));
    ladder_step st;
    st.text = text;
    const std::string origin = from_default ? fmt::format("the default ladder's step {} (give {})", text, flag)
                                            : fmt::format("{} {}", flag, text);
    st.choice = resolve_step(s, flag_step(flag, text), origin);
    st.sample_every = std::max<std::size_t>(1, st.choice.n_steps / std::max<std::size_t>(samples, 1));
    out.push_back(std::move(st));
  }
  return out;
}

max_step_choice max_step_of(const scene& s, const std::optional<std::string>& flag) {
  const auto choice = [&](const std::string& text, const std::string& origin) -> max_step_choice {
    const fixed_step_choice c = step_length(s, flag_step(origin, text), origin);
    return {c.h, fmt::format("{} ({})", text, c.rule)};
  };
  if (flag) return choice(*flag, "--max-step " + *flag);  // its messages name the text twice: "--max-step K/0 K/0: ..."
  try {
    return choice(default_max_step, "the default --max-step " + default_max_step);
  } catch (const input_error&) {  // K is undefined at the initial state
    const double span = tau_end_of<double>(s);
    return {span, fmt::format("the span, {} (K is undefined at the initial state)", span)};
  }
}

// ---- batch and check -------------------------------------------------------------------------------

shard_spec flag_shard(const std::string& text) {
  const auto bad = [&] {
    return input_error(fmt::format("--shard: expected I/N with 1 <= I <= N (e.g. 3/16), got `{}`", text));
  };
  const auto slash = text.find('/');
  if (slash == std::string::npos || slash == 0 || slash + 1 == text.size()) throw bad();
  const std::string a = text.substr(0, slash), b = text.substr(slash + 1);
  const auto digits = [](const std::string& s) {
    return s.size() <= 9 && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (!digits(a) || !digits(b)) throw bad();
  shard_spec s{std::stoll(a), std::stoll(b)};
  if (s.count < 1 || s.index < 1 || s.index > s.count) throw bad();
  return s;
}

column_names flag_columns(const std::optional<std::string>& text) {
  static const std::array<std::string, 15> canonical = {"tau", "Omega1", "Omega2", "Omega3", "t",  "omega1", "omega2",
                                                       "omega3", "y1", "y2",     "y3",     "q0", "q1",     "q2",
                                                       "q3"};
  column_names out;
  for (const std::string& c : canonical) {
    out.file[c] = c;
    out.renamed[c] = false;
  }
  if (!text) return out;
  for (const std::string& item : flag_list("--columns", *text)) {
    const std::size_t eq = item.find('=');
    const std::string key = trimmed(std::string_view(item).substr(0, eq));
    const std::string value = eq == std::string::npos ? "" : trimmed(std::string_view(item).substr(eq + 1));
    if (eq == std::string::npos || value.empty())
      throw input_error(fmt::format("--columns {}: `{}` is not NAME=COLUMN", *text, item));
    if (!out.file.contains(key))
      throw input_error(
          fmt::format("--columns {}: unknown name `{}` (expected: tau, Omega1..3, t, omega1..3, y1..3, q0..3)", *text, key));
    out.file[key] = value;
    out.renamed[key] = true;
  }
  return out;
}

}  // namespace eulervop::app
