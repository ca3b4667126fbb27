// The polynomial P of one segment of the reference, in the forms the certificate uses
// (docs/certified.md, "How"): its exact node values, its Chebyshev coefficients enclosed in
// intervals, and those coefficients as doubles with a bound of their distance (for the parts
// computed in double, bounded_chebyshev.hpp).
//
// On [a, a + 2 hl], P(tau) = X0 + q(s), s = (tau - a) / hl - 1, where X0 is the segment's base (the
// exact sum of its two stored parts) and q the interpolant of the stored increments at the
// Lobatto nodes (node_transform.hpp).
#pragma once

#include <eulervop/certify/detail/bounded_chebyshev.hpp>
#include <eulervop/certify/detail/grid_integer.hpp>
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
#include <limits>
#include <stdexcept>
#include <vector>

namespace eulervop::detail {

struct segment_polynomial {
  segment_polynomial(mpfr_prec_t bits, std::size_t degree);

  // a, hl and h = 2 hl of `seg`, exactly.
  template <scalar T>
  void place(const chebyshev_segment<T>& seg);
  // X0, vmid, v_first and v_last of `seg`, exactly (fails on a value that is not finite).
  template <scalar T>
  void load(const chebyshev_segment<T>& seg);
  // p from v; the doubles; psup; the grid.
  void enclose(node_transform& transform);

  // Stops the certificate (numerical_failure, certification_failed) at this segment's start.
  [[noreturn]] void fail(outcome_kind cause, double value = 0) const;

  mpfr_prec_t bits;
  std::size_t N, n1;
  interval a, hl, h;
  std::vector<interval> X0;            // the base (3)
  std::vector<real> vmid;              // the node values (3 x n1, component-major), exact
  vec3<interval> v_first, v_last;      // those at the segment's start and end
  // The coefficients of P (3 x n1, component-major): those of q, with X0 added to the first; and
  // the sums of q's coefficients' widths per component (64 bits, rounded up).
  std::vector<interval> p;
  std::vector<real> c_width;
  vec3<interval> psup;          // sup |P_i| <= sum_k |p_ik|
  // P's coefficients as doubles (cd), each with a bound of its distance to the exact one (crad)
  // and of its magnitude (cmag); prad per component >= sum_k crad. tail_level separates the
  // products that the residual computes in double.
  std::vector<double> cd, crad, cmag;
  std::array<double, 3> prad{};
  double tail_level = 0;
  // Component c without its coefficients below 2^-50 of the largest of P (a view whose radius
  // takes their magnitudes), for the products of the linear parts (bounded_chebyshev.hpp), whose
  // own residuals stand far above that.
  series_view short_view(int c) const { return {&cd[c * n1], short_length[c], short_radius[c]}; }
  std::array<std::size_t, 3> short_length{};
  std::array<double, 3> short_radius{};

  // P's coefficients as integers: q_k = the left end of p_k's enclosure on the grid of step
  // 2^-shift (under the largest, `bits` bits deep; toward zero, less than a step away), on `limbs`
  // limbs as magnitudes and sign masks where they fit (on_limbs; grid_integer.hpp, limbs). Per
  // component, at 64 bits rounded up: abs >= sum |q_k| and rad >= sum |p_k - q_k| over p's
  // enclosures, each with n1 steps added.
  struct grid_form {
    long shift = 0;
    std::size_t limbs = 0;
    bool on_limbs = false;
    std::vector<mp_limb_t> q, negative;
    std::vector<real> abs, rad;
  } grid;

 private:
  void coefficient_doubles();
  void place_on_grid();

  interval t_;    // scratch
  real hi_;  // scratch at the working precision
};

inline segment_polynomial::segment_polynomial(mpfr_prec_t bits_, std::size_t degree)
    : bits(bits_), N(degree), n1(degree + 1), a(interval::zero(bits_)), hl(interval::zero(bits_)),
      h(interval::zero(bits_)), X0(3, interval::zero(bits_)), vmid(3 * n1, real(bits_)),
      v_first{interval::zero(bits_), interval::zero(bits_), interval::zero(bits_)},
      v_last{interval::zero(bits_), interval::zero(bits_), interval::zero(bits_)}, p(3 * n1, interval::zero(bits_)),
      c_width(3, real(64)),
      psup{interval::zero(bits_), interval::zero(bits_), interval::zero(bits_)}, cd(3 * n1, 0.0),
      crad(3 * n1, 0.0), cmag(3 * n1, 0.0), t_(interval::zero(bits_)), hi_(bits_) {
  grid.limbs = (static_cast<std::size_t>(bits_) + 64) / 64;
  if (grid.limbs <= 8) {
    grid.q.resize(3 * n1 * grid.limbs);
    grid.negative.resize(3 * n1);
  }
  grid.abs.assign(3, real(64));
  grid.rad.assign(3, real(64));
}

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
    if (!mpfi_bounded_p(X0[i].get())) fail(outcome_kind::certify_non_finite);
    for (std::size_t j = 0; j < n1; ++j)
      if (!set_exact(vmid[i * n1 + j].get(), seg.values[j][i])) fail(outcome_kind::certify_non_finite);
    mpfi_set_fr(v_first[i].get(), vmid[i * n1].get());
    mpfi_set_fr(v_last[i].get(), vmid[i * n1 + N].get());
  }
}

