// A grid of comparison runs on one scene: every formulation x method x fixed step of a ladder,
// and x tolerance of a ladder for the methods with an embedded pair. The grid of `sweep` (one
// scene) and of `map` (one scene per torque scale).
#pragma once

#include "compute/ladders.hpp"
#include "compute/scene_library.hpp"
#include "compute/step_rule.hpp"

#include <eulervop/rk/tableaux.hpp>
#include <eulervop/runs/formulation.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace eulervop::app {

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
  max_step_choice max_step;    // the adaptive runs' maximum step, in tau
  std::size_t samples = 200;   // error samples per run, about
  std::vector<wp_case> cases;  // formulation-major, then method, then the steps, then the tols

  // forms x methods x (steps for the fixed-step methods, tols for the adaptive ones).
  void make_cases();
  // "rk8 K/400", "dop853 tol 1e-10".
  std::string configuration(const wp_case& c) const;
  // The rung's text: "K/400" or "tol 1e-10".
  std::string rung_text(const wp_case& c) const;
};

}  // namespace eulervop::app
