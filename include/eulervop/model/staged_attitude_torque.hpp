// A torque of the attitude (attitude_torque.hpp) as a torque of the time and the rates alone
// (torque.hpp), at an attitude shown to it from outside: the double-precision comparison runs
// step q on the same Runge-Kutta stages as the rates, and every stage shows the torque its own q
// before it evaluates it (runs/detail/attitude.hpp, docs/attitude-runs.md). The coupled problem
// is thereby what each run's method integrates on all seven components.
//
// Only runs that carry q can use it (its set_attitude says so: runs/varying_torque.hpp,
// reads_attitude): without q the torque would stay at the initial attitude.
#pragma once

#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/model/attitude_torque.hpp>

#include <array>
#include <cstddef>
#include <vector>

namespace eulervop {

template <class T>
class staged_attitude_torque {
 public:
  static constexpr bool depends_on_time = true;
  static constexpr bool depends_on_state = true;

  staged_attitude_torque() = default;
  staged_attitude_torque(attitude_torque<T> g, const quaternion<T>& q0) : g_(std::move(g)) { set_attitude(q0); }

  const attitude_torque<T>& torque() const { return g_; }
  const std::array<T, 4>& attitude() const { return q_; }
  // The attitude of the stage about to be evaluated.
  void set_attitude(const quaternion<T>& q) const { q_ = {q.w, q.x, q.y, q.z}; }

  const std::vector<T>& breakpoints() const { return g_.breakpoints(); }
  std::size_t interval_at(const T& t) const { return g_.interval_at(t); }
  void pin(std::size_t interval) const { g_.pin(interval); }
  void unpin() const { g_.unpin(); }

  vec3<T> value(const T& t, const vec3<T>& y) const { return g_.value(t, y, q_); }

  // J[i][k] += d g_i / d y_k at the shown attitude.
  void add_jacobian(const T& t, const vec3<T>& y, std::array<vec3<T>, 3>& J) const {
    typename attitude_torque<T>::jacobian_rows rows;
    for (auto& r : rows) r.fill(T(0));
    g_.add_jacobian(t, y, q_, rows);
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) J[i][k] += rows[i][k];
  }

 private:
  attitude_torque<T> g_;
  mutable std::array<T, 4> q_{T(1), T(0), T(0), T(0)};
};

template <class U, class T>
staged_attitude_torque<U> convert_torque(const staged_attitude_torque<T>& g) {
  const std::array<T, 4>& q = g.attitude();
  return staged_attitude_torque<U>(convert_torque<U>(g.torque()),
                                   quaternion<U>{static_cast<U>(q[0]), static_cast<U>(q[1]), static_cast<U>(q[2]),
                                                 static_cast<U>(q[3])});
}

}  // namespace eulervop
