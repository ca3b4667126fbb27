// The tally of a check: each trajectory row's Eq. 20 error against the reference at its time,
// against the bar (--tol, --rel-tol; with a certified reference, +- the row's radius), and the
// oracle metrics over all rows; for a trajectory with q0..q3, each row's attitude error (the
// angle of the rotation from the reference's q to the row's) against --attitude-tol.
#pragma once

#include "commands/check/check_job.hpp"
#include "commands/check/compared_variables.hpp"
#include "commands/check/errors_writer.hpp"
#include "commands/check/scene_terms.hpp"
#include "compute/scene_library.hpp"

#include <eulervop/core/numerical_failure.hpp>
#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/model/error_measure.hpp>
#include <eulervop/model/euler_problem.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace eulervop::app {

// The trajectory's first row at time 0 against the reference there, which is the scene's initial
// state: a trajectory started from another state (or with its q in another convention) is named
// as such, not only as a large error at t = 0. The limit is the bar when one is given, else
// `initial_state_rel` (relative for the rates, radians for the attitude).
inline constexpr double initial_state_rel = 1e-6;

struct first_row_check {
  bool done = false;  // the first row is at time 0
  std::size_t line = 0;
  std::string time;
  double rate_difference = 0, rate_limit = 0;  // in the compared variables
  bool rate_limit_is_bar = false;
  bool rates_match = true;
  bool attitude = false;  // the row has q0..q3
  double attitude_difference = 0, attitude_limit = 0;  // radians
  bool attitude_limit_is_bar = false;
  bool attitude_match = true;
  // When the row's q does not match: the order of its columns that does (order[k]: the column,
  // 0..3 of q0..q3 as found, that holds the reference's q_k), and whether the vector part is
  // negated as well (the inverse rotation).
  std::optional<std::array<int, 4>> q_order;
  bool q_inverse = false;
  bool matches() const { return rates_match && attitude_match; }
};

struct tally {
  std::size_t rows = 0;
  std::string first_time, last_time;  // as written in the file
  // The errors in the compared variables (compared_variables.hpp): rad/s for physical columns.
  double max_error = -1;
  std::string max_time;
  std::size_t max_line = 0;
  long double sum_squares = 0;
  // The Eq. 20 error in the normalized variables, when those are not the compared ones.
  double max_normalized_error = -1;
  std::string max_normalized_time;
  long double normalized_sum_squares = 0;
  std::size_t exceeding = 0;
  std::optional<std::string> first_exceeding_time;
  std::size_t first_exceeding_line = 0;
  // The oracle metrics (IVP Test Set and DiffEqDevTools terms), over rows and components:
  double max_relative = 0;  // max |dy_i| / |y_ref_i| over the components with y_ref_i != 0 (scd)
  double max_mixed = 0;     // max |dy_i| / (atol/rtol + |y_ref_i|) (mescd)
  std::array<double, 3> max_component{};  // max |dy_i| per component
  // Where the largest relative error (scd) is: the component, the reference's value there, the
  // row. A small reference value (rates that decay) explains a low scd on a good trajectory.
  int scd_component = -1;
  double scd_reference = 0;
  std::string scd_time;
  std::size_t scd_line = 0;
  // c1^2 and c2^2 (Eq. 7, of the normalized variables) of the trajectory minus the reference's:
  // largest magnitude, and at the last row. They are constant only for the torque-free normalized
  // problem of Eq. 5: whether they are reported is the scene's to say (scene_terms.hpp).
  double c1_drift_max = 0, c2_drift_max = 0, c1_drift_last = 0, c2_drift_last = 0;
  // The error along the reference's direction of motion (Eq. 5's right-hand side there: a phase
  // error) and across it, largest over the rows; absent without the torque.
  bool has_direction = false;
  double max_along = 0, max_across = 0;
  // Against a certified reference (a `radius` column, docs/certified.md): each row's error is the
  // interval error +- radius. A row fails only when error - radius exceeds the bar, and is
  // uncertain when the bar lies inside its interval.
  bool certified = false;
  double max_radius = 0;
  std::size_t uncertain = 0;
  std::vector<std::size_t> uncertain_lines;  // the first max_listed_lines of them
  static constexpr std::size_t max_listed_lines = 1000;
  // The attitude: `reference_attitude` when the reference has one (q0..q3), `attitude` when the
  // trajectory's q0..q3 are checked against it. Each row's error is the rotation angle from the
  // reference's q to the row's, in radians (the same for q and -q).
  bool reference_attitude = false;
  bool attitude = false;
  double max_attitude = -1;
  std::string max_attitude_time;
  std::size_t max_attitude_line = 0;
  long double attitude_sum_squares = 0;
  std::size_t attitude_exceeding = 0;  // rows above --attitude-tol
  std::optional<std::string> first_attitude_exceeding_time;
  std::size_t first_attitude_exceeding_line = 0;
  first_row_check first;
};

// A row's attitude beside its rates: the reference's q and the trajectory's (any norm but 0).
template <scalar T>
struct attitude_pair {
  quaternion<T> reference, trajectory;
};

