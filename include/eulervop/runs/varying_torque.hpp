// The torques of time or state the runs integrate, as one torque type (model/torque.hpp) whose
// kind is data: a formula torque of time, one of time and state (model/expression_torque.hpp), a
// torque of the attitude shown each stage's q (model/staged_attitude_torque.hpp), or a torque
// type of the user's own behind one virtual call (detail/erased_torque.hpp).
//
// The double-precision runs (comparison_run.hpp) integrate every problem with such a torque as
// the problem under this one type, so each run driver is compiled once for all of them rather
// than once per torque type (docs/design.md, "The compiled kernels"). The kind is read at each
// evaluation; the evaluation itself is the kind's own, in the same order, so a run gives the
// same doubles as under the kind's own type. A constant torque is not one of them: its runs take
// the paper's fast paths (the torque read once per run, the VOP torque in its frame once).
#pragma once

#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/model/expression_torque.hpp>
#include <eulervop/model/staged_attitude_torque.hpp>
#include <eulervop/runs/detail/erased_torque.hpp>

#include <array>
#include <cstddef>
#include <utility>
#include <variant>
#include <vector>

namespace eulervop {

template <class T>
class varying_torque {
 public:
  static constexpr bool depends_on_time = true;
  static constexpr bool depends_on_state = true;
  using kinds = std::variant<time_torque<T>, state_torque<T>, staged_attitude_torque<T>, detail::erased_torque<T>>;

  varying_torque() = default;
  explicit varying_torque(kinds g) : g_(std::move(g)) {}

  const kinds& kind() const { return g_; }
  // A torque of the attitude (one with set_attitude): its runs must carry q.
  bool reads_attitude() const {
    if (const auto* g = std::get_if<detail::erased_torque<T>>(&g_)) return g->reads_attitude();
    return std::holds_alternative<staged_attitude_torque<T>>(g_);
  }
  // The attitude of the stage about to be evaluated (a no-op for the formula kinds).
  void set_attitude(const quaternion<T>& q) const {
    if (const auto* g = std::get_if<staged_attitude_torque<T>>(&g_)) g->set_attitude(q);
    else if (const auto* e = std::get_if<detail::erased_torque<T>>(&g_)) e->set_attitude(q);
  }

  const std::vector<T>& breakpoints() const {
    return std::visit([](const auto& g) -> const std::vector<T>& { return g.breakpoints(); }, g_);
  }
  std::size_t interval_at(const T& t) const {
    return std::visit([&](const auto& g) { return g.interval_at(t); }, g_);
  }
  void pin(std::size_t interval) const {
    std::visit([&](const auto& g) { g.pin(interval); }, g_);
  }
  void unpin() const {
    std::visit([](const auto& g) { g.unpin(); }, g_);
  }

  // Out of line: one copy of each kind's evaluation per driver, however many stages call it
  // (the evaluation of a formula is itself a call to the compiled program).
  [[gnu::noinline]] vec3<T> value(const T& t, const vec3<T>& y) const {
    return std::visit([&](const auto& g) -> vec3<T> { return g.value(t, y); }, g_);
  }

  void add_jacobian(const T& t, const vec3<T>& y, std::array<vec3<T>, 3>& J) const {
    std::visit(
        [&](const auto& g) {
          if constexpr (requires { g.add_jacobian(t, y, J); }) g.add_jacobian(t, y, J);
        },
        g_);
  }

 private:
  kinds g_;
};

template <class U, class T>
varying_torque<U> convert_torque(const varying_torque<T>& g) {
  return varying_torque<U>(
      std::visit([](const auto& k) { return typename varying_torque<U>::kinds(convert_torque<U>(k)); }, g.kind()));
}

}  // namespace eulervop
