// One segment of the reference's dense output, and its evaluation anywhere inside it.
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/detail/fixed_point_matvec.hpp>

#include <array>
#include <cstddef>
#include <cstring>
#include <type_traits>
#include <vector>

namespace eulervop {

namespace detail {
// a == b and a > b as IEEE comparisons, which are false for NaN already. For quad these compare
// the __float128 values directly: Boost.Multiprecision's operators first test both sides for NaN,
// out of line unless the compiler happens to inline them, on every comparison of the node search.
template <scalar T>
bool equal_values(const T& a, const T& b) {
  if constexpr (std::is_same_v<T, quad>) return a.backend().value() == b.backend().value();
  else return a == b;
}
template <scalar T>
bool greater_value(const T& a, const T& b) {
  if constexpr (std::is_same_v<T, quad>) return a.backend().value() > b.backend().value();
  else return a > b;
}
}  // namespace detail

// y(tau) = base + (base_lo + p(s)), where p is the polynomial through the increments `values` at
// the Chebyshev-Lobatto nodes s_j = -cos(j pi/N) and s = (tau - tau_begin) / half_length - 1 in
// [-1, 1]. base_lo is the TwoSum compensation. D is the dimension of the state.
template <scalar T, std::size_t D = 3>
struct chebyshev_segment {
  using state = std::array<T, D>;
  T tau_begin, tau_end, half_length;
  state base, base_lo;
  std::vector<state> values;  // y(tau_j) - y(tau_begin) at the N+1 nodes
};

// y(tau) on one segment (tau in [seg.tau_begin, seg.tau_end]), from its node values: by
// barycentric Lagrange interpolation (second form) on the Lobatto nodes, with weights (-1)^j,
// halved at the ends: backward stable for these nodes (Higham 2004, Berrut & Trefethen 2004) and
// O(N) per call. At a node, and at the segment's start, the stored value is returned exactly.
// In quad the numerators and the denominator are exact integer sums rounded once.
template <scalar T, std::size_t D>
std::array<T, D> evaluate_segment(const chebyshev_segment<T, D>& seg, const std::vector<T>& nodes, const T& tau) {
  std::array<T, D> out;
  const std::size_t n1 = nodes.size();
  T s = (tau - seg.tau_begin) / seg.half_length - 1;
  if (detail::greater_value(s, T(1))) s = 1;
  auto at_node = [&](std::size_t j) {
    for (std::size_t i = 0; i < D; ++i) out[i] = seg.base[i] + (seg.base_lo[i] + seg.values[j][i]);
    return out;
  };
  if (detail::equal_values(tau, seg.tau_begin)) return at_node(0);  // the segment's start is known exactly
  if constexpr (std::is_same_v<T, quad>) {
    // The differences s - s_j first: one is zero exactly where s is that node (in IEEE
    // arithmetic x - y = 0 only for x = y, subnormals included), so they serve as the node
    // search, by their bit patterns, and then as the weights' divisors.
    std::vector<T> w(n1);
    for (std::size_t j = 0; j < n1; ++j) {
      w[j] = s - nodes[j];
      unsigned __int128 bits;
      std::memcpy(&bits, &w[j].backend().value(), sizeof bits);
      if ((bits << 1) == 0) return at_node(j);
    }
    for (std::size_t j = 0; j < n1; ++j) {
      w[j] = 1 / w[j];
      if (j % 2) w[j] = -w[j];
      if (j == 0 || j + 1 == n1) w[j] /= 2;
    }
    // The sums as exact integer sums of the weights' and values' images, each rounded once
    // (fixed_point_matvec.hpp): seven of a node's nine soft-float operations, and more accurate.
    std::array<T, D + 1> sums;
    detail::fixed_point_matrix<quad>::dots(w.data(), &seg.values[0][0], D, D, n1, sums.data());
    for (std::size_t i = 0; i < D; ++i) out[i] = seg.base[i] + (seg.base_lo[i] + sums[1 + i] / sums[0]);
    return out;
  }
  for (std::size_t j = 0; j < n1; ++j)
    if (detail::equal_values(s, nodes[j])) return at_node(j);
  T den = 0;
  std::array<T, D> num;
  num.fill(T(0));
  for (std::size_t j = 0; j < n1; ++j) {
    T w = 1 / (s - nodes[j]);
    if (j % 2) w = -w;
    if (j == 0 || j + 1 == n1) w /= 2;
    den += w;
    for (std::size_t i = 0; i < D; ++i) num[i] += w * seg.values[j][i];
  }
  for (std::size_t i = 0; i < D; ++i) out[i] = seg.base[i] + (seg.base_lo[i] + num[i] / den);
  return out;
}

}  // namespace eulervop