// What a check found, and how it describes its reference.
struct check_result {
  tally t;
  std::string time_name;
  compared_terms terms;
  std::string reference_text;  // for the table
  nlohmann::ordered_json reference_json;
  scene_terms scene;                    // what the reference's scene says about the metrics
  std::array<std::string, 4> q_columns;  // the trajectory's names of q0..q3 (for a hint on their order)
};

// The oracle metrics of one row (tally's second half), in the compared variables but for Eq. 7,
// which is stated in the normalized ones. Each difference is taken in T and rounded to double
// once; the rest is figures of a few digits, computed in double. `motion`: the equations, for the
// reference's direction of motion at `tau` (its time in the integrator's variables), if known.
template <scalar T>
void record_metrics(const check_job& job, tally& t, std::size_t line, const decimal& time, const row_states<T>& s,
                    const compared_variables<T>& vars, const motion_function* motion, const T& tau) {
  const vec3<T>& ref = s.reference;
  std::array<double, 3> d, y;
  for (int i = 0; i < 3; ++i) {
    d[i] = static_cast<double>(T(s.trajectory[i] - ref[i]));
    y[i] = static_cast<double>(ref[i]);
    const double err = std::abs(d[i]), size = std::abs(y[i]);
    t.max_component[i] = std::max(t.max_component[i], err);
    if (size > 0 && err / size > t.max_relative) {
      t.max_relative = err / size;
      t.scd_component = i;
      t.scd_reference = size;
      t.scd_time = time.text;
      t.scd_line = line;
    }
    t.max_mixed = std::max(t.max_mixed, err / (job.scd_atol / job.scd_rtol + size));
  }
  // c1^2 and c2^2 of the trajectory minus the reference's: Om_i^2 - Ref_i^2 = (Om_i - Ref_i)(Om_i + Ref_i),
  // the difference from T, so that a tiny drift keeps its digits.
  const vec3<T>& Om = s.trajectory_Omega;
  const vec3<T>& Ref = s.reference_Omega;
  std::array<double, 3> square;
  for (int i = 0; i < 3; ++i)
    square[i] = static_cast<double>(T(Om[i] - Ref[i])) * (static_cast<double>(Om[i]) + static_cast<double>(Ref[i]));
  t.c1_drift_last = square[0] + square[1];
  t.c2_drift_last = square[1] + square[2];
  t.c1_drift_max = std::max(t.c1_drift_max, std::abs(t.c1_drift_last));
  t.c2_drift_max = std::max(t.c2_drift_max, std::abs(t.c2_drift_last));
  if (!motion) return;
  vec3<double> v_Omega;
  (*motion)(static_cast<double>(tau), {static_cast<double>(Ref[0]), static_cast<double>(Ref[1]),
                                       static_cast<double>(Ref[2])}, v_Omega);
  const vec3<double> v = vars.direction(v_Omega);
  const double speed = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (!(speed > 0)) return;  // at rest: no direction of motion (the row is left out of the split)
  t.has_direction = true;
  const double along = (d[0] * v[0] + d[1] * v[1] + d[2] * v[2]) / speed;
  const double across2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - along * along;
  t.max_along = std::max(t.max_along, std::abs(along));
  t.max_across = std::max(t.max_across, across2 > 0 ? std::sqrt(across2) : 0.0);
}

// The attitude error of one row (tally's last part); with `text`, also the text --errors-out
// writes: every digit of T. rotation_angle does not depend on the norms of the quaternions, so
// the trajectory's q need not be normalized; the angle is in [0, pi].
template <scalar T>
void record_attitude(const check_job& job, tally& t, std::size_t line, const decimal& time, const attitude_pair<T>& q,
                     std::string* text) {
  const T angle = rotation_angle(q.reference, q.trajectory);
  const double a = static_cast<double>(angle);
  if (!std::isfinite(a)) throw numerical_failure({outcome_kind::error_non_finite, time.value});
  if (job.attitude_tol && a > *job.attitude_tol) {
    if (!t.attitude_exceeding) {
      t.first_attitude_exceeding_time = time.text;
      t.first_attitude_exceeding_line = line;
    }
    ++t.attitude_exceeding;
  }
  if (a > t.max_attitude) {
    t.max_attitude = a;
    t.max_attitude_time = time.text;
    t.max_attitude_line = line;
  }
  t.attitude_sum_squares += static_cast<long double>(a) * a;
  if (text) *text = to_text(angle);
}

