// The body rates that turn the attitude (docs/attitude.md), from the integrator's state.
#pragma once

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/model/principal_axes.hpp>

namespace eulervop {

// Body rates per unit of the integrator's time, in the body's axes as the scene lists them, from
// the integrator's state y: omega = P^T (sqrt(A) Omega) and dt = dtau / (dtau/dt) for a body in
// the normalized form (Eqs. 2-4), omega = y itself in the direct form.
template <scalar T>
struct body_rates {
  bool identity = true;
  axis_permutation axes;
  vec3<T> scale{T(1), T(1), T(1)};  // sqrt(A_i) / (dtau/dt)

  static body_rates of(const physical_scaling<T>& s) {
    body_rates b;
    if (s.is_direct()) return b;
    b.identity = false;
    b.axes = s.axes();
    for (int i = 0; i < 3; ++i) b.scale[i] = s.sqrt_A()[i] / s.tau_rate();
    return b;
  }

  vec3<T> operator()(const vec3<T>& y) const {
    if (identity) return y;
    return axes.to_user(vec3<T>{y[0] * scale[0], y[1] * scale[1], y[2] * scale[2]});
  }
};

}  // namespace eulervop
