// How the Runge-Kutta steppers walk a state, and the checks a driver makes on one.
//
// A state is a fixed-shape container of T. Supported out of the box: anything indexable with
// size() and operator[] (std::array<T, N>, eulervop::vec3<T>, ...) and plain aggregates whose
// fields are all T (through Boost.PFR), e.g.
//   template <class T> struct planar { T x, y; };
// Other types: specialize eulervop::rk::state_traits<State>.
#pragma once

#include <eulervop/core/scalar_traits.hpp>

#include <boost/pfr.hpp>

#include <cmath>
#include <cstddef>
#include <type_traits>
#include <utility>

namespace eulervop::rk {

namespace detail {
template <class S>
concept indexable_state = requires(S& s, std::size_t i) {
  s.size();
  s[i];
};
}  // namespace detail

// How the stepper walks a state. for_each_index(s, f) calls f(i) for every component index i
// (a std::size_t, or a std::integral_constant for aggregates); get(s, i) returns a reference to
// that component. Specialize for other state types.
template <class State>
struct state_traits {
  template <class F>
  [[gnu::always_inline]] static void for_each_index(const State& s, F&& f) {
    if constexpr (detail::indexable_state<State>) {
      const std::size_t n = s.size();
      for (std::size_t i = 0; i < n; ++i) f(i);
    } else {
      static_assert(std::is_aggregate_v<State>,
                    "state must be indexable, an aggregate of scalars, or have a state_traits "
                    "specialization");
      [&]<std::size_t... I>(std::index_sequence<I...>) {
        (f(std::integral_constant<std::size_t, I>{}), ...);
      }(std::make_index_sequence<boost::pfr::tuple_size_v<State>>{});
    }
  }
  template <class S, class Index>
  static decltype(auto) get(S& s, Index i) {
    if constexpr (detail::indexable_state<State>) {
      return (s[i]);
    } else {
      return (boost::pfr::get<Index::value>(s));
    }
  }
};

namespace detail {
template <class State>
struct first_index {
  using type = std::conditional_t<indexable_state<State>, std::size_t,
                                  std::integral_constant<std::size_t, 0>>;
};
}  // namespace detail

// The scalar type of a state's components.
template <class State>
using state_value_t = std::remove_cvref_t<decltype(state_traits<State>::get(
    std::declval<State&>(), std::declval<typename detail::first_index<State>::type>()))>;

template <scalar T>
bool is_finite_value(const T& v) {
  using std::isfinite;
  return static_cast<bool>(isfinite(v));  // unqualified: ADL finds boost::multiprecision::isfinite
}

// True when every component is finite.
template <class State>
bool all_finite(const State& x) {
  bool ok = true;
  state_traits<State>::for_each_index(x, [&](auto i) __attribute__((always_inline)) {
    ok = ok && is_finite_value(state_traits<State>::get(x, i));
  });
  return ok;
}

namespace detail {
// True when some component lies outside [lo, hi]. NaN is never outside.
template <class State, scalar T>
bool outside_band(const State& x, const T& lo, const T& hi) {
  bool out = false;
  state_traits<State>::for_each_index(x, [&](auto i) __attribute__((always_inline)) {
    const auto& v = state_traits<State>::get(x, i);
    out = out || v > hi || v < lo;
  });
  return out;
}
}  // namespace detail

// True when some component has |x_i| > bound, i.e. the max-norm exceeds bound.
template <class State, scalar T>
bool exceeds_max_norm(const State& x, const T& bound) {
  const T lo = -bound;
  return detail::outside_band(x, lo, bound);
}

}  // namespace eulervop::rk
