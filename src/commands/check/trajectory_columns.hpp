// The trajectory `check` reads: its columns, found by name (tau and Omega1..3, t and omega1..3,
// or t and y1..3 for the coefficient form, and q0..q3 for an attitude; --columns renames), and
// its rows, each checked as it is read.
#pragma once

#include "commands/check/check_job.hpp"
#include "commands/check/compared_variables.hpp"
#include "compute/scene_library.hpp"
#include "io/table_rows.hpp"

#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/core/scalar_traits.hpp>

#include <array>
#include <cstddef>
#include <optional>
#include <string>

namespace eulervop::app {

struct trajectory_columns {
  bool physical = false;        // the time is t (omega1..3, or y1..3)
  std::string state = "Omega";  // the state's name: Omega, omega or y
  std::size_t time = 0;
  std::array<std::size_t, 3> value{};
  std::string time_name;  // as in the file
  // The attitude q0..q3 (scalar first), if the file has those columns: all four or none.
  std::optional<std::array<std::size_t, 4>> q;
};

// The canonical names the reference is compared by (for a header that has neither): tau and
// Omega, t and omega, or t and y.
struct expected_names {
  std::string time = "tau", state = "Omega";
};

// The columns of the header of `rows`; input_error naming the missing one otherwise, with the
// header's own names and the --columns that maps them to `expected`.
trajectory_columns find_columns(const check_job& job, const table_rows& rows, const expected_names& expected);

// The trajectory has q0..q3 but the reference no attitude: input_error "<where>: line <header>:
// columns q0..q3: <reference> has no attitude (<why>)". Without q0..q3, --attitude-tol is bad
// input too (there is nothing to hold to it), and so is a bar on the rates without
// --attitude-tol or --ignore-attitude when there are q0..q3 (no silent pass).
void require_attitude_match(const check_job& job, const trajectory_columns& cols, const table_rows& rows,
                            bool reference_has_attitude, const std::string& reference, const std::string& why);

// The names and units of the compared variables (compared_variables.hpp) of a trajectory with
// columns `cols`, against the reference of a scene that is physical or not. `normalized_apart`:
// the compared variables are not the integrator's, which are then reported beside them.
compared_terms terms_of(const trajectory_columns& cols, bool physical_scene, bool normalized_apart);

// A trajectory row: its time and state, checked (numbers, time >= 0 and increasing).
struct row_reader {
  table_rows& rows;
  const trajectory_columns& cols;
  std::optional<decimal> previous;
  std::size_t previous_line = 0;

  decimal time();
  std::array<decimal, 3> values() const;
  // q0..q3 (cols.q must be set), not all zero.
  std::array<decimal, 4> attitude() const;
};

// Three cells as a vector in T.
template <scalar T>
vec3<T> vec3_of(const std::array<decimal, 3>& d) {
  return {d[0].template to_scalar<T>(), d[1].template to_scalar<T>(), d[2].template to_scalar<T>()};
}

// q0..q3 as a quaternion in T.
template <scalar T>
quaternion<T> quaternion_of(const std::array<decimal, 4>& q) {
  return {q[0].template to_scalar<T>(), q[1].template to_scalar<T>(), q[2].template to_scalar<T>(),
          q[3].template to_scalar<T>()};
}

}  // namespace eulervop::app
