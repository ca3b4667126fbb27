// The scene's own time for what a long computation tells the user: its progress
// (compute/progress.hpp) and where a numerical failure happened.
#pragma once

#include "compute/progress.hpp"
#include "compute/scene_library.hpp"

#include <eulervop/core/numerical_failure.hpp>

#include <string>
#include <string_view>
#include <utility>

namespace eulervop::app {

// t in seconds for a physical scene (tau / (dtau/dt) of Eq. 4, or tau itself in the direct form),
// t for the coefficient form, tau for a normalized scene.
scene_clock clock_of(const scene& s);

// A time of scene `s`, given in tau, in the scene's own words, to six significant digits:
// "tau = 136" (a normalized scene), "t = 100" (the coefficient form), "t = 50 s" (a body in the
// direct form, whose time is t), "t = 600 s (tau = 173.205)" (a body in the normalized form, whose
// runs integrate in tau). `equals` is " = ", or "=" inside a table's cell.
std::string scene_time_text(const scene& s, double tau, std::string_view equals = " = ");

// Runs `run` with the scene's clock set for the progress display, and states a numerical failure
// in the scene's time first ("at t=X s (tau=Y)").
template <class Run>
decltype(auto) in_scene_time(const scene& s, Run&& run) {
  const scene_clock clock = clock_of(s);
  const scene_clock_scope scope(clock);
  try {
    return std::forward<Run>(run)();
  } catch (const numerical_failure& e) {
    if (clock.unit.name == "tau" || !e.status().tau) throw;
    throw e.placed_at(clock.at(*e.status().tau));
  }
}

}  // namespace eulervop::app
