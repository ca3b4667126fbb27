// What the reference's scene says about the figures `check` prints: whether its body is
// torque-free (the drift of Eq. 7 and the normalized Eq. 20 figure mean something only then), the
// names of its initial state (for the first row's check) and the unit of a reference file's
// estimated error.
#pragma once

#include "commands/check/trajectory_columns.hpp"
#include "compute/scene_library.hpp"

#include <eulervop/core/vec3.hpp>

#include <functional>
#include <optional>
#include <string>

namespace eulervop::app {

struct scene_terms {
  std::optional<bool> torque_free;  // not known for a reference file without `# scene_text:`
  // Eq. 7's drift: reported or not, and why not (or, when reported, why it may not apply).
  bool invariants = true;
  std::string invariants_note;
  // Not reported: a line in the table saying why (a form without Eq. 7), or none (a torque: the
  // drift of a body under a torque is no error, and the JSON says why it is null).
  bool invariants_in_table = true;
  // What the first row at time 0 is held to: "the initial state of scene NAME ([initial] omega)".
  std::string initial_rates = "the reference's state at time 0";
  std::string initial_q = "the reference's q at time 0";
  // A reference file's `# estimated_max_error`: the variables its integrator ran in (--verify
  // compares those), which are not the compared ones for a physical scene.
  std::string estimated_error_unit;   // for the JSON: "normalized (Eq. 20)", "rad/s", ...
  std::string estimated_error_label;  // for the table, after the number: "(normalized, Eq. 20)"
};

// How a reference is integrated, when its file gives no scene: from its columns.
enum class integrated_form { normalized, direct, coefficient };

// The terms of scene `s`, for a trajectory with columns `cols`.
scene_terms scene_terms_of(const scene& s, const trajectory_columns& cols);

// The terms of a reference file without `# scene_text:`, integrated in `form`.
scene_terms unknown_scene_terms(integrated_form form);


// How scene `s` is integrated.
integrated_form integrated_form_of(const scene& s);

// The rates' own equations, for the reference's direction of motion at a row (check_tally.hpp):
// the right-hand side in double, which is all a direction needs.
using motion_function = std::function<void(double tau, const vec3<double>& y, vec3<double>& dy)>;

// Scene `s`'s; none for a torque of the attitude, whose rates need q.
std::optional<motion_function> motion_of(const scene& s);

}  // namespace eulervop::app
