// The polynomial P of one segment of the reference, in the forms the certificate uses
// (docs/certified.md, "How"): its exact node values, its Chebyshev coefficients enclosed in
// intervals, and those coefficients as doubles with a bound of their distance (for the parts
// computed in double, bounded_chebyshev.hpp).
//
// On [a, a + 2 hl], P(tau) = X0 + q(s), s = (tau - a) / hl - 1, where X0 is the segment's base (the
// exact sum of its two stored parts) and q the interpolant of the stored increments at the
// Lobatto nodes (node_transform.hpp).
#pragma once

#include <eulervop/certify/detail/node_transform.hpp>
#include <eulervop/certify/detail/real.hpp>
#include <eulervop/certify/interval.hpp>
#include <eulervop/core/numerical_failure.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/segment.hpp>

#include <mpfi.h>
#include <mpfr.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <vector>

namespace eulervop::detail {

struct segment_polynomial {
  segment_polynomial(mpfr_prec_t bits, std::size_t degree);

  // a, hl and h = 2 hl of `seg`, exactly.
  template <scalar T>
  void place(const chebyshev_segment<T>& seg);
  // X0, v (and vmid) of `seg`, exactly (fails on a value that is not finite).
  template <scalar T>
  void load(const chebyshev_segment<T>& seg);
  // c, p from v; psup; then the doubles.
  void enclose(node_transform& transform);

  // Stops the certificate (numerical_failure, certification_failed) at this segment's start.
  [[noreturn]] void fail(outcome_kind cause, double value = 0) const;

  mpfr_prec_t bits;
  std::size_t N, n1;
  interval a, hl, h;
  std::vector<interval> X0, v;  // the base (3); the node values (3 x n1, component-major)
  std::vector<real> vmid;       // the node values as MPFR numbers (exact)
  std::vector<interval> c, p;   // the coefficients of q, and of P (c with X0 added to c_0)
  vec3<interval> psup;          // sup |P_i| <= sum_k |p_ik|
  // P's coefficients as doubles (cd), each with a bound of its distance to the exact one (crad)
  // and of its magnitude (cmag); prad per component >= sum_k crad. tail_level separates the
  // products that the residual computes in double.
  std::vector<double> cd, crad, cmag;
  std::array<double, 3> prad{};
  double tail_level = 0;

 private:
  void coefficient_doubles();

  interval t_;    // scratch
  real lo_, hi_;  // scratch at the working precision
};

inline segment_polynomial::segment_polynomial(mpfr_prec_t bits_, std::size_t degree)
    : bits(bits_), N(degree), n1(degree + 1), a(interval::zero(bits_)), hl(interval::zero(bits_)),
      h(interval::zero(bits_)), X0(3, interval::zero(bits_)), v(3 * n1, interval::zero(bits_)),
      vmid(3 * n1, real(bits_)), c(3 * n1, interval::zero(bits_)), p(3 * n1, interval::zero(bits_)),
      psup{interval::zero(bits_), interval::zero(bits_), interval::zero(bits_)}, cd(3 * n1, 0.0),
      crad(3 * n1, 0.0), cmag(3 * n1, 0.0), t_(interval::zero(bits_)), lo_(bits_), hi_(bits_) {}

template <scalar T>
void segment_polynomial::place(const chebyshev_segment<T>& seg) {
  if (seg.values.size() != n1) throw std::invalid_argument("certifier: the segment's degree differs");
  set_exact(a, seg.tau_begin);
  set_exact(hl, seg.half_length);
  mpfi_mul_2si(h.get(), hl.get(), 1);
}

template <scalar T>
void segment_polynomial::load(const chebyshev_segment<T>& seg) {
  for (int i = 0; i < 3; ++i) {
    set_exact(X0[i], seg.base[i]);
    set_exact(t_, seg.base_lo[i]);
    mpfi_add(X0[i].get(), X0[i].get(), t_.get());
    for (std::size_t j = 0; j < n1; ++j) {
      set_exact(v[i * n1 + j], seg.values[j][i]);
      mpfi_get_left(vmid[i * n1 + j].get(), v[i * n1 + j].get());  // a point: exact
    }
  }
  for (const interval& x : v)
    if (!mpfi_bounded_p(x.get())) fail(outcome_kind::certify_non_finite);
}

inline void segment_polynomial::enclose(node_transform& transform) {
  transform.apply(vmid, c);
  for (std::size_t q = 0; q < 3 * n1; ++q) mpfi_set(p[q].get(), c[q].get());
  for (int i = 0; i < 3; ++i) mpfi_add(p[i * n1].get(), p[i * n1].get(), X0[i].get());
  for (int i = 0; i < 3; ++i) {  // a point: the sum of the magnitudes, rounded up
    mpfr_set_ui(lo_.get(), 0, MPFR_RNDU);
    for (std::size_t k = 0; k < n1; ++k) {
      mpfi_mag(hi_.get(), p[i * n1 + k].get());
      mpfr_add(lo_.get(), lo_.get(), hi_.get(), MPFR_RNDU);
    }
    mpfi_set_fr(psup[i].get(), lo_.get());
  }
  coefficient_doubles();
}

inline void segment_polynomial::fail(outcome_kind cause, double value) const {
  outcome o;
  o.kind = outcome_kind::certification_failed;
  o.cause = cause;
  o.value = value;
  o.tau = mpfi_get_d(a.get());
  throw numerical_failure(o);
}

inline void segment_polynomial::coefficient_doubles() {
  double scale = 0;
  for (std::size_t q = 0; q < 3 * n1; ++q) {
    cd[q] = to_double(p[q], crad[q], lo_, hi_);
    cmag[q] = (std::abs(cd[q]) + crad[q]) * (1 + 1e-15);
    scale = std::max(scale, cmag[q]);
  }
  tail_level = std::ldexp(scale * scale, -static_cast<int>(bits - 64 + 40 - 53));
  if (!(tail_level > 1e-250)) tail_level = 0;  // deep MPFR levels: everything in intervals
  for (int i = 0; i < 3; ++i) {
    prad[i] = 0;
    for (std::size_t k = 0; k < n1; ++k) prad[i] += crad[i * n1 + k];
    prad[i] *= 1 + 1e-12;
  }
}

}  // namespace eulervop::detail
