#include "comparison_common.hpp"

#include "atomic_file.hpp"
#include "input_error.hpp"
#include "scene_overrides.hpp"
#include "scene_problem.hpp"

#include <eulervop/elliptic.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include <sys/wait.h>

#ifndef EULERVOP_SOURCE_DIR
#define EULERVOP_SOURCE_DIR "."
#endif

namespace eulervop::app {

namespace fs = std::filesystem;

// ---- the step ---------------------------------------------------------------------------------

step_spec parse_step_text(const std::string& text, const std::string& flag) {
  step_spec spec;
  if (text.starts_with("K/")) {
    std::int64_t n = 0;
    const char* digits = text.data() + 2;
    auto [ptr, ec] = std::from_chars(digits, text.data() + text.size(), n);
    if (ec != std::errc{} || ptr != text.data() + text.size() || n < 1)
      throw input_error(fmt::format("{} {}: expected K/N with a whole number N >= 1, or a positive number", flag, text));
    spec.K_divisor = n;
  } else {
    spec.value = positive_flag_number(flag, text);
  }
  return spec;
}

step_spec parse_step_flag(const std::string& text) { return parse_step_text(text, "--step"); }

fixed_step_choice step_length(const scene& s, const step_spec& spec, const std::string& origin) {
  fixed_step_choice out;
  if (spec.K_divisor) {
    const auto N = static_cast<double>(*spec.K_divisor);
    const vec3<double> Om = to_problem<double>(s).Omega0;
    const double c1 = std::hypot(Om[0], Om[1]), c2 = std::hypot(Om[1], Om[2]);
    if (!(c1 > 0 || c2 > 0))
      throw input_error(fmt::format("{}: K/N needs a rotating initial state (Omega(0) = 0); give the step as a number",
                                    origin));
    if (c1 == c2)
      throw input_error(fmt::format("{}: K/N is undefined at k0 = c1/c2 = 1 (the separatrix, K = infinity); give the "
                                    "step as a number",
                                    origin));
    if (c1 < c2) {
      const double k0 = c1 / c2;
      const double K = elliptic_modulus<double>(k0).K();
      out.h = K / (N * c2);
      out.rule = fmt::format("h = K(k0)/({} c2) = {} with k0 = c1/c2 = {}, K = {}, c2 = {}", *spec.K_divisor, out.h,
                             k0, K, c2);
    } else {
      // Rotation near the minor axis: the period is set by the reciprocal modulus (docs/vop-strategies.md).
      const double k0 = c1 / c2;  // may be inf when c2 = 0
      const double K = elliptic_modulus<double>(c2 / c1).K();
      out.h = K / (N * c1);
      out.reciprocal = true;
      out.rule = fmt::format("h = K(1/k0)/({} c1) = {} with the reciprocal modulus, since k0 = c1/c2 = {} >= 1; K = {}, "
                             "c1 = {}",
                             *spec.K_divisor, out.h, k0, K, c1);
    }
  } else {
    const double value = spec.value->value;
    if (s.is_physical()) {
      out.h = value * scaling_of<double>(s).tau_rate();
      out.rule = fmt::format("h = {} s in t = {} in tau", spec.value->text, out.h);
    } else {
      out.h = value;
      out.rule = fmt::format("h = {}", spec.value->text);
    }
  }
  if (!(out.h > 0) || !std::isfinite(out.h))
    throw input_error(fmt::format("{}: the step h = {} in tau is not a positive finite number", origin, out.h));
  return out;
}

fixed_step_choice resolve_step(const scene& s, const step_spec& spec, const std::string& origin) {
  fixed_step_choice out = step_length(s, spec, origin);
  const double tau_span = tau_end_of<double>(s);
  const double n = std::floor(tau_span / out.h + 1e-9);
  constexpr double max_steps = 2e9;
  if (n < 1)
    throw input_error(fmt::format("{}: the step h = {} in tau is longer than the span (tau_end = {})", origin, out.h,
                                  tau_span));
  if (n > max_steps)
    throw input_error(fmt::format("{}: h = {} in tau needs {:.3g} steps to tau_end = {} (at most {:.0e})", origin,
                                  out.h, n, tau_span, max_steps));
  out.n_steps = static_cast<std::size_t>(n);
  return out;
}

// ---- formulations and methods -------------------------------------------------------------------

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + std::string(n);
  return s;
}

std::vector<std::string> available_formulations() {
  std::vector<std::string> names;
  for (formulation f : all_formulations) names.emplace_back(formulation_name(f));
  return names;
}

std::vector<std::string> available_methods() {
  std::vector<std::string> names;
  for (rk::method m : rk::fixed_step_methods) names.emplace_back(rk::method_name(m));
  return names;
}

