// Small test systems of the Runge-Kutta tests with exact solutions, and Eq. 5 as the runs see it.
#pragma once

#include <eulervop/core/vec3.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/rk/problem_system.hpp>

#include <array>

namespace eulervop::rk_test {

// A state with named members instead of indexable storage, for the stepper's non-array path.
template <class T>
struct planar {
  T x, y;
};

// The rotation x1' = -x2, x2' = x1: from (1, 0) the exact solution is (cos t, sin t).
struct rotation {
  template <class T>
  void operator()(const std::array<T, 2>& x, std::array<T, 2>& dx, const T&) const {
    dx[0] = -x[1];
    dx[1] = x[0];
  }
  template <class T>
  void operator()(const planar<T>& x, planar<T>& dx, const T&) const {
    dx.x = -x.y;
    dx.y = x.x;
  }
};

// Eq. 5 with the constant torque G, through the adaptor of the runs (rk/problem_system.hpp).
template <class T>
rk::problem_system<euler_problem<T>> euler_system(const vec3<T>& G) {
  euler_problem<T> p;
  p.torque.G = G;
  return {p};
}

}  // namespace eulervop::rk_test
