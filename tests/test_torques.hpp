// Torque types the tests share (model/torque.hpp's interface): each with convert_torque, found by
// argument-dependent lookup, for the reference's passes in double.
#pragma once

#include <eulervop/core/vec3.hpp>

#include <array>

namespace eulervop::test_torques {

// g = -D y: linear damping, a torque of the state alone.
template <class T>
struct damping_torque {
  static constexpr bool depends_on_time = false;
  static constexpr bool depends_on_state = true;
  T D;
  vec3<T> value(const T&, const vec3<T>& y) const { return {-D * y[0], -D * y[1], -D * y[2]}; }
  void add_jacobian(const T&, const vec3<T>&, std::array<vec3<T>, 3>& J) const {
    for (int i = 0; i < 3; ++i) J[i][i] -= D;
  }
};
template <class U, class T>
damping_torque<U> convert_torque(const damping_torque<T>& g) {
  return {static_cast<U>(g.D)};
}

}  // namespace eulervop::test_torques
