// The stage loop of an explicit Runge-Kutta step, shared by the fixed-step stepper
// (explicit_rk.hpp) and the embedded one (embedded_rk.hpp): the stages, and the weighted
// increment of the new state.
//
// The loop is statically typed on the tableau, the state and the scalar, and unrolled over the
// stages at compile time: zero coefficients cost nothing (the tableau's sparsity), and for a
// trivially copyable state (std::array<double, 3>) the stage derivatives live on the stack, where
// the compiler keeps them in registers. No heap allocation (for MPFR, whose values allocate, the
// stage storage is made once, with the stepper) and no virtual call per step. Every function is
// force-inlined: a call that is not inlined spills the registers of the whole step.
#pragma once

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/rk/state_traits.hpp>
#include <eulervop/rk/tableaux.hpp>

#include <array>
#include <cstddef>
#include <type_traits>
#include <utility>

namespace eulervop::rk::detail {

// Calls f(std::integral_constant<std::size_t, I>{}) for I = First, ..., Last - 1.
template <std::size_t First, std::size_t Last, class F>
[[gnu::always_inline]] constexpr void static_for(F&& f) {
  if constexpr (First < Last) {
    f(std::integral_constant<std::size_t, First>{});
    static_for<First + 1, Last>(f);
  }
}

// The first j < End with mask[j] set (End if none).
template <std::size_t S>
constexpr std::size_t first_set(const std::array<bool, S>& mask, std::size_t begin, std::size_t end) {
  for (std::size_t j = begin; j < end; ++j)
    if (mask[j]) return j;
  return end;
}

// Where one step keeps its stage derivatives and temporaries. A trivially copyable state and
// scalar (double, std::array<double, N>) gets a fresh work area on the stack for every step:
// the compiler then sees that nothing else can touch it and keeps it in registers. Other types
// (MPFR values allocate) use one kept for the stepper's lifetime.
template <class State, scalar T, std::size_t S>
struct stage_work {
  std::array<State, S> k;  // stage derivatives
  State tmp;               // stage input
  T ts{}, dk{}, inc{}, bb{};
  stage_work() = default;
  explicit stage_work(const State& shape) : tmp(shape) { k.fill(shape); }
};

template <class State, scalar T>
inline constexpr bool work_on_stack = std::is_trivially_copyable_v<State> && std::is_trivially_copyable_v<T>;

// k[0..S) at (t, x) for the tableau `tab` with non-zero pattern `nz`:
//   k_s = f(t + c_s h, x + h sum_{j<s} a_sj k_j),
// the sum in increasing j and formed in place (no MPFR temporary). Only stages From..S-1 are
// evaluated; k[0..From) must hold already (FSAL).
template <std::size_t S, const sparsity<S>& nz, std::size_t From = 0, class System, class State, scalar T>
[[gnu::always_inline]] inline void compute_stages(System& sys, const butcher_tableau<T, S>& tab, const State& x, const T& t, const T& h,
                    stage_work<State, T, S>& w) {
  using traits = state_traits<State>;
  if constexpr (From == 0) sys(x, w.k[0], t);
  static_for<(From > 1 ? From : 1), S>([&](auto s) __attribute__((always_inline)) {
    constexpr std::size_t first = first_set<S>(nz.a[s], 0, s);
    traits::for_each_index(x, [&](auto i) __attribute__((always_inline)) {
      auto& y = traits::get(w.tmp, i);
      if constexpr (first == s) {
        y = traits::get(x, i);
      } else {
        y = tab.a[s][first] * traits::get(w.k[first], i);
        static_for<first + 1, s>([&](auto j) __attribute__((always_inline)) {
          if constexpr (nz.a[s][j]) y += tab.a[s][j] * traits::get(w.k[j], i);
        });
        y *= h;
        y += traits::get(x, i);
      }
    });
    w.ts = tab.c[s] * h;
    w.ts += t;
    sys(static_cast<const State&>(w.tmp), w.k[s], static_cast<const T&>(w.ts));
  });
}

// y = h sum_j b_j k_j[i], formed as h (k_1 + sum_{j>1} b_j (k_j - k_1)). The two are equal
// because sum_j b_j = 1 (consistency), but the second is exact when all stages agree: a
// constant derivative (torque-free VOP: u' = c2) then advances by exactly h k_1 instead of
// h k_1 (sum_j b_j rounded), which would drift systematically over 1e5 steps.
template <std::size_t S, const sparsity<S>& nz, class State, scalar T, class Index>
[[gnu::always_inline]] inline void weighted_increment(const std::array<T, S>& b, Index i, const T& h, stage_work<State, T, S>& w, T& y) {
  using traits = state_traits<State>;
  const T& k1 = traits::get(w.k[0], i);
  constexpr std::size_t first = first_set<S>(nz.b, 1, S);
  if constexpr (first == S) {
    y = k1;
  } else {
    w.dk = traits::get(w.k[first], i);
    w.dk -= k1;
    y = b[first] * w.dk;
    static_for<first + 1, S>([&](auto j) __attribute__((always_inline)) {
      if constexpr (nz.b[j]) {
        w.dk = traits::get(w.k[j], i);
        w.dk -= k1;
        y += b[j] * w.dk;
      }
    });
    y += k1;
  }
  y *= h;
}

}  // namespace eulervop::rk::detail
