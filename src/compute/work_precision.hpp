// A grid of timed comparison runs on one scene, measured against one reference: every
// formulation x method x fixed step of a ladder, and x tolerance of a ladder for the methods with
// an embedded pair. The machinery of `sweep` (one scene) and `map` (one scene per torque scale).
#pragma once

#include "compute/scene_library.hpp"
#include "compute/step_rule.hpp"

#include <eulervop/reference/integrate.hpp>
#include <eulervop/runs/comparison_run.hpp>
#include <eulervop/rk/explicit_rk.hpp>
#include <eulervop/core/scalar.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace eulervop::app {

// One fixed step of the ladder.
struct ladder_step {
  std::string text;          // as given: "K/25", "0.01"
  fixed_step_choice choice;  // h in tau, steps to the span end
  std::size_t sample_every = 1;
};

// One tolerance of the ladder: atol = rtol = value.
struct ladder_tol {
  std::string text;  // as given: "1e-8"
  double value = 0;
};

struct wp_case {
  formulation form = formulation::euler;
  rk::method method = rk::method::rk4;
  bool adaptive = false;
  std::size_t rung = 0;  // index into the grid's steps (fixed) or tols (adaptive)
};

struct wp_grid {
  scene scn;
  std::vector<formulation> forms;
  std::vector<rk::method> methods;
  std::vector<ladder_step> steps;
  std::vector<ladder_tol> tols;
  double h_max = 0;  // the adaptive runs' maximum step, in tau
  std::string h_max_rule;
  std::size_t samples = 200;  // error samples per run, about
  std::vector<wp_case> cases;  // formulation-major, then method, then the steps, then the tols

  // forms x methods x (steps for the fixed-step methods, tols for the adaptive ones).
  void make_cases();
  // "rk8 K/400", "dop853 tol 1e-10".
  std::string configuration(const wp_case& c) const;
  // The rung's text: "K/400" or "tol 1e-10".
  std::string rung_text(const wp_case& c) const;
};

struct wp_result {
  run_result run;       // the first of the timed runs (they differ only in their time)
  double seconds = 0;   // the minimum time over the runs
  std::optional<double> max_error, final_error;  // Eq. 20 over the samples; none after divergence
  bool skipped = false;  // not run: a looser rung of its ladder already reached every level
};

struct wp_outcome {
  std::vector<wp_result> results;  // per case, in the grid's order
  double reference_seconds = 0;
  std::size_t reference_segments = 0;
  double reference_tau_end = 0;
};

struct wp_run_options {
  int repeat = 1;             // timed runs per case, the minimum time kept
  int jobs = 1;               // threads
  std::string progress_label;
  // If set, each ladder (one formulation, method and kind, rungs from loose to tight) stops at
  // the first rung whose max error is at most this: a tighter rung costs more and cannot be the
  // cheapest at any level. The rest are marked skipped.
  std::optional<double> stop_below;
};

// Runs every grid's reference (in precision p) and cases on `jobs` threads: the references first,
// then the cases (or, with stop_below, the ladders) longest first. Results land in their case's
// slot, so nothing depends on the scheduling but the times. Errors (Eq. 20) are computed in p at
// each run's samples. numerical_failure from a reference propagates.
std::vector<wp_outcome> run_grids(const std::vector<wp_grid>& grids, const eulervop::precision& p,
                                  const picard_settings& settings, const wp_run_options& options);

// The cheapest case per formulation whose max error is at most the level (diverged runs never),
// and the formulation with the cheapest of those.
struct level_choice {
  double level = 0;
  std::vector<std::optional<std::size_t>> best;  // per formulation (grid.forms order): case index
  std::optional<std::size_t> winner;             // index into grid.forms
};
std::vector<level_choice> cheapest_per_level(const wp_grid& grid, const wp_outcome& outcome,
                                             const std::vector<double>& levels);
// An error level as tables print it: "1e-08".
std::string level_text(double level);

// ---- ladders from flags ---------------------------------------------------------------------------

// The default fixed steps K/25, K/50, ..., K/6400 (doubling) and tolerances 1e-3 ... 1e-15 (a
// factor 100 apart; 1e-15, next to the rounding of double, is where DOP853 reaches 1e-12 on
// the paper scene).
inline const std::string default_step_ladder = "K/25,K/50,K/100,K/200,K/400,K/800,K/1600,K/3200,K/6400";
inline const std::string default_tol_ladder = "1e-3,1e-5,1e-7,1e-9,1e-11,1e-13,1e-15";
// The adaptive runs' default maximum step: a half of K, the quarter period of the initial
// motion (the VOP elements' forcing then gets at least 8 steps per period).
inline const std::string default_max_step = "K/2";

// Sets g.h_max and g.h_max_rule from --max-step (or the default; when K is undefined at the
// initial state, Omega = 0 or k0 = 1, the default is the span).
void resolve_max_step(wp_grid& g, const std::optional<std::string>& flag);

// The fixed steps "K/N" or plain numbers (`flag` names the source in messages), with about
// `samples` error samples each.
std::vector<ladder_step> step_ladder(const scene& s, const std::vector<std::string>& texts, const std::string& flag,
                                     bool from_default, std::size_t samples);
// "1e-4,1e-6,...": positive, finite, strictly monotone (either way); below 1.
std::vector<ladder_tol> tol_ladder(const std::string& flag, const std::string& text);
// The adaptive runs' maximum step: "K/N" (K of the initial modulus, as for --step) or a number
// in the scene's time variable.
fixed_step_choice max_step_of(const scene& s, const std::string& text, const std::string& origin);

// The methods for the ladders present: each must run on at least one of them (a fixed-step
// method on the steps, an adaptive one on the tolerances); input_error naming `where` otherwise.
void check_methods_for_ladders(const std::vector<rk::method>& methods, bool steps, bool tols, const std::string& where);

}  // namespace eulervop::app
