// The error norm of the adaptive runs (HNW I, II.4, Eq. 4.11): err = sqrt(mean_i (e_i / sc_i)^2),
// with the default scale sc_i = atol + rtol max(|x0_i|, |x1_i|) (hairer_scale); callers measure
// other quantities by passing their own scale (the VOP runs weight the phase,
// runs/detail/vop_adaptive_run.hpp).
// HNW I = E. Hairer, S. P. Norsett, G. Wanner, Solving Ordinary Differential Equations I, 2nd ed.
#pragma once

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/rk/state_traits.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace eulervop::rk {

// sc_i = atol + rtol max(|x0_i|, |x1_i|) (HNW I, Eq. II.4.10).
template <scalar T>
struct hairer_scale {
  T atol, rtol;
  template <class State>
  void operator()(const State& x0, const State& x1, State& sc) const {
    using std::abs;
    using std::max;
    state_traits<State>::for_each_index(x0, [&](auto i) __attribute__((always_inline)) {
      auto& s = state_traits<State>::get(sc, i);
      s = max(abs(state_traits<State>::get(x0, i)), abs(state_traits<State>::get(x1, i)));
      s *= rtol;
      s += atol;
    });
  }
};

// sqrt(mean_i (e_i / sc_i)^2) in double (the controller needs no more).
template <class State>
double rms_norm(const State& e, const State& sc) {
  double sum = 0;
  std::size_t n = 0;
  state_traits<State>::for_each_index(e, [&](auto i) __attribute__((always_inline)) {
    const double r = static_cast<double>(state_traits<State>::get(e, i)) /
                     static_cast<double>(state_traits<State>::get(sc, i));
    sum += r * r;
    ++n;
  });
  return std::sqrt(sum / static_cast<double>(n));
}

}  // namespace eulervop::rk
