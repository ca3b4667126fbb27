// The error at a segment's start, e(a) = y(a) - P(a), kept as a parallelepiped B [x]: B a point
// matrix (doubles), x a box (docs/certified.md, "How", step 5; Lohner 1987, Nedialkov & Jackson
// 2001). Across a segment, e(b) lies in Phi B x + r(b) + u(b) + a ball; the new B is the Q of a
// QR factorisation of mid(Phi B) (columns by decreasing length times the box's width along them),
// its inverse enclosed from the computed Q. The signed r(b) + u(b) moves the box, only the ball
// widens it, so the bound grows like the flow's sensitivity, not like exp(int mu).
#pragma once

#include <eulervop/certify/detail/segment_polynomial.hpp>
#include <eulervop/certify/interval.hpp>

#include <mpfi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace eulervop::detail {

class lohner_box {
 public:
  // `bits`: the box's own precision. Its numbers are tiny errors, whose enclosures need only a
  // few digits; what cancels (the joins, r(b) and u(b)) arrives enclosed at the working precision.
  explicit lohner_box(mpfr_prec_t bits)
      : x_(3, interval::zero(bits)), Qinv_(9, interval::zero(bits)), A_(9, interval::zero(bits)),
        C_(9, interval::zero(bits)), local_(3, interval::zero(bits)), next_(3, interval::zero(bits)),
        t_(interval::zero(bits)), u_(interval::zero(bits)) {}

  // The first segment's: e(a) = Omega(0) - X0 - v_0, B = I.
  void start(const vec3<interval>& Omega0, const segment_polynomial& P);
  // A later segment's: the previous box plus the jump between the two polynomials at the join.
  void join(const std::vector<interval>& jump);
  // out = [0, an upper bound of |B x|_2 over the box].
  void norm(interval& out);
  // To the segment's end, e(b) in Phi1 B x + r1 + u1 + ball (`ball` = [-b, b]). Fails when the
  // box grows beyond 2^-20 of the state (sup |P_i| <= psup_i): of no use to anyone then.
  void step(const std::vector<interval>& Phi1, const std::vector<interval>& r1, const std::vector<interval>& u1,
            const interval& ball, const segment_polynomial& P);

 private:
  void orthogonal_factor(double Q[9]);
  void enclose_inverse(const double Q[9], const segment_polynomial& P);
  void propagate(const std::vector<interval>& r1, const std::vector<interval>& u1, const interval& ball);

  std::array<double, 9> B_{};
  std::vector<interval> x_, Qinv_;
  // Scratch: Phi1 B, Q^-1 Phi1 B, the local part, the next box.
  std::vector<interval> A_, C_, local_, next_;
  interval t_, u_;
};

inline void lohner_box::start(const vec3<interval>& Omega0, const segment_polynomial& P) {
  B_ = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  interval e = interval::zero(P.bits);  // the difference cancels: at P's bits, then rounded outward
  for (int i = 0; i < 3; ++i) {
    mpfi_sub(e.get(), Omega0[i].get(), P.X0[i].get());
    mpfi_sub(e.get(), e.get(), P.v_first[i].get());
    mpfi_set(x_[i].get(), e.get());
  }
}

inline void lohner_box::join(const std::vector<interval>& jump) {
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      mpfi_mul(t_.get(), Qinv_[i * 3 + k].get(), jump[k].get());
      mpfi_add(x_[i].get(), x_[i].get(), t_.get());
    }
}

inline void lohner_box::norm(interval& out) {
  mpfi_set_ui(out.get(), 0);
  for (int i = 0; i < 3; ++i) {
    mpfi_set_ui(u_.get(), 0);
    for (int k = 0; k < 3; ++k) {
      mpfi_mul_d(t_.get(), x_[k].get(), B_[i * 3 + k]);
      mpfi_add(u_.get(), u_.get(), t_.get());
    }
    mpfi_abs(u_.get(), u_.get());
    mpfi_sqr(u_.get(), u_.get());
    mpfi_add(out.get(), out.get(), u_.get());
  }
  mpfi_sqrt(out.get(), out.get());
  to_zero_hull(out);
}

inline void lohner_box::step(const std::vector<interval>& Phi1, const std::vector<interval>& r1,
                             const std::vector<interval>& u1, const interval& ball, const segment_polynomial& P) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      mpfi_set_ui(A_[i * 3 + j].get(), 0);
      for (int k = 0; k < 3; ++k) {
        mpfi_mul_d(t_.get(), Phi1[i * 3 + k].get(), B_[k * 3 + j]);
        mpfi_add(A_[i * 3 + j].get(), A_[i * 3 + j].get(), t_.get());
      }
    }
  double Q[9];
  orthogonal_factor(Q);
  enclose_inverse(Q, P);
  propagate(r1, u1, ball);
  for (int q = 0; q < 9; ++q) B_[q] = Q[q];
  interval& size_of = local_[0];  // free after propagate
  norm(size_of);
  const double size = magnitude_up(size_of);
  double state = 0;
  for (int i = 0; i < 3; ++i) state = std::max(state, magnitude_up(P.psup[i]));
  if (!(size <= std::ldexp(1.0, -20) * std::max(1.0, state)))
    P.fail(outcome_kind::certify_growth, size / std::max(1.0, state));
}

