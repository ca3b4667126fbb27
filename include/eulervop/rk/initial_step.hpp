// The starting step of an adaptive run: HNW I, II.4, "Starting step size" (the "hinit" of
// dopri5/dop853), capped at h_max; when the trial Euler step leaves the derivative exactly
// unchanged (a constant derivative) it is h_max.
// HNW I = E. Hairer, S. P. Norsett, G. Wanner, Solving Ordinary Differential Equations I, 2nd ed.
#pragma once

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/rk/error_norm.hpp>
#include <eulervop/rk/state_traits.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace eulervop::rk {

// The starting step from (t0, x0), where the derivative is f0. Evaluates the system once more,
// counted in evals.
template <class Pair, class System, class State, scalar T, class Scale>
T initial_step(System& sys, const State& x0, const T& t0, const State& f0, const T& h_max, Scale& scale,
               std::size_t& evals) {
  using std::abs;
  using std::pow;
  State sc = x0, x1 = x0, f1 = f0, d = f0;
  scale(x0, x0, sc);
  const double d0 = rms_norm(x0, sc), d1 = rms_norm(f0, sc);
  T h0 = (d0 < 1e-5 || d1 < 1e-5) ? T(1e-6) : T(0.01 * d0 / d1);
  if (h0 > h_max) h0 = h_max;
  state_traits<State>::for_each_index(x0, [&](auto i) {
    state_traits<State>::get(x1, i) = state_traits<State>::get(x0, i) + h0 * state_traits<State>::get(f0, i);
  });
  sys(x1, f1, T(t0 + h0));
  ++evals;
  bool unchanged = true;
  state_traits<State>::for_each_index(x0, [&](auto i) {
    auto& di = state_traits<State>::get(d, i);
    di = state_traits<State>::get(f1, i) - state_traits<State>::get(f0, i);
    unchanged = unchanged && di == 0;
  });
  if (unchanged) return h_max;  // a constant derivative: every step is exact
  const double d2 = rms_norm(d, sc) / static_cast<double>(h0);
  const double dm = std::max(d1, d2);
  const double k = Pair::estimate_order + 1;
  T h1 = dm <= 1e-15 ? std::max(T(1e-6), T(h0 * 1e-3)) : T(std::pow(0.01 / dm, 1.0 / k));
  T h = std::min(T(100 * h0), h1);
  if (h > h_max) h = h_max;
  return h;
}

}  // namespace eulervop::rk
