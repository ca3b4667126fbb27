// Shared by tests/test_adaptive_runge_kutta.cpp and tests/test_adaptive_runs.cpp: the
// least-squares slope of y on x, for checking that log(error) follows log(tolerance).
#pragma once

#include <cstddef>
#include <vector>

namespace slope_test {

inline double least_squares_slope(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    mx += x[i] / n;
    my += y[i] / n;
  }
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
  }
  return sxy / sxx;
}

}  // namespace slope_test
