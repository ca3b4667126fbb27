// The reference integrator's state on one segment: the iterate and everything derived from it
// at the nodes, per component i of the state and node j (arrays of one vector per component).
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/detail/picard_field.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

#include <mpfr.h>

namespace eulervop::detail {

template <class P>
struct picard_workspace {
  using T = typename P::value_type;
  static constexpr std::size_t D = P::dimension;
  using wide = std::array<std::vector<T>, D>;
  using narrow = std::array<std::vector<double>, D>;

  using field_type = field_of<P>;
  using traits = typename field_type::torque_traits_type;

  std::size_t n1;  // nodes per segment, N + 1
  field_type field;  // the equations of the run
  //   Yc     the iterate: increments X - x0 at the nodes, in T (X the state at the nodes)
  //   Yn     the Picard map hl S f(X) of the iterate, in T: the segment's values once converged
  //   F      f(X) in T (times hl in the double-double residual)
  wide F, Yc, Yn;
  //   Xd     X in double, where the correction linearizes f; Xl: X - Xd (MPFR), so X in
  //          double-double for the residual updates
  //   warm   the warm start's increments
  //   r      the residual hl S f(X) - Yc
  //   delta  the correction of Yc; Sg  S g when a correction settles the segment
  //   g      f(X + delta) - f(X) in a sweep (f(X) in the double residual)
  //   df_hi, df_lo  g in double-double, for the residual updates
  //   Ydd_hi, Ydd_lo  the iterate in double-double during the passes before the first residual
  //          in T, for a field whose right-hand side has a double-double form
  //   Fdd_hi, Fdd_lo  hl f(X) in double-double there
  narrow Xd, Xl, warm, r, delta, Sg, g, df_hi, df_lo, Ydd_hi, Ydd_lo, Fdd_hi, Fdd_lo;
  // One component at a time: F and S F split into double-double hi + lo.
  std::vector<double> F_hi, F_lo, Y_hi, Y_lo;
  // The node times, for a torque of time: in T and in double.
  std::vector<T> t;
  std::vector<double> t_d;
  // The torque's Jacobian at the nodes, for a torque of the state (in double); the whole
  // Jacobian for the coupled problem.
  std::vector<typename field_type::node_jacobian> torque_J;
  T acc;  // accumulator in T: in place, no temporary per operation for MPFR
  std::array<T, D> node_x, node_f;  // the state and f at one node, reused (no allocation per node)

  explicit picard_workspace(std::size_t nodes) : n1(nodes) {
    for (auto* set : {&F, &Yc, &Yn})
      for (auto& v : *set) v.resize(n1);
    for (auto* set : {&Xd, &Xl, &warm, &r, &delta, &Sg, &g, &df_hi, &df_lo, &Ydd_hi, &Ydd_lo, &Fdd_hi, &Fdd_lo})
      for (auto& v : *set) v.resize(n1);
    for (auto* v : {&F_hi, &F_lo, &Y_hi, &Y_lo}) v->resize(n1);
    if constexpr (traits::depends_on_time) {
      t.resize(n1);
      t_d.resize(n1);
    }
    if constexpr (traits::depends_on_state) torque_J.resize(n1);
    acc = T(0);
  }

  // x += d, in place (for MPFR without a temporary, which would allocate). In quad, d enters
  // through its bit pattern (exact_binary128).
  static void add_double(T& x, double d) {
    if constexpr (std::is_same_v<T, mpfr_real>)
      mpfr_add_d(x.backend().data(), x.backend().data(), d, MPFR_RNDN);
    else if constexpr (std::is_same_v<T, quad>)
      x.backend().value() += exact_binary128(d);
    else
      x += d;
  }
  // d in binary128, exactly: a normal double's sign, exponent rebiased (1023 to 16383) and its 52
  // fraction bits at the top of the 112; zeros, subnormals, infinities and NaNs by the compiler's
  // conversion. The same value as that conversion (libgcc's __extenddftf2, about 3% of a quad
  // run through the corrections' additions), with a few integer operations.
  static __float128 exact_binary128(double d) {
    std::uint64_t b;
    std::memcpy(&b, &d, sizeof b);
    const std::uint64_t e = (b >> 52) & 0x7ff;
    if (e == 0 || e == 0x7ff) return static_cast<__float128>(d);
    using u128 = unsigned __int128;
    const u128 bits = (static_cast<u128>(b >> 63) << 127) | (static_cast<u128>(e + (16383 - 1023)) << 112) |
                      (static_cast<u128>(b & ((std::uint64_t{1} << 52) - 1)) << 60);
    __float128 out;
    std::memcpy(&out, &bits, sizeof out);
    return out;
  }
  // The time of node j (a torque of time), or the start for a torque without one.
  const T& time_of(std::size_t j) const {
    if constexpr (traits::depends_on_time) return t[j];
    else return field.problem().tau0;
  }
  double time_d_of(std::size_t j) const {
    if constexpr (traits::depends_on_time) return t_d[j];
    else return 0.0;
  }
};

}  // namespace eulervop::detail