// `where` names the source in messages: "--formulations euler,foo" or "[run] formulations".
std::vector<formulation> formulations_of(const std::vector<std::string>& names, const std::string& where,
                                         const std::string& hint) {
  std::vector<formulation> out;
  for (const std::string& name : names) {
    const auto f = formulation_from_name(name);
    if (!f) {
      const bool known = std::find(known_formulations.begin(), known_formulations.end(), name) != known_formulations.end();
      throw input_error(fmt::format("{}: formulation `{}` {} (available: {}){}", where, name,
                                    known ? "is not implemented yet" : "is unknown", joined(available_formulations()),
                                    hint));
    }
    if (std::find(out.begin(), out.end(), *f) != out.end())
      throw input_error(fmt::format("{}: formulation `{}` is listed twice", where, name));
    out.push_back(*f);
  }
  return out;
}

std::vector<rk::method> methods_of(const std::vector<std::string>& names, const std::string& where,
                                   const std::string& hint) {
  std::vector<rk::method> out;
  for (const std::string& name : names) {
    const auto m = rk::method_from_name(name);
    if (!m)
      throw input_error(fmt::format("{}: method `{}` is unknown (available: {}){}", where, name,
                                    joined(available_methods()), hint));
    if (std::find(out.begin(), out.end(), *m) != out.end())
      throw input_error(fmt::format("{}: method `{}` is listed twice", where, name));
    out.push_back(*m);
  }
  return out;
}

// ---- the output directory -----------------------------------------------------------------------

output_dir::output_dir(const fs::path& dir, const std::string& probe_file) : dir_(dir) {
  const std::string where = fmt::format("--out-dir {}", dir.string());
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) throw input_error(fmt::format("{}: exists and is not a directory", where));
  } else {
    created_ = fs::create_directories(dir, ec);
    if (ec) throw input_error(fmt::format("{}: cannot create the directory: {}", where, ec.message()));
  }
  try {
    atomic_file probe(dir / probe_file);  // removed again on scope exit
  } catch (const input_error& e) {
    std::string why = e.what();
    if (why.starts_with("--out ")) why = why.substr(6);
    remove_if_created();
    throw input_error(fmt::format("{}: {}", where, why));
  }
}

output_dir::~output_dir() {
  if (!kept_) remove_if_created();
}

void output_dir::remove_if_created() noexcept {
  std::error_code ec;
  if (created_) fs::remove(dir_, ec);  // only if empty
}

void write_atomically(const fs::path& path, const std::string& text) {
  atomic_file f(path);
  f.write(text);
  f.commit();
}

nlohmann::ordered_json number_or_null(const std::optional<double>& x) {
  return x ? nlohmann::ordered_json(*x) : nlohmann::ordered_json(nullptr);
}

std::string csv_number(const std::optional<double>& x) { return x ? fmt::format("{}", *x) : std::string(); }

// ---- the figure ------------------------------------------------------------------------------------

void draw_figure(const fs::path& dir, const std::string& script_name) {
  const fs::path script = fs::path(EULERVOP_SOURCE_DIR) / "tools" / script_name;
  const std::string how =
      fmt::format("apt-get install python3-matplotlib, then tools/{} {}", script_name, dir.string());
  std::error_code ec;
  if (!fs::exists(script, ec)) {
    fmt::print(stderr, "figure skipped: {} not found ({})\n", script.string(), how);
    return;
  }
  auto quote = [](const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
  };
  // The python3 on PATH first; then Debian's own, which is where python3-matplotlib installs
  // (a pyenv or venv python3 on PATH does not see it).
  int code = -1;
  std::string output;
  for (const char* python : {"python3", "/usr/bin/python3"}) {
    if (python[0] == '/' && !fs::exists(python, ec)) continue;
    const std::string cmd = fmt::format("{} {} {} 2>&1 < /dev/null", python, quote(script.string()), quote(dir.string()));
    std::fflush(stdout);
    FILE* pipe = ::popen(cmd.c_str(), "r");
    if (!pipe) continue;
    output.clear();
    char buf[512];
    while (std::size_t n = std::fread(buf, 1, sizeof buf, pipe)) output.append(buf, n);
    const int status = ::pclose(pipe);
    code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (code != 4 && code != 127) break;  // drawn, or failed for another reason
  }
  if (code == 0) return;
  if (code == 4) {
    fmt::print(stderr, "figure skipped: matplotlib not found ({})\n", how);
  } else if (code == 127) {
    fmt::print(stderr, "figure skipped: python3 not found ({})\n", how);
  } else {
    std::string last;  // the last line of the script's output says why (a traceback ends with it)
    std::istringstream in(output);
    for (std::string l; std::getline(in, l);)
      if (!l.empty()) last = l;
    fmt::print(stderr, "figure failed: {} exited with code {}: {}\n", script_name, code, input_error::one_line(last));
  }
}

void probe_formulations(const std::vector<formulation>& forms, const normalized_problem<double>& problem, double h) {
  for (formulation f : forms) {
    try {
      (void)run_fixed(f, rk::method::rk4, problem, fixed_run_settings{h, 1, 1});
    } catch (const std::domain_error& e) {
      throw input_error(fmt::format("formulation {} cannot start from this scene: {} (leave it out with --formulations)",
                                    formulation_name(f), e.what()));
    }
  }
}

}  // namespace eulervop::app
