// What the subcommands that run the double-precision comparisons share (`report`, `sweep`):
// the step rule ("K/N" or a number), the formulation and method lists, the output directory,
// atomic writes and the figure drawn by a python script in tools/.
#pragma once

#include "scene.hpp"

#include <eulervop/comparison_run.hpp>
#include <eulervop/model.hpp>
#include <eulervop/runge_kutta.hpp>
#include <eulervop/scalar.hpp>

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace eulervop::app {

// ---- the step ---------------------------------------------------------------------------------

// The fixed step of the comparison runs, in tau.
struct fixed_step_choice {
  double h = 0;
  std::size_t n_steps = 0;     // floor(tau_span / h + 1e-9): the runs end at n_steps h <= tau_end
  bool reciprocal = false;     // "K/N" with k0 > 1: K(1/k0) / (N c1)
  std::string rule;            // how h was obtained, for the summary
};

// Resolves a step specification for scene `s` ("K/N": h = K(k0) / (N c2_0), or for k0 > 1
// K(1/k0) / (N c1_0); a number: h in the scene's time variable, converted to tau). `origin`
// names where the step came from ("--step K/0", "[run] step") in messages.
fixed_step_choice resolve_step(const scene& s, const step_spec& spec, const std::string& origin);
// The same length alone (n_steps stays 0): for a maximum step, which may exceed the span.
fixed_step_choice step_length(const scene& s, const step_spec& spec, const std::string& origin);

// Parses step text: "K/N" (whole N >= 1) or a positive number; input_error "FLAG TEXT: why".
step_spec parse_step_text(const std::string& text, const std::string& flag);
// The --step flag of `report`.
step_spec parse_step_flag(const std::string& text);

// n h, exactly in quad and MPFR (a 53-bit h times an integer below 2^53).
template <scalar T>
T tau_of_step(std::size_t n, double h) {
  return T(static_cast<double>(n)) * T(h);
}

// ---- formulations and methods -------------------------------------------------------------------

std::string joined(const std::vector<std::string>& names);
std::vector<std::string> available_formulations();
std::vector<std::string> available_methods();

// Names -> values; input_error naming `where` ("--formulations euler,foo", "[run] formulations")
// for an unknown or repeated name, followed by `hint`.
std::vector<formulation> formulations_of(const std::vector<std::string>& names, const std::string& where,
                                         const std::string& hint);
std::vector<rk::method> methods_of(const std::vector<std::string>& names, const std::string& where,
                                   const std::string& hint);

// A formulation that cannot start from this state (the paper's VOP needs k0 < 1) is bad input:
// one step of each, before anything is computed.
void probe_formulations(const std::vector<formulation>& forms, const normalized_problem<double>& problem, double h);

// ---- output ------------------------------------------------------------------------------------

// Creates the output directory (if missing) and checks that files can be created in it (by
// creating and removing a temporary next to `probe_file`), before any computation. If the
// command then fails, a directory it created is removed again (it is still empty: every file
// is written atomically at the end).
class output_dir {
 public:
  output_dir(const std::filesystem::path& dir, const std::string& probe_file);
  ~output_dir();
  output_dir(const output_dir&) = delete;
  output_dir& operator=(const output_dir&) = delete;

  void keep() { kept_ = true; }
  const std::filesystem::path& path() const { return dir_; }

 private:
  void remove_if_created() noexcept;
  std::filesystem::path dir_;
  bool created_ = false;
  bool kept_ = false;
};

void write_atomically(const std::filesystem::path& path, const std::string& text);

nlohmann::ordered_json number_or_null(const std::optional<double>& x);
// A CSV cell: the shortest round-trip text of x, or empty.
std::string csv_number(const std::optional<double>& x);

// Runs tools/<script> DIR (python3 on PATH, then /usr/bin/python3). Never fails the command: a
// missing python3 or matplotlib (the script exits with 4) is one line on stderr saying how to
// get the figure.
void draw_figure(const std::filesystem::path& dir, const std::string& script);

}  // namespace eulervop::app
