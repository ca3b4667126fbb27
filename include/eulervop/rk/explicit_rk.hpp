// One explicit Runge-Kutta method at a fixed step, in the manner of Boost.Odeint's steppers:
//   - system:  sys(const State& x, State& dxdt, const T& t)   (no return value used;
//              problem_system.hpp makes one of a problem);
//   - state:   a fixed-shape container of T (state_traits.hpp);
//   - tableau: a tag type of tableaux.hpp.
// The stages are the unrolled loop of detail/stage_loop.hpp; integrate_fixed (fixed_step.hpp)
// drives the stepper over a run, and dispatch_method (tableaux.hpp) picks the tableau at run
// time, once per run.
#pragma once

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/rk/detail/compensated_sum.hpp>
#include <eulervop/rk/detail/stage_loop.hpp>
#include <eulervop/rk/state_traits.hpp>
#include <eulervop/rk/tableaux.hpp>

#include <cstddef>
#include <string_view>
#include <utility>

namespace eulervop::rk {

// One explicit Runge-Kutta method, fixed step, generic over state, scalar and system.
// For MPFR, construct it inside the mpfr_precision_scope of the run: the coefficients and the
// stage storage take the thread's precision at construction.
template <class Tableau, class State, scalar T = state_value_t<State>>
class explicit_rk {
 public:
  using tableau_type = Tableau;
  using state_type = State;
  using value_type = T;
  static constexpr std::size_t stages = Tableau::stages;
  static constexpr int order = Tableau::order;
  static constexpr std::string_view name = Tableau::name;

  // `shape` only gives the stage storage its shape (it matters for resizable states).
  explicit explicit_rk(const State& shape = State{})
      : tab_(Tableau::template coefficients<T>()), work_(shape), out_(shape) {}

  const butcher_tableau<T, stages>& coefficients() const { return tab_; }

  // Right-hand-side evaluations since construction (= stages x steps).
  std::size_t rhs_evaluations() const { return evals_; }

  // out = one step of size h from (t, x). out must not alias x.
  template <class System>
  [[gnu::always_inline]] void do_step(System& sys, const State& x, const T& t, const T& h, State& out) {
    if constexpr (detail::work_on_stack<State, T>) {
      work_type w;
      step(w, sys, x, t, h, out, nullptr);
    } else {
      step(work_, sys, x, t, h, out, nullptr);
    }
  }

  // The same step with compensated summation of the state (detail/compensated_sum.hpp): `comp`
  // carries the rounding error of x + increment from step to step.
  template <class System>
  [[gnu::always_inline]] void do_step(System& sys, const State& x, const T& t, const T& h, State& out, State& comp) {
    if constexpr (detail::work_on_stack<State, T>) {
      work_type w;
      step(w, sys, x, t, h, out, &comp);
    } else {
      step(work_, sys, x, t, h, out, &comp);
    }
  }

  // In-place variant: x <- one step from (t, x). Uses an internal buffer.
  template <class System>
  void do_step(System& sys, State& x, const T& t, const T& h) {
    do_step(sys, static_cast<const State&>(x), t, h, out_);
    using std::swap;
    swap(x, out_);
  }

 private:
  using work_type = detail::stage_work<State, T, stages>;

  // The step in the work area w: the stages, then out = x + increment (compensated when comp
  // is given). Inlined into do_step so that a work area on the stack stays in registers.
  template <class System>
  [[gnu::always_inline]] void step(work_type& w, System& sys, const State& x, const T& t, const T& h, State& out,
                                   State* comp) {
    using traits = state_traits<State>;
    detail::compute_stages<stages, Tableau::nonzero>(sys, tab_, x, t, h, w);
    evals_ += stages;
    traits::for_each_index(x, [&](auto idx) __attribute__((always_inline)) {
      auto& y = traits::get(out, idx);
      if (comp) {
        detail::weighted_increment<stages, Tableau::nonzero>(tab_.b, idx, h, w, w.inc);
        auto& c = traits::get(*comp, idx);
        detail::compensated_add(traits::get(x, idx), w.inc, c, c, y, w.bb);
      } else {
        detail::weighted_increment<stages, Tableau::nonzero>(tab_.b, idx, h, w, y);
        y += traits::get(x, idx);
      }
    });
  }

  butcher_tableau<T, stages> tab_;
  work_type work_;  // used only when the state cannot live on the stack (see stage_work)
  State out_;
  std::size_t evals_ = 0;
};

}  // namespace eulervop::rk
