// What the comparison runs need of a problem's torque (model/torque.hpp): its breakpoints in the
// span and the pinning of the interval a step works in, and a bound of its size for the
// explosion test. A constant torque has no breakpoints, and its size is its norm.
//
// A torque given by formulas keeps scratch space for its evaluation and its pinned interval, so
// a run evaluates and pins only its own copy of the problem: sweep and map run many runs of one
// problem at once, on several threads.
#pragma once

#include <eulervop/core/vec3.hpp>
#include <eulervop/model/torque.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace eulervop::detail {

// The torque's breakpoints strictly inside (t0, t_end), increasing; none for a torque without.
template <class Problem>
std::vector<double> breakpoints_between(const Problem& p, double t0, double t_end) {
  std::vector<double> out;
  if constexpr (piecewise_torque<typename Problem::torque_type>)
    for (const double b : p.torque.breakpoints())
      if (b > t0 && b < t_end) out.push_back(b);
  return out;
}

// Pins the torque's interval that contains t (a step's start; no step crosses a breakpoint), in
// the run's own copy of the problem.
template <class Problem>
void pin_torque_at(const Problem& p, double t) {
  if constexpr (piecewise_torque<typename Problem::torque_type>) p.torque.pin(p.torque.interval_at(t));
}

// The largest |g_i| the explosion bound assumes (divergence.hpp): the constant torque itself, or
// for a torque of time and state the largest of its components at the initial state over 257
// times spread over the span (a torque that grows far beyond that makes the bound loose, never
// wrong: a run is declared exploded only a thousand times beyond it).
template <class Problem>
vec3<double> torque_size(const Problem& p, double t_end) {
  const vec3<double>& y0 = p.initial_state();
  const double t0 = p.initial_time();
  if constexpr (is_constant_torque_v<typename Problem::torque_type>) {
    return p.torque.value(t0, y0);
  } else {
    const typename Problem::torque_type g_own = p.torque;  // this thread's copy
    vec3<double> size{0, 0, 0};
    constexpr int n = 256;
    for (int k = 0; k <= n; ++k) {
      const double t = t0 + (t_end - t0) * k / n;
      const vec3<double> g = g_own.value(t, y0);
      for (int i = 0; i < 3; ++i) size[i] = std::max(size[i], std::abs(g[i]));
    }
    return size;
  }
}

}  // namespace eulervop::detail