// Q from modified Gram-Schmidt on mid(A), columns by decreasing length times box width.
inline void lohner_box::orthogonal_factor(double Q[9]) {
  double Am[9];
  for (int q = 0; q < 9; ++q) Am[q] = mpfi_get_d(A_[q].get());
  std::array<int, 3> order = {0, 1, 2};
  double weight[3];
  for (int j = 0; j < 3; ++j) {
    const double len = std::hypot(Am[j], Am[3 + j], Am[6 + j]);
    // The width, not the magnitude: only the widths wrap (the centres move by the point part).
    weight[j] = len * (mpfr_get_d(&x_[j].get()->right, MPFR_RNDU) - mpfr_get_d(&x_[j].get()->left, MPFR_RNDD));
  }
  std::sort(order.begin(), order.end(), [&](int p, int q) { return weight[p] > weight[q]; });
  auto orthogonalize = [&](double v[3], int c) {
    for (int prev = 0; prev < c; ++prev) {
      const double d = v[0] * Q[prev] + v[1] * Q[3 + prev] + v[2] * Q[6 + prev];
      for (int i = 0; i < 3; ++i) v[i] -= d * Q[i * 3 + prev];
    }
  };
  for (int c = 0; c < 3; ++c) {
    double v[3] = {Am[order[c]], Am[3 + order[c]], Am[6 + order[c]]};
    orthogonalize(v, c);
    double len = std::hypot(v[0], v[1], v[2]);
    if (!(len > 0) || !std::isfinite(len)) {
      // A degenerate column (a zero box): any unit vector orthogonal to the previous ones.
      for (int e = 0; e < 3 && !(len > 1e-3); ++e) {
        v[0] = v[1] = v[2] = 0;
        v[e] = 1;
        orthogonalize(v, c);
        len = std::hypot(v[0], v[1], v[2]);
      }
    }
    for (int i = 0; i < 3; ++i) Q[i * 3 + c] = v[i] / len;
  }
}

// Q^-1 = (I + D)^-1 Q^T with D = Q^T Q - I: |Q^-1 - Q^T| <= delta/(1 - delta) |Q^T|_inf,
// delta = |D|_inf (enclosed).
inline void lohner_box::enclose_inverse(const double Q[9], const segment_polynomial& P) {
  interval& delta = local_[0];
  interval& row = local_[1];
  interval& product = local_[2];
  mpfi_set_ui(delta.get(), 0);
  for (int i = 0; i < 3; ++i) {
    mpfi_set_ui(row.get(), 0);
    for (int j = 0; j < 3; ++j) {
      mpfi_set_si(t_.get(), i == j ? -1 : 0);
      for (int k = 0; k < 3; ++k) {
        mpfi_set_d(product.get(), Q[k * 3 + i]);
        mpfi_mul_d(product.get(), product.get(), Q[k * 3 + j]);
        mpfi_add(t_.get(), t_.get(), product.get());
      }
      mpfi_abs(t_.get(), t_.get());
      mpfi_add(row.get(), row.get(), t_.get());
    }
    mpfi_union(delta.get(), delta.get(), row.get());  // its right end: the largest row sum
  }
  double qt_inf = 0;
  for (int i = 0; i < 3; ++i) qt_inf = std::max(qt_inf, std::abs(Q[i]) + std::abs(Q[3 + i]) + std::abs(Q[6 + i]));
  interval& slack = t_;
  interval& one = u_;
  mpfi_set_ui(one.get(), 1);
  mpfi_sub(one.get(), one.get(), delta.get());
  if (!(mpfi_is_strictly_pos(one.get()) > 0)) P.fail(outcome_kind::certify_non_finite);
  mpfi_div(slack.get(), delta.get(), one.get());
  mpfi_mul_d(slack.get(), slack.get(), qt_inf * (1 + 1e-15));
  to_symmetric_hull(slack, one);  // [-slack, slack]
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      mpfi_set_d(Qinv_[i * 3 + j].get(), Q[j * 3 + i]);
      mpfi_add(Qinv_[i * 3 + j].get(), Qinv_[i * 3 + j].get(), slack.get());
    }
}

// x' = (Q^-1 A) x + Q^-1 (r1 + u1 + ball).
inline void lohner_box::propagate(const std::vector<interval>& r1, const std::vector<interval>& u1,
                                  const interval& ball) {
  for (int i = 0; i < 3; ++i) {
    mpfi_add(local_[i].get(), r1[i].get(), u1[i].get());
    mpfi_add(local_[i].get(), local_[i].get(), ball.get());
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      mpfi_set_ui(C_[i * 3 + j].get(), 0);
      for (int k = 0; k < 3; ++k) {
        mpfi_mul(t_.get(), Qinv_[i * 3 + k].get(), A_[k * 3 + j].get());
        mpfi_add(C_[i * 3 + j].get(), C_[i * 3 + j].get(), t_.get());
      }
    }
  for (int i = 0; i < 3; ++i) {
    mpfi_set_ui(next_[i].get(), 0);
    for (int k = 0; k < 3; ++k) {
      mpfi_mul(t_.get(), C_[i * 3 + k].get(), x_[k].get());
      mpfi_add(next_[i].get(), next_[i].get(), t_.get());
      mpfi_mul(t_.get(), Qinv_[i * 3 + k].get(), local_[k].get());
      mpfi_add(next_[i].get(), next_[i].get(), t_.get());
    }
  }
  x_.swap(next_);
}

}  // namespace eulervop::detail
