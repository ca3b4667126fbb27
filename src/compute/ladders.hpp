// The rungs of the work-precision ladders of `sweep` and `map` (and the tolerances of
// `report --tols`): a fixed step as given and resolved, a tolerance as given, and the defaults.
#pragma once

#include "compute/step_rule.hpp"

#include <cstddef>
#include <string>

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

// The default fixed steps K/25, K/50, ..., K/6400 (doubling) and tolerances 1e-3 ... 1e-15 (a
// factor 100 apart; 1e-15, next to the rounding of double, is where DOP853 reaches 1e-12 on
// the paper scene).
inline const std::string default_step_ladder = "K/25,K/50,K/100,K/200,K/400,K/800,K/1600,K/3200,K/6400";
inline const std::string default_tol_ladder = "1e-3,1e-5,1e-7,1e-9,1e-11,1e-13,1e-15";
// The adaptive runs' default maximum step: a half of K, the quarter period of the initial
// motion (the VOP elements' forcing then gets at least 8 steps per period).
inline const std::string default_max_step = "K/2";

}  // namespace eulervop::app
