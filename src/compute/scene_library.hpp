// The scene library (eulervop::scene: scene files, exact decimals, the input_error of bad input)
// as the program names it: the program layer uses these names on nearly every line that reads
// or validates input, so it takes them into its namespace here, once, rather than qualifying each.
#pragma once

#include <eulervop/scene/decimal.hpp>
#include <eulervop/scene/input_error.hpp>
#include <eulervop/scene/scene.hpp>
#include <eulervop/scene/scene_problem.hpp>

#include <iostream>
#include <optional>
#include <string>

namespace eulervop::app {

using eulervop::scene::binary_number;
using eulervop::scene::decimal;
using eulervop::scene::decimal_problem;
using eulervop::scene::decimal_product;
using eulervop::scene::input_error;
using eulervop::scene::load_default_scene;
using eulervop::scene::load_scene_file;
using eulervop::scene::parse_decimal;
using eulervop::scene::parse_scene;
using eulervop::scene::sample_times;
using eulervop::scene::sample_times_of;
using eulervop::scene::scaling_of;
using eulervop::scene::scene;
using eulervop::scene::scene_limits;
using eulervop::scene::step_spec;
using eulervop::scene::tau_end_of;
using eulervop::scene::attitude_of;
using eulervop::scene::body_rates_of;
using eulervop::scene::initial_state_of;
using eulervop::scene::to_coupled_problem;
using eulervop::scene::to_problem;
using eulervop::scene::torque_kind;
using eulervop::scene::torque_kind_of;
using eulervop::scene::with_problem;
using eulervop::scene::with_run_problem;
using eulervop::scene::uses_direct_form;

// The scene a command works on: the file, or the embedded default. Its notes (what the user
// should know but is no error, scene.hpp) go to standard error, one "note:" line each.
inline scene load_scene(const std::optional<std::string>& path) {
  scene s = path ? load_scene_file(*path) : load_default_scene();
  for (const std::string& note : s.notes) std::cerr << "note: scene " << s.name << ": " << note << "\n";
  return s;
}

}  // namespace eulervop::app
