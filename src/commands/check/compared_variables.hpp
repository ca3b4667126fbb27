// The variables `check` compares in: the trajectory's own. A trajectory with physical columns
// (t, omega1..3) of a physical scene is compared in rad/s, on the body's axes in the order the
// scene lists its moments, so that --tol, the errors and the metrics are in the user's terms. The
// normalized variables of Eq. 4 (tau, Omega, in the principal order), where Eq. 20 and Eq. 7 are
// stated, are kept beside them and reported apart.
#pragma once

#include "compute/scene_library.hpp"

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/model/physical_scaling.hpp>

#include <array>
#include <optional>
#include <string>

namespace eulervop::app {

// One row's state, the reference's and the trajectory's, in the compared variables and in the
// normalized ones (the same vectors when the trajectory's columns are tau and Omega).
template <scalar T>
struct row_states {
  vec3<T> reference, trajectory;
  vec3<T> reference_Omega, trajectory_Omega;
};

template <scalar T>
class compared_variables {
 public:
  // The trajectory's variables are the integrator's (tau and Omega; t and y; or t and omega of a
  // body in the direct form, where Omega = omega and tau = t).
  compared_variables() = default;
  // Physical columns of a physical scene: omega in rad/s and t in seconds.
  explicit compared_variables(const physical_scaling<T>& scale) : scale_(scale) {}

  // Whether the compared variables are the physical ones (rad/s) rather than the normalized.
  bool physical() const { return scale_.has_value() && !scale_->is_direct(); }

  // The time in the integrator's variables.
  T tau_of(const T& time) const { return scale_ ? scale_->tau_of_t(time) : time; }

  // A reference state in the integrator's variables, and a trajectory's as read: both ways.
  row_states<T> states(const vec3<T>& reference_Omega, const vec3<T>& trajectory) const {
    if (!physical()) return {reference_Omega, trajectory, reference_Omega, trajectory};
    return {scale_->omega_of_Omega(reference_Omega), trajectory, reference_Omega, scale_->Omega_of_omega(trajectory)};
  }
  // The same when the reference's compared state is known as well (a physical reference file's
  // omega columns), so that it is compared as printed.
  row_states<T> states(const vec3<T>& reference_Omega, const vec3<T>& reference, const vec3<T>& trajectory) const {
    if (!physical()) return states(reference_Omega, trajectory);
    return {reference, trajectory, reference_Omega, scale_->Omega_of_omega(trajectory)};
  }
  // A direction of motion in the integrator's variables, in the compared ones (the change of
  // variables is linear: Eq. 3 and the axes' order); a direction needs no more than double.
  vec3<double> direction(const vec3<double>& v_Omega) const {
    if (!physical()) return v_Omega;
    const vec3<T> w = scale_->omega_of_Omega(vec3<T>{T(v_Omega[0]), T(v_Omega[1]), T(v_Omega[2])});
    return {static_cast<double>(w[0]), static_cast<double>(w[1]), static_cast<double>(w[2])};
  }

 private:
  std::optional<physical_scaling<T>> scale_;
};

// What the compared variables are called and measured in, for the outputs.
struct compared_terms {
  std::array<std::string, 3> components = {"Omega1", "Omega2", "Omega3"};  // the trajectory's column names
  std::string time_unit;   // "s", or empty (tau, or a scene without units)
  std::string state_unit;  // "rad/s", or empty (Omega of Eq. 4, y of the coefficient form)
  bool normalized_apart = false;  // the Eq. 20 error in the normalized variables is reported too
};

}  // namespace eulervop::app
