#include "commands/check/against_scene.hpp"

#include "commands/check/trajectory_columns.hpp"
#include "commands/check/trajectory_stream.hpp"
#include "compute/reference_compute.hpp"
#include "compute/with_scalar.hpp"
#include "io/table_rows.hpp"

#include <eulervop/model/physical_scaling.hpp>

#include <fmt/format.h>

#include <array>
#include <cstdlib>
#include <memory>
#include <optional>

namespace eulervop::app {

namespace {

// The variables the trajectory is compared in: its own (compared_variables.hpp).
template <scalar T>
compared_variables<T> variables_of(const scene& s, const trajectory_columns& cols) {
  if (cols.physical && s.is_physical()) return compared_variables<T>(scaling_of<T>(s));
  return {};
}

// The trajectory's columns, which the scene must be able to compare: physical times need a
// physical scene, and a body in the direct form has no tau or Omega.
trajectory_columns scene_columns(const check_job& job, const table_rows& rows) {
  const scene& s = job.scn;
  const trajectory_columns cols =
      find_columns(job, rows, {std::string(s.time_name()), s.is_physical() ? "omega" : std::string(s.state_name())});
  if (cols.physical && s.units == eulervop::scene::scene_units::normalized)
    throw input_error(fmt::format("{}: line {}: column `{}` is a physical time, but scene {} is normalized (give "
                                  "tau,Omega1,Omega2,Omega3)",
                                  rows.where(), rows.line(), cols.time_name, s.name));
  if (!cols.physical && s.is_coefficient_form())
    throw input_error(fmt::format("{}: line {}: scene {} is in the coefficient form ([equations]), which has no tau or "
                                  "Omega: give t,y1,y2,y3",
                                  rows.where(), rows.line(), s.name));
  if (!cols.physical && uses_direct_form(s))
    throw input_error(fmt::format("{}: line {}: scene {} is integrated in the direct form of Eq. 1 (two moments are "
                                  "equal or nearly so), which has no tau or Omega: give t,omega1,omega2,omega3",
                                  rows.where(), rows.line(), s.name));
  if (cols.physical && (cols.state == "y") != s.is_coefficient_form())
    throw input_error(fmt::format("{}: line {}: columns {}1..3 do not fit scene {}, whose state is {}1..3",
                                  rows.where(), rows.line(), cols.state, s.name, s.state_name()));
  require_attitude_match(job, cols, rows, s.has_attitude(), "scene " + s.name, "[initial] q");
  return cols;
}

// Pass 1: the columns, and every row validated; of the times only the last one is kept, so the
// memory does not grow with the rows.
struct trajectory_scan {
  trajectory_columns cols;
  std::vector<std::string> header;
  std::size_t rows = 0;
  decimal last_time;
};

trajectory_scan scan_trajectory(const check_job& job) {
  const std::unique_ptr<table_rows> rows = job.open_trajectory();
  trajectory_scan out{scene_columns(job, *rows), rows->header(), 0, {}};
  row_reader reader{*rows, out.cols};
  while (rows->next()) {
    out.last_time = reader.time();
    reader.values();
    if (out.cols.q) reader.attitude();
    ++out.rows;
  }
  if (!out.rows) throw input_error(fmt::format("{}: no data rows", rows->where()));
  return out;
}

// `end`: the last row's time, as the file states it (`time_name` = end).
void describe_scene_reference(const check_job& job, const std::string& time_name, const std::string& end,
                              double tau_end, const reference_run& ref, check_result& r) {
  const scene& s = job.scn;
  // The time as the table prints every time: six significant digits, in the scene's units.
  r.reference_text = fmt::format("scene {} ({}, computed to {} = {:.6g}{} in {:.2f} s, {} segments)", s.name,
                                 job.precision.name(), time_name, std::strtod(end.c_str(), nullptr),
                                 r.terms.time_unit.empty() ? "" : " " + r.terms.time_unit, ref.wall_seconds,
                                 ref.stats.segments);
  r.reference_json = {{"source", "scene"},
                      {"path", job.reference_path},
                      {"scene", s.name},
                      {"precision", job.precision.name()},
                      {"time_end", std::strtod(end.c_str(), nullptr)},
                      {"tau_end", tau_end},
                      {"seconds", ref.wall_seconds},
                      {"segments", ref.stats.segments}};
}

// The scene's reference at the times `times` gives, each handed to compare(y, q): q the attitude
// (null unless `attitude`).
template <scalar T, class Compare>
reference_run integrate_against(const check_job& job, const T& tau_end, const sample_time_source<T>& times,
                                bool attitude, const Compare& compare) {
  if (job.scn.couples_attitude())
    return integrate_scene_attitude<T>(job.scn, tau_end, times, job.settings, "reference",
                                       [&](std::size_t, const vec3<T>& y, const quaternion<T>& q) {
                                         compare(y, attitude ? &q : nullptr);
                                       });
  return with_problem<T>(job.scn, [&](const auto& problem) {
    if (attitude)
      return integrate_attitude_streaming<T>(problem, body_rates_of<T>(job.scn), attitude_of<T>(job.scn), tau_end,
                                             times, job.settings, "reference",
                                             [&](std::size_t, const vec3<T>& y, const quaternion<T>& q) {
                                               compare(y, &q);
                                             });
    return integrate_streaming<T>(problem, tau_end, times, job.settings, "reference",
                                  [&](std::size_t, const vec3<T>& y) { compare(y, nullptr); });
  });
}

// The integration, with the rows pulled as its samples: the rates alone, or with the scene's
// attitude integrated beside them (integrate_attitude_streaming) when the trajectory has q0..q3,
// or the rates and q as one problem for a torque of the attitude. The sampler asks for a row only
// after it has compared the one before, so the stream holds one row at a time.
template <scalar T>
check_result check_in(const check_job& job) {
  const trajectory_scan scan = scan_trajectory(job);
  const trajectory_columns& cols = scan.cols;
  const compared_variables<T> vars = variables_of<T>(job.scn, cols);
  T tau_end = vars.tau_of(scan.last_time.template to_scalar<T>());
  if (!(tau_end > 0)) tau_end = T(1);  // a trajectory at tau = 0 only
  errors_writer out(job.errors_out);    // an unwritable path fails before the integration

  check_result r;
  r.time_name = cols.time_name;
  r.terms = terms_of(cols, job.scn.is_physical(), vars.physical());
  r.t.reference_attitude = job.scn.has_attitude();
  r.t.attitude = cols.q.has_value();
  r.scene = scene_terms_of(job.scn, cols);
  out.header(cols.time_name, false, r.t.attitude);
  if (cols.q)
    for (int k = 0; k < 4; ++k) r.q_columns[k] = scan.header[(*cols.q)[k]];
  trajectory_stream<T> rows(job, cols, scan.rows, vars, tau_end);
  // The current row against the reference there (q_ref: its attitude, if checked), with the
  // equations for the direction of motion, if they are the rates' own.
  const std::optional<motion_function> motion = motion_of(job.scn);
  const auto compare = [&](const vec3<T>& Omega_ref, const quaternion<T>* q_ref) {
    const auto& row = rows.current();
    const row_states<T> states = vars.states(Omega_ref, row.values);
    std::optional<attitude_pair<T>> q;
    if (q_ref) q = attitude_pair<T>{*q_ref, row.q};
    record<T>(job, r.t, out, row.line, row.time, states, vars, motion ? &*motion : nullptr, row.tau, std::nullopt,
              q ? &*q : nullptr);
  };
  const reference_run ref = integrate_against(job, tau_end, rows.times(), cols.q.has_value(), compare);
  out.commit();
  describe_scene_reference(job, cols.time_name, scan.last_time.text, static_cast<double>(tau_end), ref, r);
  return r;
}

}  // namespace

check_result check_against_scene(const check_job& job) {
  return with_scalar(job.precision, [&](auto zero) { return check_in<decltype(zero)>(job); });
}

}  // namespace eulervop::app
