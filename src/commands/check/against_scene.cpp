#include "commands/check/against_scene.hpp"

#include "commands/check/trajectory_columns.hpp"
#include "compute/reference_compute.hpp"
#include "compute/with_scalar.hpp"
#include "io/csv_rows.hpp"

#include <eulervop/model/physical_scaling.hpp>

#include <fmt/format.h>

#include <cstdlib>
#include <fstream>
#include <optional>
#include <vector>

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
trajectory_columns scene_columns(const check_job& job, const csv_rows& rows) {
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

// Pass 1: the columns, and every row validated with its time in tau (the values are not held).
template <scalar T>
struct trajectory_times {
  trajectory_columns cols;
  std::vector<T> tau;
};

template <scalar T>
trajectory_times<T> read_times(const check_job& job) {
  std::ifstream in = open_input_file("trajectory", job.trajectory_path);
  csv_rows rows(in, "trajectory " + job.trajectory_path);
  trajectory_times<T> out{scene_columns(job, rows), {}};
  const compared_variables<T> vars = variables_of<T>(job.scn, out.cols);
  row_reader reader{rows, out.cols};
  while (rows.next()) {
    out.tau.push_back(vars.tau_of(reader.time().template to_scalar<T>()));
    reader.values();
    if (out.cols.q) reader.attitude();
  }
  if (out.tau.empty()) throw input_error(fmt::format("{}: no data rows", rows.where()));
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

// Pass 2, during the integration: each row is read again as the reference at its time arrives.
// Pass 1 checked that the times increase, and their conversion to tau in T is monotone, so the
// reference is evaluated as its segments are accepted and none is kept (integrate_at would fall
// back to the dense output otherwise). A trajectory with q0..q3 has the scene's attitude
// integrated beside the rates (integrate_attitude_streaming); one without, the rates alone, as
// for a scene without an attitude.
template <scalar T>
check_result check_in(const check_job& job) {
  const trajectory_times<T> pass1 = read_times<T>(job);
  const trajectory_columns& cols = pass1.cols;
  const std::vector<T>& taus = pass1.tau;
  T tau_end = taus.back();
  if (!(tau_end > 0)) tau_end = T(1);  // a trajectory at tau = 0 only
  errors_writer out(job.errors_out);    // an unwritable path fails before the integration
  const compared_variables<T> vars = variables_of<T>(job.scn, cols);

  check_result r;
  r.time_name = cols.time_name;
  r.terms = terms_of(cols, job.scn.is_physical(), vars.physical());
  r.t.reference_attitude = job.scn.has_attitude();
  r.t.attitude = cols.q.has_value();
  r.scene = scene_terms_of(job.scn, cols);
  out.header(cols.time_name, false, r.t.attitude);
  std::ifstream in = open_input_file("trajectory", job.trajectory_path);
  csv_rows rows(in, "trajectory " + job.trajectory_path);
  if (cols.q)
    for (int k = 0; k < 4; ++k) r.q_columns[k] = rows.header()[(*cols.q)[k]];
  row_reader reader{rows, cols};
  const auto changed = [&] { return input_error(fmt::format("{}: the file changed while it was read", rows.where())); };
  // Row i of the trajectory against the reference there (q_ref: its attitude, if checked), with
  // the equations `motion` for the direction of motion, if they are the rates' own.
  const auto compare = [&](std::size_t i, const vec3<T>& Omega_ref, const quaternion<T>* q_ref, const auto* motion) {
    if (!rows.next()) throw changed();
    const decimal time = reader.time();
    if (vars.tau_of(time.template to_scalar<T>()) != taus[i]) throw changed();
    const row_states<T> states = vars.states(Omega_ref, vec3_of<T>(reader.values()));
    std::optional<attitude_pair<T>> q;
    if (q_ref) q = attitude_pair<T>{*q_ref, quaternion_of<T>(reader.attitude())};
    record<T>(job, r.t, out, rows.line(), time, states, vars, motion, taus[i], std::nullopt, q ? &*q : nullptr);
  };
  // A torque of the attitude: the rates' direction of motion needs q, so the split along and
  // across it is left out.
  const auto* no_motion = static_cast<const euler_problem<T>*>(nullptr);
  const reference_run ref =
      job.scn.couples_attitude()
          ? integrate_scene_attitude<T>(job.scn, tau_end, taus, job.settings, "reference",
                                        [&](std::size_t i, const vec3<T>& y, const quaternion<T>& q) {
                                          compare(i, y, cols.q ? &q : nullptr, no_motion);
                                        })
          : with_problem<T>(job.scn, [&](const auto& problem) {
              // The direction of motion is evaluated on a copy: the integrator's own evaluates the torque.
              const auto motion = problem;
              if (cols.q)
                return integrate_attitude_streaming<T>(
                    problem, body_rates_of<T>(job.scn), attitude_of<T>(job.scn), tau_end, taus, job.settings,
                    "reference",
                    [&](std::size_t i, const vec3<T>& y, const quaternion<T>& q) { compare(i, y, &q, &motion); });
              return integrate_at<T>(problem, tau_end, taus, job.settings, "reference",
                                     [&](std::size_t i, const vec3<T>& Omega_ref) {
                                       compare(i, Omega_ref, nullptr, &motion);
                                     });
            });
  if (rows.next()) throw changed();
  out.commit();
  describe_scene_reference(job, cols.time_name, r.t.last_time, static_cast<double>(tau_end), ref, r);
  return r;
}

}  // namespace

check_result check_against_scene(const check_job& job) {
  return with_scalar(job.precision, [&](auto zero) { return check_in<decltype(zero)>(job); });
}

}  // namespace eulervop::app