// The norm of a state, in double (for the limits, which need no more).
template <scalar T>
double norm_of(const vec3<T>& v) {
  using std::sqrt;
  return static_cast<double>(sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
}

// The first row, at time 0, against the reference's initial state (first_row_check). `e`: the
// row's Eq. 20 error; `bar`: its bar on the rates, if given.
template <scalar T>
void record_first_row(const check_job& job, tally& t, std::size_t line, const decimal& time, double e,
                      const row_states<T>& s, std::optional<double> bar, const attitude_pair<T>* q) {
  first_row_check& f = t.first;
  f.done = true;
  f.line = line;
  f.time = time.text;
  f.rate_difference = e;
  f.rate_limit_is_bar = bar.has_value();
  f.rate_limit = bar ? *bar : initial_state_rel * std::max(norm_of(s.reference), norm_of(s.trajectory));
  f.rates_match = !(e > f.rate_limit);
  if (!q) return;
  f.attitude = true;
  const double angle = static_cast<double>(rotation_angle(q->reference, q->trajectory));
  f.attitude_difference = angle;
  f.attitude_limit_is_bar = job.attitude_tol.has_value();
  f.attitude_limit = job.attitude_tol.value_or(initial_state_rel);
  f.attitude_match = !(angle > f.attitude_limit);
  if (f.attitude_match) return;
  // A reordering of the row's q0..q3, or its inverse, that gives the reference's q: the likely
  // mix-up of conventions. It must match to the limit (at least initial_state_rel, so that a q
  // written in fewer digits is still recognized) and be ten times closer than the row as written,
  // so that equal components swapped are no hint. Scalar last, and the inverse, are tried first.
  const double limit = std::max(f.attitude_limit, initial_state_rel);
  const auto matches = [&](const std::array<int, 4>& order, bool inverse) {
    const std::array<T, 4> c = {q->trajectory.w, q->trajectory.x, q->trajectory.y, q->trajectory.z};
    const T sign = inverse ? T(-1) : T(1);
    const quaternion<T> candidate{c[order[0]], sign * c[order[1]], sign * c[order[2]], sign * c[order[3]]};
    const double a = static_cast<double>(rotation_angle(q->reference, candidate));
    return a <= limit && 10 * a <= angle;
  };
  const std::array<int, 4> identity = {0, 1, 2, 3}, scalar_last = {3, 0, 1, 2};
  std::vector<std::pair<std::array<int, 4>, bool>> tries = {
      {scalar_last, false}, {identity, true}, {scalar_last, true}};
  for (std::array<int, 4> order = identity;;) {
    if (order != identity && order != scalar_last) {
      tries.push_back({order, false});
      tries.push_back({order, true});
    }
    if (!std::next_permutation(order.begin(), order.end())) break;
  }
  for (const auto& [order, inverse] : tries)
    if (matches(order, inverse)) {
      f.q_order = order;
      f.q_inverse = inverse;
      return;
    }
}

// The two-norm error of Eq. 20 in the normalized variables, when the compared ones differ.
template <scalar T>
void record_normalized(tally& t, const decimal& time, const row_states<T>& s) {
  const double e = static_cast<double>(eq20_error(s.reference_Omega, s.trajectory_Omega));
  if (e > t.max_normalized_error) {
    t.max_normalized_error = e;
    t.max_normalized_time = time.text;
  }
  t.normalized_sum_squares += static_cast<long double>(e) * e;
}

// `radius`: the reference row's certified radius (of the compared state), if it has one. `tau`:
// the row's time in the integrator's variables (for a torque of time, the direction of motion
// depends on it); `motion`: the equations for that direction, or null. `attitude`: the row's attitude and the reference's, for a trajectory with q0..q3.
// The error is the two-norm of Eq. 20 taken in the compared variables.
template <scalar T>
void record(const check_job& job, tally& t, errors_writer& out, std::size_t line, const decimal& time,
            const row_states<T>& s, const compared_variables<T>& vars, const motion_function* motion, const T& tau,
            const std::optional<decimal>& radius = std::nullopt, const attitude_pair<T>* attitude = nullptr) {
  const vec3<T>& ref = s.reference;
  const double e = static_cast<double>(eq20_error(ref, s.trajectory));
  if (!std::isfinite(e)) throw numerical_failure({outcome_kind::error_non_finite, time.value});
  std::string attitude_text;
  if (attitude) record_attitude(job, t, line, time, *attitude, out.writing() ? &attitude_text : nullptr);
  record_metrics(job, t, line, time, s, vars, motion, tau);
  if (vars.physical()) record_normalized(t, time, s);
  const double r = radius ? radius->value : 0.0;
  if (radius) t.max_radius = std::max(t.max_radius, r);
  std::optional<double> bar;
  if (job.tol || job.rel_tol) {
    bar = job.tol.value_or(0.0) + job.rel_tol.value_or(0.0) * norm_of(ref);
    // The true error lies in [e - r, e + r]: failing only if certainly above the bar.
    if (radius && e - r <= *bar && e + r > *bar) {
      ++t.uncertain;
      if (t.uncertain_lines.size() < tally::max_listed_lines) t.uncertain_lines.push_back(line);
    }
    if (e - r > *bar) {
      if (!t.exceeding) {
        t.first_exceeding_time = time.text;
        t.first_exceeding_line = line;
      }
      ++t.exceeding;
    }
  }
  if (!t.rows && time.value == 0) record_first_row(job, t, line, time, e, s, bar, attitude);
  if (!t.rows) t.first_time = time.text;
  t.last_time = time.text;
  ++t.rows;
  if (e > t.max_error) {
    t.max_error = e;
    t.max_time = time.text;
    t.max_line = line;
  }
  t.sum_squares += static_cast<long double>(e) * e;
  out.row(line, time.text, e, bar, radius, attitude ? &attitude_text : nullptr);
}

}  // namespace eulervop::app