inline void segment_polynomial::enclose(node_transform& transform) {
  transform.apply(vmid, p, c_width);
  for (int i = 0; i < 3; ++i) mpfi_add(p[i * n1].get(), p[i * n1].get(), X0[i].get());
  coefficient_doubles();
  for (int i = 0; i < 3; ++i) {  // a point: the sum of the magnitudes (cmag) rounded up
    double sum = 0;
    for (std::size_t k = 0; k < n1; ++k) sum += cmag[i * n1 + k];
    mpfi_set_d(psup[i].get(), sum * (1 + 1e-12));
  }
  place_on_grid();
}

// |q_k| <= |left end| <= cmag_k; |p_k - q_k| < p_k's width + a step, the widths summed as q's
// (c_width) and p_0's own.
inline void segment_polynomial::place_on_grid() {
  grid.shift = detail::grid_shift(p, [](const interval& x) { return &x.get()->left; }, bits);
  grid.on_limbs = grid.limbs <= 8;  // |q| < 2^bits < 2^(64 limbs): fits
  for (std::size_t q = 0; grid.on_limbs && q < 3 * n1; ++q)
    grid.on_limbs = limbs::load_truncated(&p[q].get()->left, grid.shift, grid.limbs, &grid.q[q * grid.limbs],
                                          grid.negative[q]);
  real& steps = hi_;
  mpfr_set_ui_2exp(steps.get(), static_cast<unsigned long>(n1), -grid.shift, MPFR_RNDU);
  for (int i = 0; i < 3; ++i) {
    double sum = 0;
    for (std::size_t k = 0; k < n1; ++k) sum += cmag[i * n1 + k];
    mpfr_set_d(grid.abs[i].get(), sum * (1 + 1e-12), MPFR_RNDU);
    mpfr_add(grid.abs[i].get(), grid.abs[i].get(), steps.get(), MPFR_RNDU);
    mpfr_ptr rad = grid.rad[i].get();
    width_up(grid.rad[i], p[i * n1]);
    mpfr_add(rad, rad, c_width[i].get(), MPFR_RNDU);
    mpfr_add(rad, rad, steps.get(), MPFR_RNDU);
  }
}

inline void segment_polynomial::fail(outcome_kind cause, double value) const {
  outcome o;
  o.kind = outcome_kind::certification_failed;
  o.cause = cause;
  o.value = value;
  o.tau = mpfi_get_d(a.get());
  throw numerical_failure(o);
}

// Each d_k is p_k's right end rounded to nearest; crad_k adds p_k's width, bounded by the sum of
// the widths of q's coefficients (node_transform) for k >= 1 and computed for p_0 = c_0 + X0.
inline void segment_polynomial::coefficient_doubles() {
  const double eps = std::numeric_limits<double>::epsilon(), tiny = std::numeric_limits<double>::denorm_min();
  double scale = 0;
  for (int i = 0; i < 3; ++i) {
    const double width = mpfr_get_d(c_width[i].get(), MPFR_RNDU);
    for (std::size_t k = 0; k < n1; ++k) {
      const std::size_t q = i * n1 + k;
      double w = width;
      if (k == 0) {
        width_up(hi_, p[q]);
        w = mpfr_get_d(hi_.get(), MPFR_RNDU);
      }
      cd[q] = mpfr_get_d(&p[q].get()->right, MPFR_RNDN);
      crad[q] = (w + std::abs(cd[q]) * eps + tiny) * (1 + 1e-15);
      cmag[q] = (std::abs(cd[q]) + crad[q]) * (1 + 1e-15);
      scale = std::max(scale, cmag[q]);
    }
  }
  tail_level = std::ldexp(scale * scale, -static_cast<int>(bits - 64 + 40 - 53));
  if (!(tail_level > 1e-250)) tail_level = 0;  // deep MPFR levels: everything in intervals
  for (int i = 0; i < 3; ++i) {
    prad[i] = 0;
    for (std::size_t k = 0; k < n1; ++k) prad[i] += crad[i * n1 + k];
    prad[i] *= 1 + 1e-12;
    std::size_t n = n1;
    double dropped = 0;
    while (n > 1 && cmag[i * n1 + n - 1] < std::ldexp(scale, -50)) dropped += cmag[i * n1 + --n];
    short_length[i] = n;
    short_radius[i] = (prad[i] + dropped) * (1 + 1e-12);
  }
}

}  // namespace eulervop::detail
