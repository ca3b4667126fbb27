// One embedded Runge-Kutta pair (embedded_pairs.hpp), attempt by attempt: the stages (the stage
// loop of detail/stage_loop.hpp, from k_1 kept between steps), the compensated new state, and the
// error norm (error_norm.hpp) of the embedded estimate. Acceptance and the step size belong to
// the caller (adaptive_driver.hpp, runs/detail/vop_adaptive_run.hpp).
//
// Every estimate is formed as h sum_j e_j (k_j - k_1) with sum_j e_j = 0, so it is exactly zero
// when all stages agree (a constant derivative, as for torque-free VOP elements): such a step is
// exact and the controller then takes the largest step allowed.
#pragma once

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/rk/detail/compensated_sum.hpp>
#include <eulervop/rk/detail/stage_loop.hpp>
#include <eulervop/rk/error_norm.hpp>
#include <eulervop/rk/initial_step.hpp>
#include <eulervop/rk/state_traits.hpp>
#include <eulervop/rk/tableaux.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <type_traits>
#include <utility>

namespace eulervop::rk {

// One embedded pair, attempt by attempt. The caller owns acceptance:
//   prime(sys, x, t)                       k_1 = f(t, x) (at the start, and after x changed other
//                                          than by an accepted step)
//   attempt(sys, x, t, h, out, comp, comp_out, scale)
//                                          out = x + increment (compensated: comp -> comp_out);
//                                          returns the error norm (NaN if a stage was not finite)
//   accept(sys, out, t + h)                FSAL: k_1 of the next step
// For MPFR, construct it inside the run's mpfr_precision_scope.
//
// Measure says which part of the state the error norm and the starting step see: the whole state
// (whole_state), or a leading part that the rest never feeds (runs/detail/attitude.hpp: the rates
// with the attitude beside them), so that the steps are those of that part alone.
struct whole_state {
  template <class State>
  static const State& part(const State& x) { return x; }
  template <class System>
  static System& system(System& sys) { return sys; }
};

template <class Pair, class State, scalar T = state_value_t<State>, class Measure = whole_state>
class embedded_rk {
  using Part = std::decay_t<decltype(Measure::part(std::declval<const State&>()))>;

 public:
  using pair_type = Pair;
  static constexpr std::size_t stages = Pair::stages;

  explicit embedded_rk(const State& shape = State{})
      : tab_(Pair::template coefficients<T>()),
        e_(Pair::template error_weights<T>()),
        work_(shape),
        k1_(shape),
        k_last_(shape),
        sc_(Measure::part(shape)),
        err_(shape),
        err2_(shape) {
    if constexpr (Pair::two_estimates) e2_ = Pair::template second_error_weights<T>();
  }

  std::size_t rhs_evaluations() const { return evals_; }

  template <class System>
  [[gnu::always_inline]] void prime(System& sys, const State& x, const T& t) {
    sys(x, k1_, t);
    ++evals_;
  }

  template <class System, class Scale>
  [[gnu::always_inline]] double attempt(System& sys, const State& x, const T& t, const T& h, State& out,
                                        const State& comp, State& comp_out, Scale&& scale) {
    if constexpr (detail::work_on_stack<State, T>) {
      work_type w;
      State err, err2;
      Part sc;
      return attempt_in(w, err, err2, sc, sys, x, t, h, out, comp, comp_out, scale);
    } else {
      return attempt_in(work_, err_, err2_, sc_, sys, x, t, h, out, comp, comp_out, scale);
    }
  }

  template <class System>
  [[gnu::always_inline]] void accept(System& sys, const State& out, const T& t_new) {
    if constexpr (Pair::fsal && stages == 7) {
      // dp45: the 7th stage was f at x + h sum b_j k_j, the new state before compensation.
      k1_ = k_last_;
      (void)sys, (void)out, (void)t_new;
    } else {
      sys(out, k1_, t_new);
      ++evals_;
    }
  }

  // The derivative at the current state (valid after prime or accept).
  const State& derivative() const { return k1_; }

  // HNW's starting step (initial_step.hpp) from the primed state, in the norm of attempt.
  template <class System, class Scale>
  T starting_step(System& sys, const State& x, const T& t, const T& h_max, Scale& scale,
                  std::size_t& evals) const {
    auto&& part_system = Measure::system(sys);
    return initial_step<Pair>(part_system, Measure::part(x), t, Measure::part(k1_), h_max, scale, evals);
  }

 private:
  using work_type = detail::stage_work<State, T, stages>;

  template <class System, class Scale>
  [[gnu::always_inline]] double attempt_in(work_type& w, State& err, State& err2, Part& sc, System& sys,
                                           const State& x, const T& t, const T& h, State& out, const State& comp,
                                           State& comp_out, Scale& scale) {
    using traits = state_traits<State>;
    w.k[0] = k1_;
    detail::compute_stages<stages, Pair::nonzero, 1>(sys, tab_, x, t, h, w);
    evals_ += stages - 1;
    if constexpr (Pair::fsal && stages == 7) k_last_ = w.k[stages - 1];
    traits::for_each_index(x, [&](auto i) __attribute__((always_inline)) {
      detail::weighted_increment<stages, Pair::nonzero>(tab_.b, i, h, w, w.inc);
      detail::compensated_add(traits::get(x, i), w.inc, traits::get(comp, i), traits::get(comp_out, i),
                              traits::get(out, i), w.bb);
      error_sum(w, e_, i, h, traits::get(err, i));
      if constexpr (Pair::two_estimates) error_sum(w, e2_, i, h, traits::get(err2, i));
    });
    scale(Measure::part(x), Measure::part(out), sc);
    const double n1 = rms_norm(Measure::part(err), sc);
    if constexpr (Pair::two_estimates) {
      // dop853.f: err5^2 / sqrt(err5^2 + 0.01 err3^2) (0 when both vanish).
      const double n3 = rms_norm(Measure::part(err2), sc);
      const double den = std::sqrt(n1 * n1 + 0.01 * n3 * n3);
      return den > 0 ? n1 * n1 / den : (std::isnan(den) ? den : 0.0);
    } else {
      return n1;
    }
  }

  // y = h sum_{j>=2} e_j (k_j - k_1)[i]: zero when all stages agree, since sum_j e_j = 0.
  template <class Index>
  [[gnu::always_inline]] static void error_sum(work_type& w, const std::array<T, stages>& e, Index i, const T& h,
                                               T& y) {
    using traits = state_traits<State>;
    const T& k1 = traits::get(w.k[0], i);
    y = T(0);
    detail::static_for<1, stages>([&](auto j) __attribute__((always_inline)) {
      if constexpr (Pair::error_nonzero[j]) {
        w.dk = traits::get(w.k[j], i);
        w.dk -= k1;
        y += e[j] * w.dk;
      }
    });
    y *= h;
  }

  butcher_tableau<T, stages> tab_;
  std::array<T, stages> e_, e2_{};
  work_type work_;           // used only when the state cannot live on the stack
  State k1_, k_last_;        // the derivative at the current state; dp45's 7th stage
  Part sc_;                  // likewise
  State err_, err2_;
  std::size_t evals_ = 0;
};

}  // namespace eulervop::rk
