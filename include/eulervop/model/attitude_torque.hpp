// A torque of the attitude: formulas of the time, the rates and q0..q3, plus the gravity gradient
// (gravity_gradient.hpp), g(t, y, q) in the integrator's variables (docs/attitude.md, "Torques of
// the attitude"). The rates then no longer evolve on their own: the rates and q are one problem
// of 7 states (coupled_problem.hpp).
//
// Both terms are formed in the scene's variables (N m in the listed axes, at the scene's time)
// and their sum is mapped to the integrator's as every formula torque is (expression_torque.hpp).
#pragma once

#include <eulervop/core/vec3.hpp>
#include <eulervop/model/expression_torque.hpp>
#include <eulervop/model/gravity_gradient.hpp>

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

namespace eulervop {

template <class T>
class attitude_torque {
 public:
  static constexpr bool depends_on_time = true;
  static constexpr bool depends_on_state = true;
  using attitude_values = std::array<T, 4>;
  // d g_i / d (y_1, y_2, y_3, q_0, ..., q_3).
  using jacobian_rows = std::array<std::array<T, 7>, 3>;

  attitude_torque() = default;
  // `law`: the formulas (numbers for a constant torque); `gravity`: the gravity gradient, if any,
  // in the scene's variables.
  attitude_torque(std::shared_ptr<const torque_law> law, const torque_variables<T>& vars,
                  std::optional<gravity_gradient<T>> gravity)
      : formulas_(std::move(law), vars), gravity_(std::move(gravity)) {}

  const expression_torque<T, true>& formulas() const { return formulas_; }
  const std::optional<gravity_gradient<T>>& gravity() const { return gravity_; }

  const std::vector<T>& breakpoints() const { return formulas_.breakpoints(); }
  std::size_t interval_at(const T& t) const { return formulas_.interval_at(t); }
  void pin(std::size_t interval) const { formulas_.pin(interval); }
  void unpin() const { formulas_.unpin(); }

  // g at the integrator's time t, state y and attitude q.
  vec3<T> value(const T& t, const vec3<T>& y, const attitude_values& q) const {
    const T ts = formulas_.scene_time(t);
    vec3<T> m = formulas_.scene_torque(t, ts, formulas_.scene_state(y), &q);
    if (gravity_) {
      const vec3<T> gg = gravity_->value(ts, q);
      for (int i = 0; i < 3; ++i) m[i] += gg[i];
    }
    return formulas_.integrator_torque(m);
  }

  // J[i][k] += d g_i / d (y, q)_k.
  void add_jacobian(const T& t, const vec3<T>& y, const attitude_values& q, jacobian_rows& J) const {
    const T ts = formulas_.scene_time(t);
    std::array<std::array<T, 7>, 3> Js;
    formulas_.scene_jacobian(t, ts, formulas_.scene_state(y), &q, Js);
    if (gravity_) {
      std::array<std::array<T, 4>, 3> dM;
      gravity_->value(ts, q, &dM);
      for (int i = 0; i < 3; ++i)
        for (int m = 0; m < 4; ++m) Js[i][3 + m] += dM[i][m];
    }
    formulas_.add_mapped_jacobian(Js, J, 7);
  }

 private:
  expression_torque<T, true> formulas_;
  std::optional<gravity_gradient<T>> gravity_;
};

// The same torque in U (the reference's double passes).
template <class U, class T>
attitude_torque<U> convert_torque(const attitude_torque<T>& g) {
  std::optional<gravity_gradient<U>> gravity;
  if (g.gravity()) gravity = g.gravity()->template to<U>();
  return attitude_torque<U>(g.formulas().law(), g.formulas().variables().template to<U>(), gravity);
}

}  // namespace eulervop
