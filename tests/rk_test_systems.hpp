// Small test systems of the Runge-Kutta tests with exact solutions.
#pragma once

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

}  // namespace eulervop::rk_test
