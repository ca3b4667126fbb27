// A proven bound on the distance between the reference of Eq. 5 and the exact solution
// (docs/certified.md explains the method and what it assumes).
//
// The reference is a continuous-in-spirit piecewise polynomial P: on each segment, the degree-N
// interpolant of the stored node values (chebyshev_segment). Those values define P exactly, so
// everything below is a statement about a known polynomial, checked in interval arithmetic with
// outward rounding (MPFI) at a working precision above the reference's:
//
//   1. the Picard residual r(tau) = P(a) + int_a^tau f(P) - P(tau) of the segment is a polynomial
//      of degree 2N + 1 (f is quadratic); its Chebyshev coefficients are enclosed exactly, and
//      sup |r| <= sum |r_k| on the segment;
//   2. the error e = y - P obeys e(tau) = e(a) + r(tau) + int_a^tau (J e + N(e)), J = DN(P) and
//      N(e) the quadratic part of Eq. 5, |N(e)| <= |e|^2 / sqrt(3); a Gronwall argument gives an
//      a-priori bound R of |e| on the segment;
//   3. integrating by parts with the variational matrix Phi' = J Phi (Phi(a) = I),
//        e(b) = Phi(b, a) e(a) + r(b) + int_a^b Phi(b, s) [J(s) r(s) + N(e(s))] ds,
//      |Phi(b, s)| <= exp(mu (b - s)), mu = sup |P_2| the logarithmic norm of J;
//   4. Phi(b, a) is computed in double on Chebyshev nodes and enclosed by its own Picard residual,
//      bounded with a floating-point error analysis (its error only multiplies e(a), which is
//      ~1e-30, so double accuracy is far more than enough);
//   5. e(a) is kept as a parallelepiped B [x] and moved across segments by Lohner's QR method
//      (Lohner 1987; Nedialkov & Jackson 2001), so the bound grows like the flow's sensitivity
//      rather than like exp(int mu).
// A row inside a segment adds exp(mu (tau - a)) |e(a)|, the residual and the integral term, and
// the distance from the printed decimals to P(tau), all as upper bounds.
#pragma once

#include <eulervop/reference/integrate.hpp>
#include <eulervop/certify/detail/bounded_chebyshev.hpp>
#include <eulervop/reference/detail/chebyshev_basis.hpp>
#include <eulervop/certify/interval.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/core/numerical_failure.hpp>
#include <eulervop/core/scalar.hpp>

#include <mpfi.h>
#include <mpfr.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace eulervop {

// The problem of Eq. 5 as exact data: G and Omega(tau0 = 0) enclosed from the scene's decimals.
struct certified_problem {
  std::vector<detail::interval> G, Omega0;  // three intervals each
};

class certifier {
 public:
  // `bits`: the working precision (the reference's bits + 64 or more); `degree`: the reference's N.
  certifier(mpfr_prec_t bits, std::size_t degree, certified_problem problem);

  // Checks the next accepted segment of the reference (in order) and moves the error bound to
  // its end. Throws numerical_failure (certification_failed) where the bound cannot be proven.
  template <scalar T>
  void add_segment(const chebyshev_segment<T>& seg);

  // At tau in the latest segment: `error` = [0, e] with |y(tau) - P(tau)|_2 <= e, and P(tau)
  // enclosed; `state` = [0, Y] with |y| <= Y on the whole segment, and `rate` = [0, F] with
  // |y'| <= F wherever |y| <= 2 Y (for moving a bound along tau by a rounding's worth).
  struct enclosure {
    detail::interval error;
    std::vector<detail::interval> P;
    detail::interval state, rate;
  };
  template <scalar T>
  enclosure enclose(const T& tau) const;

  // An upper bound of |y(tau) - printed|_2 (Eq. 20's norm), for tau in the latest segment, the
  // row printed as the decimals `printed` (three texts). Also raises max_radius().
  template <scalar T>
  detail::interval row_radius(const T& tau, const std::array<std::string, 3>& printed);
  // The same from an enclosure at that tau.
  detail::interval row_radius(const enclosure& at, const std::array<std::string, 3>& printed);

  // The largest row radius so far (an upper bound: the interval's right end).
  const detail::interval& max_radius() const { return max_radius_; }

 private:
  using ivec = std::vector<detail::interval>;

  detail::interval make() const { return detail::interval(bits_); }
  ivec make_vec(std::size_t n) const { return ivec(n, make()); }
  [[noreturn]] void fail(outcome_kind cause, double value = 0) const;

  void validate_segment();         // steps 1-5 on the values in v_, a_, hl_
  void chebyshev_coefficients();   // v_ -> c_ (and P coefficients p_)
  void picard_residual();          // p_ -> r_, rsup_, r1_
  double to_double(const detail::interval& x, double& radius) const;
  void coefficient_doubles();      // p_ -> cd_, crad_, cmag_, tail_level_
  void doubles_of_polynomials();   // crad_ -> prad_; r_ -> rd_, rrad_
  void variational_matrix(double hl, double mu, double jmax, double h);  // Phi1_, eps_phi_
  void signed_integral_term(double hl, double mu, double jmax, double h);  // u1_, eps_u_
  void error_at_end(detail::interval& out, double supR, double mu, double h, double jmax) const;
  void lohner_step();              // B_, x_ to the segment's end
  void box_norm(detail::interval& out) const;  // [0, an upper bound of |B x|_2 over the box]

  mpfr_prec_t bits_;
  std::size_t N_, n1_;
  certified_problem problem_;
  ivec M_;           // (N+1)x(N+1): node values -> Chebyshev coefficients
  // The current segment
  detail::interval a_, hl_, h_;
  ivec X0_, v_, c_, p_, prod_, r_;
  ivec rsup_, psup_, r1_;
  detail::interval rsup2_, mu_, jmax_, R_, rho_a_, ell_, eps_phi_, max_radius_;
  ivec Phi1_;        // 3x3 enclosure of Phi_num(b)
  // The error at the segment's start: e(a) in B x, B a point matrix (doubles), x a box.
  std::array<double, 9> B_{};
  ivec x_, Qinv_;
  ivec prev_end_;    // P(b) of the previous segment, exactly
  detail::interval prev_b_;
  bool started_ = false;
  // Phi in double, on m+1 Lobatto nodes
  detail::chebyshev_basis<double> phi_basis_;
  std::vector<double> rd_, ud_;  // r and u_num as doubles, 3 x (2N+2) (P's are cd_)
  std::array<double, 3> prad_{}, rrad_{};  // bounds of sum |exact - double| per component
  detail::integrated_products product_sum_;
  ivec u1_;          // u_num(1), the signed integral term

  std::vector<double> cd_, crad_, cmag_, gd_;  // P's coefficients in double; double products
  double tail_level_ = 0;
  // Bounds at 64 bits, rounded up: the inexact products' total error per component, its image in
  // r ([-b, b]), and the pieces of the midpoint bounds.
  std::vector<detail::real> product_rem_, Pabs_, Prad_;
  ivec r_rem_;
  detail::real F_{64}, bound_scratch_{64}, transform_error_scale_{64}, product_error_scale_{64};
  // Midpoints at the working precision: node values, M, folded values, P and products.
  std::vector<detail::real> vmid_, Mmid_, fold_plus_, fold_minus_, pmid_, pmid_half_, outmid_;
  detail::real cmid_{64}, mid_scratch_{64};
  long r_scale_ = 0;  // r is 2^-r_scale_ times its doubles rd_
  ivec r_scaled_;

  detail::interval eps_u_;
  // scratch
  mutable ivec t_;
  mutable detail::real scratch_fr_{64}, scratch_lo_{64};  // at the working precision (constructor)
};

// ---- implementation ----------------------------------------------------------------------------

inline certifier::certifier(mpfr_prec_t bits, std::size_t degree, certified_problem problem)
    : bits_(bits), N_(degree), n1_(degree + 1), problem_(std::move(problem)), a_(bits), hl_(bits), h_(bits),
      rsup2_(bits), mu_(bits), jmax_(bits), R_(bits), rho_a_(bits), ell_(bits), eps_phi_(bits), max_radius_(bits),
      prev_b_(bits), phi_basis_(16), eps_u_(bits) {
  // a_k = (2/N) sum_j'' v_j T_k(s_j), ends halved, a_0 and a_N halved, with s_j = -cos(j pi/N):
  // T_k(s_j) = (-1)^k cos(k j pi / N), the angle reduced modulo 2N (exact integers).
  const std::size_t N = N_;
  ivec cosines = make_vec(2 * N);
  detail::interval pi = make();
  mpfi_const_pi(pi.get());
  for (std::size_t m = 0; m < 2 * N; ++m) {
    mpfi_mul_ui(cosines[m].get(), pi.get(), static_cast<unsigned long>(m));
    mpfi_div_ui(cosines[m].get(), cosines[m].get(), static_cast<unsigned long>(N));
    mpfi_cos(cosines[m].get(), cosines[m].get());
  }
  M_ = make_vec(n1_ * n1_);
  for (std::size_t k = 0; k < n1_; ++k)
    for (std::size_t j = 0; j < n1_; ++j) {
      detail::interval& w = M_[k * n1_ + j];
      mpfi_set(w.get(), cosines[(k * j) % (2 * N)].get());
      if (k % 2) mpfi_neg(w.get(), w.get());
      mpfi_mul_ui(w.get(), w.get(), 2);
      mpfi_div_ui(w.get(), w.get(), static_cast<unsigned long>(N));
      if (j == 0 || j == N) mpfi_mul_2si(w.get(), w.get(), -1);
      if (k == 0 || k == N) mpfi_mul_2si(w.get(), w.get(), -1);
    }
  X0_ = make_vec(3);
  v_ = make_vec(3 * n1_);
  c_ = make_vec(3 * n1_);
  p_ = make_vec(3 * n1_);
  prod_ = make_vec(3 * (2 * N + 1));
  r_ = make_vec(3 * (2 * N + 2));
  rsup_ = make_vec(3);
  psup_ = make_vec(3);
  r1_ = make_vec(3);
  Phi1_ = make_vec(9);
  x_ = make_vec(3);
  Qinv_ = make_vec(9);
  prev_end_ = make_vec(3);
  t_ = make_vec(4);
  rd_.assign(3 * (2 * N + 2), 0.0);
  const detail::real wide(bits), narrow(64);
  scratch_lo_ = wide;  // end points at the working precision: their difference is the width
  scratch_fr_ = wide;
  fold_plus_.assign(n1_ / 2, wide);
  fold_minus_.assign(n1_ / 2, wide);
  vmid_.assign(3 * n1_, wide);
  pmid_.assign(3 * n1_, wide);
  pmid_half_.assign(3 * n1_, wide);
  outmid_.assign(2 * N + 1, wide);
  cmid_ = wide;
  mid_scratch_ = wide;
  product_rem_.assign(3, narrow);
  Pabs_.assign(3, narrow);
  Prad_.assign(3, narrow);
  r_rem_ = make_vec(3);
  // M's midpoints, dM >= max |M - M^| (the widths), Mmax >= max |M^|.
  Mmid_.assign(n1_ * n1_, wide);
  detail::real dM(64), Mmax(64);
  for (std::size_t q = 0; q < n1_ * n1_; ++q) {
    mpfi_mid(Mmid_[q].get(), M_[q].get());
    mpfi_get_left(scratch_lo_.get(), M_[q].get());
    mpfi_get_right(scratch_fr_.get(), M_[q].get());
    mpfr_sub(scratch_fr_.get(), scratch_fr_.get(), scratch_lo_.get(), MPFR_RNDU);
    mpfr_max(dM.get(), dM.get(), scratch_fr_.get(), MPFR_RNDU);
    mpfr_abs(scratch_fr_.get(), Mmid_[q].get(), MPFR_RNDU);
    mpfr_max(Mmax.get(), Mmax.get(), scratch_fr_.get(), MPFR_RNDU);
  }
  // (1 + 2^-40) (dM + Mmax (n + 2) 2^-p (1 + 2^-20)), n = half + 1 terms; and (2N + 6) 2^-p (1 + 2^-20).
  mpfr_set_ui(transform_error_scale_.get(), static_cast<unsigned long>(n1_ / 2 + 3), MPFR_RNDU);
  mpfr_mul_2si(transform_error_scale_.get(), transform_error_scale_.get(), -static_cast<long>(bits), MPFR_RNDU);
  mpfr_mul_d(transform_error_scale_.get(), transform_error_scale_.get(), 1 + std::ldexp(1.0, -20), MPFR_RNDU);
  mpfr_mul(transform_error_scale_.get(), transform_error_scale_.get(), Mmax.get(), MPFR_RNDU);
  mpfr_add(transform_error_scale_.get(), transform_error_scale_.get(), dM.get(), MPFR_RNDU);
  mpfr_mul_d(transform_error_scale_.get(), transform_error_scale_.get(), 1 + std::ldexp(1.0, -40), MPFR_RNDU);
  mpfr_set_ui(product_error_scale_.get(), static_cast<unsigned long>(2 * N + 6), MPFR_RNDU);
  mpfr_mul_2si(product_error_scale_.get(), product_error_scale_.get(), -static_cast<long>(bits), MPFR_RNDU);
  mpfr_mul_d(product_error_scale_.get(), product_error_scale_.get(), 1 + std::ldexp(1.0, -20), MPFR_RNDU);
  cd_.assign(3 * n1_, 0.0);
  crad_.assign(3 * n1_, 0.0);
  cmag_.assign(3 * n1_, 0.0);
  gd_.assign(2 * N + 1, 0.0);
  u1_ = make_vec(3);
  r_scaled_ = make_vec(3 * (2 * N + 2));
}

inline void certifier::fail(outcome_kind cause, double value) const {
  outcome o;
  o.kind = outcome_kind::certification_failed;
  o.cause = cause;
  o.value = value;
  o.tau = mpfi_get_d(a_.get());
  throw numerical_failure(o);
}

template <scalar T>
void certifier::add_segment(const chebyshev_segment<T>& seg) {
  if (seg.values.size() != n1_) throw std::invalid_argument("certifier: the segment's degree differs");
  detail::set_exact(a_, seg.tau_begin);
  detail::set_exact(hl_, seg.half_length);
  mpfi_mul_2si(h_.get(), hl_.get(), 1);
  // The segment must start exactly where the previous one ended (a + 2 hl, exact at these bits).
  if (started_ && !detail::same_point(prev_b_, a_)) fail(outcome_kind::certify_segment_gap);
  for (int i = 0; i < 3; ++i) {
    detail::set_exact(X0_[i], seg.base[i]);
    detail::set_exact(t_[0], seg.base_lo[i]);
    mpfi_add(X0_[i].get(), X0_[i].get(), t_[0].get());
    for (std::size_t j = 0; j < n1_; ++j) {
      detail::set_exact(v_[i * n1_ + j], seg.values[j][i]);
      mpfi_get_left(vmid_[i * n1_ + j].get(), v_[i * n1_ + j].get());  // a point: exact
    }
  }
  for (const detail::interval& x : v_)
    if (!mpfi_bounded_p(x.get())) fail(outcome_kind::certify_non_finite);
  validate_segment();
}

// ---- one segment ---------------------------------------------------------------------------

inline void certifier::chebyshev_coefficients() {
  // The columns j and N - j of the transform differ by the factor (-1)^k (T_k(-s) =
  // (-1)^k T_k(s) and the nodes are symmetric), so the sums and differences of mirrored values
  // halve the products. The sums are done on midpoints, rounded to nearest at the working
  // precision p, and then widened by one bound E per component:
  //   |c_k - c^_k| <= sum_j |M_kj - M^_kj| |f_j| + |M^_kj| |f_j - f^_j| + gamma_n sum |M^_kj| |f^_j|
  //               <= F^ (1 + 2^-p) (dM + Mmax ((n + 2) 2^-p (1 + 2^-20))),
  // F^ = sum |f^_j| (Higham 2002, section 3.1, for the dot products); plain MPFR operations cost
  // less than half of interval ones.
  const std::size_t half = n1_ / 2;  // pairs j < half with N - j; N even leaves j = N/2 alone
  mpfr_ptr tmp = mid_scratch_.get();
  detail::interval widen = make();
  for (int i = 0; i < 3; ++i) {
    const detail::real* v = &vmid_[i * n1_];
    mpfr_set_ui(F_.get(), 0, MPFR_RNDU);
    for (std::size_t j = 0; j < half; ++j) {
      mpfr_add(fold_plus_[j].get(), v[j].get(), v[N_ - j].get(), MPFR_RNDN);
      mpfr_sub(fold_minus_[j].get(), v[j].get(), v[N_ - j].get(), MPFR_RNDN);
      detail::add_abs_up(F_, fold_plus_[j].get());
      detail::add_abs_up(F_, fold_minus_[j].get());
    }
    if (n1_ % 2) detail::add_abs_up(F_, v[half].get());
    for (std::size_t k = 0; k < n1_; ++k) {
      const std::vector<detail::real>& folded = (k % 2) ? fold_minus_ : fold_plus_;
      mpfr_ptr ck = cmid_.get();
      mpfr_set_ui(ck, 0, MPFR_RNDN);
      for (std::size_t j = 0; j < half; ++j) {
        mpfr_mul(tmp, Mmid_[k * n1_ + j].get(), folded[j].get(), MPFR_RNDN);
        mpfr_add(ck, ck, tmp, MPFR_RNDN);
      }
      if (n1_ % 2) {
        mpfr_mul(tmp, Mmid_[k * n1_ + half].get(), v[half].get(), MPFR_RNDN);
        mpfr_add(ck, ck, tmp, MPFR_RNDN);
      }
      mpfi_set_fr(c_[i * n1_ + k].get(), ck);
    }
    mpfr_mul(F_.get(), F_.get(), transform_error_scale_.get(), MPFR_RNDU);
    mpfi_interv_fr(widen.get(), F_.get(), F_.get());
    mpfi_neg(widen.get(), widen.get());
    mpfi_put_fr(widen.get(), F_.get());  // [-E, E]
    for (std::size_t k = 0; k < n1_; ++k) {
      mpfi_add(c_[i * n1_ + k].get(), c_[i * n1_ + k].get(), widen.get());
      mpfi_set(p_[i * n1_ + k].get(), c_[i * n1_ + k].get());
    }
  }
  for (int i = 0; i < 3; ++i) mpfi_add(p_[i * n1_].get(), p_[i * n1_].get(), X0_[i].get());
}

inline void certifier::picard_residual() {
  const std::size_t N = N_, np = 2 * N + 1, nr = 2 * N + 2;
  detail::interval& t = t_[0];
  // f(P) = G + N(P), N = (-P2 P3, P1 P3, -P1 P2): Chebyshev products,
  // T_m T_n = (T_{m+n} + T_{|m-n|}) / 2.
  const int pair[3][2] = {{1, 2}, {0, 2}, {0, 1}};
  const int sign[3] = {-1, 1, -1};
  coefficient_doubles();
  // The products of the large coefficients on midpoints (p^ = mid p, |p - p^| <= width), rounded
  // to nearest at the working precision: summed over the coefficients of one product, the error
  // is at most A B' + A' B + A' B' + (2N + 6) 2^-p (1 + 2^-20) A B, with A = sum |a^_m|,
  // A' = sum width(a_m) (the same for b), and enters `rem` below.
  for (int c = 0; c < 3; ++c) {
    mpfr_set_ui(Pabs_[c].get(), 0, MPFR_RNDU);
    mpfr_set_ui(Prad_[c].get(), 0, MPFR_RNDU);
    for (std::size_t k = 0; k < n1_; ++k) {
      const std::size_t q = c * n1_ + k;
      mpfi_mid(pmid_[q].get(), p_[q].get());
      mpfr_mul_2si(pmid_half_[q].get(), pmid_[q].get(), -1, MPFR_RNDN);  // exact
      detail::add_abs_up(Pabs_[c], pmid_[q].get());
      mpfi_get_left(scratch_lo_.get(), p_[q].get());
      mpfi_get_right(scratch_fr_.get(), p_[q].get());
      mpfr_sub(scratch_fr_.get(), scratch_fr_.get(), scratch_lo_.get(), MPFR_RNDU);
      mpfr_add(Prad_[c].get(), Prad_[c].get(), scratch_fr_.get(), MPFR_RNDU);
    }
  }
  mpfr_ptr tmp = mid_scratch_.get();
  for (int i = 0; i < 3; ++i) {
    detail::interval* out = &prod_[i * np];
    const int ca = pair[i][0], cb = pair[i][1];
    const detail::real* A = &pmid_half_[ca * n1_];  // a^_m / 2: T_m T_n's factor 1/2
    const detail::real* Bp = &pmid_[cb * n1_];
    for (std::size_t k = 0; k < np; ++k) mpfr_set_ui(outmid_[k].get(), 0, MPFR_RNDN);
    // The products of large coefficients here; those far below the precision of the reference
    // (|a_m| |b_n| < 2^-(bits - 54) of the state squared) in double, with a bound `rem` of their
    // total error, which the integral turns into a function bound below.
    std::fill(gd_.begin(), gd_.end(), 0.0);
    double rem = 0, small = 0;
    std::size_t in_double = 0;
    for (std::size_t m = 0; m < n1_; ++m)
      for (std::size_t n = 0; n < n1_; ++n) {
        const std::size_t d = m > n ? m - n : n - m;
        if (cmag_[ca * n1_ + m] * cmag_[cb * n1_ + n] < tail_level_) {
          const double pr = 0.5 * cd_[ca * n1_ + m] * cd_[cb * n1_ + n];
          gd_[m + n] += pr;
          gd_[d] += pr;
          small += std::abs(pr);
          ++in_double;
          rem += cmag_[ca * n1_ + m] * crad_[cb * n1_ + n] + crad_[ca * n1_ + m] * cmag_[cb * n1_ + n];
          continue;
        }
        mpfr_mul(tmp, A[m].get(), Bp[n].get(), MPFR_RNDN);
        mpfr_add(outmid_[m + n].get(), outmid_[m + n].get(), tmp, MPFR_RNDN);
        mpfr_add(outmid_[d].get(), outmid_[d].get(), tmp, MPFR_RNDN);
      }
    for (std::size_t k = 0; k < np; ++k) {
      mpfi_set_fr(out[k].get(), outmid_[k].get());
      if (gd_[k] != 0) mpfi_add_d(out[k].get(), out[k].get(), gd_[k]);
    }
    // The double sums have at most 2 (N+1) terms each; the exact a_m differ from cd_ by crad_;
    // an underflow allowance covers results near zero.
    const double rem_double = in_double ? (detail::gamma_of(2 * n1_ + 2) * 2 * small + rem +
                                           detail::underflow_allowance(4 * n1_ * n1_)) * (1 + 1e-12)
                                        : 0.0;
    detail::real& e = product_rem_[i];
    detail::real& w = bound_scratch_;
    mpfr_mul(e.get(), Pabs_[ca].get(), Prad_[cb].get(), MPFR_RNDU);
    mpfr_mul(w.get(), Prad_[ca].get(), Pabs_[cb].get(), MPFR_RNDU);
    mpfr_add(e.get(), e.get(), w.get(), MPFR_RNDU);
    mpfr_mul(w.get(), Prad_[ca].get(), Prad_[cb].get(), MPFR_RNDU);
    mpfr_add(e.get(), e.get(), w.get(), MPFR_RNDU);
    mpfr_mul(w.get(), Pabs_[ca].get(), Pabs_[cb].get(), MPFR_RNDU);
    mpfr_mul(w.get(), w.get(), product_error_scale_.get(), MPFR_RNDU);
    mpfr_add(e.get(), e.get(), w.get(), MPFR_RNDU);
    mpfr_add_d(e.get(), e.get(), rem_double, MPFR_RNDU);
    for (std::size_t k = 0; k < np; ++k)
      if (sign[i] < 0) mpfi_neg(out[k].get(), out[k].get());
    mpfi_add(out[0].get(), out[0].get(), problem_.G[i].get());
    // F = int_{-1}^s f: b_1 = a_0 - a_2/2, b_k = (a_{k-1} - a_{k+1}) / (2k), b_0 so that F(-1) = 0.
    detail::interval* r = &r_[i * nr];
    auto a = [&](std::size_t k) -> const detail::interval* { return k < np ? &out[k] : nullptr; };
    for (std::size_t k = 1; k < nr; ++k) {
      const detail::interval* lo = a(k - 1);
      const detail::interval* hi = a(k + 1);
      if (lo) mpfi_set(r[k].get(), lo->get()); else mpfi_set_ui(r[k].get(), 0);
      if (hi) {
        mpfi_set(t.get(), hi->get());
        if (k == 1) mpfi_mul_2si(t.get(), t.get(), -1);
        mpfi_sub(r[k].get(), r[k].get(), t.get());
      }
      if (k > 1) mpfi_div_ui(r[k].get(), r[k].get(), static_cast<unsigned long>(2 * k));
    }
    mpfi_set_ui(r[0].get(), 0);
    for (std::size_t k = 1; k < nr; ++k) {
      if (k % 2) mpfi_add(r[0].get(), r[0].get(), r[k].get());
      else mpfi_sub(r[0].get(), r[0].get(), r[k].get());
    }
    // r = v_0 - q + hl F (q the increment polynomial, q(-1) = v_0 exactly: node 0 is s = -1).
    for (std::size_t k = 0; k < nr; ++k) mpfi_mul(r[k].get(), r[k].get(), hl_.get());
    for (std::size_t k = 0; k < n1_; ++k) mpfi_sub(r[k].get(), r[k].get(), c_[i * n1_ + k].get());
    mpfi_add(r[0].get(), r[0].get(), v_[i * n1_].get());
    // sup |r| <= sum |r_k|; r(1) = sum r_k; both widened by the double products' error,
    // integrated: |hl int_{-1}^s e| <= 2 |hl| rem.
    mpfi_set_ui(rsup_[i].get(), 0);
    mpfi_set_ui(r1_[i].get(), 0);
    for (std::size_t k = 0; k < nr; ++k) {
      mpfi_abs(t.get(), r[k].get());
      mpfi_add(rsup_[i].get(), rsup_[i].get(), t.get());
      mpfi_add(r1_[i].get(), r1_[i].get(), r[k].get());
    }
    mpfi_set_fr(t.get(), product_rem_[i].get());
    mpfi_mul(t.get(), t.get(), hl_.get());
    mpfi_mul_2si(t.get(), t.get(), 1);
    mpfi_abs(t.get(), t.get());
    detail::to_upper_point(t);
    mpfi_add(rsup_[i].get(), rsup_[i].get(), t.get());
    mpfi_set(r_rem_[i].get(), t.get());
    mpfi_neg(t.get(), t.get());
    mpfi_put(r_rem_[i].get(), t.get());  // [-b, b]
    mpfi_add(r1_[i].get(), r1_[i].get(), r_rem_[i].get());
  }
}

inline void certifier::box_norm(detail::interval& out) const {
  // |B x|_2 with B point doubles: each component an interval, then [0, the norm's upper end].
  detail::interval& c = t_[2];
  detail::interval& t = t_[3];
  mpfi_set_ui(out.get(), 0);
  for (int i = 0; i < 3; ++i) {
    mpfi_set_ui(c.get(), 0);
    for (int k = 0; k < 3; ++k) {
      mpfi_mul_d(t.get(), x_[k].get(), B_[i * 3 + k]);
      mpfi_add(c.get(), c.get(), t.get());
    }
    mpfi_abs(c.get(), c.get());
    mpfi_sqr(c.get(), c.get());
    mpfi_add(out.get(), out.get(), c.get());
  }
  mpfi_sqrt(out.get(), out.get());
  detail::to_zero_hull(out);
}

inline void certifier::validate_segment() {
  chebyshev_coefficients();
  detail::interval& t = t_[0];
  // The error at the start: the scene's exact initial state minus P(a), or the previous box
  // plus the jump between the two segments' polynomials there (TwoSum compensation leaves one).
  if (!started_) {
    B_ = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (int i = 0; i < 3; ++i) {
      mpfi_sub(x_[i].get(), problem_.Omega0[i].get(), X0_[i].get());
      mpfi_sub(x_[i].get(), x_[i].get(), v_[i * n1_].get());
    }
  } else {
    ivec jump = make_vec(3);
    for (int i = 0; i < 3; ++i) {
      mpfi_sub(jump[i].get(), prev_end_[i].get(), X0_[i].get());
      mpfi_sub(jump[i].get(), jump[i].get(), v_[i * n1_].get());
    }
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) {
        mpfi_mul(t.get(), Qinv_[i * 3 + k].get(), jump[k].get());
        mpfi_add(x_[i].get(), x_[i].get(), t.get());
      }
  }
  box_norm(rho_a_);  // [0, rho]

  picard_residual();
  // sup |P_i| <= sum |p_ik|; mu = sup |P_2| bounds the logarithmic norm of J (the symmetric part
  // of J has eigenvalues +-|P_2| and 0); |J|_2 <= |J|_F = sqrt(2) |P|_2.
  for (int i = 0; i < 3; ++i) {
    mpfi_set_ui(psup_[i].get(), 0);
    for (std::size_t k = 0; k < n1_; ++k) {
      mpfi_abs(t.get(), p_[i * n1_ + k].get());
      mpfi_add(psup_[i].get(), psup_[i].get(), t.get());
    }
  }
  mpfi_set(mu_.get(), psup_[1].get());
  mpfi_set_ui(jmax_.get(), 0);
  mpfi_set_ui(rsup2_.get(), 0);
  for (int i = 0; i < 3; ++i) {
    mpfi_sqr(t.get(), psup_[i].get());
    mpfi_add(jmax_.get(), jmax_.get(), t.get());
    mpfi_sqr(t.get(), rsup_[i].get());
    mpfi_add(rsup2_.get(), rsup2_.get(), t.get());
  }
  mpfi_mul_ui(jmax_.get(), jmax_.get(), 2);
  mpfi_sqrt(jmax_.get(), jmax_.get());
  mpfi_sqrt(rsup2_.get(), rsup2_.get());

  // A-priori bound: with c = |e(a)| + sup |r| and L = |J| + R/sqrt(3), |e| stays below R on the
  // segment if c exp(L h) < R (Gronwall on e = e(a) + r + int (J e + N(e)), continued while
  // |e| < R). Try R = 2 c exp(|J| h).
  detail::interval c = make(), L = make(), e = make(), s3 = make();
  mpfi_add(c.get(), rho_a_.get(), rsup2_.get());
  mpfi_mul(e.get(), jmax_.get(), h_.get());
  mpfi_exp(e.get(), e.get());
  mpfi_mul(R_.get(), c.get(), e.get());
  mpfi_mul_ui(R_.get(), R_.get(), 2);
  detail::to_upper_point(R_);
  mpfi_set_ui(s3.get(), 3);
  mpfi_sqrt(s3.get(), s3.get());
  mpfi_div(L.get(), R_.get(), s3.get());
  mpfi_add(L.get(), L.get(), jmax_.get());
  mpfi_mul(L.get(), L.get(), h_.get());
  mpfi_exp(L.get(), L.get());
  mpfi_mul(L.get(), L.get(), c.get());
  if (!(mpfi_cmp(L.get(), R_.get()) < 0)) fail(outcome_kind::certify_a_priori);
  detail::to_zero_hull(R_);

  // The quadratic part of the integral term of step 3: h exp(mu h) R^2/sqrt(3) (its linear part,
  // int Phi J r, is signed_integral_term's).
  mpfi_sqr(ell_.get(), R_.get());
  mpfi_div(ell_.get(), ell_.get(), s3.get());
  mpfi_mul(e.get(), mu_.get(), h_.get());
  mpfi_exp(e.get(), e.get());
  mpfi_mul(ell_.get(), ell_.get(), e.get());
  mpfi_mul(ell_.get(), ell_.get(), h_.get());

  doubles_of_polynomials();
  const double hl = mpfi_get_d(hl_.get()), mu = detail::magnitude_up(mu_), jmax = detail::magnitude_up(jmax_),
               h = detail::magnitude_up(h_);
  variational_matrix(hl, mu, jmax, h);
  signed_integral_term(hl, mu, jmax, h);
  lohner_step();
  for (int i = 0; i < 3; ++i) {
    mpfi_add(prev_end_[i].get(), X0_[i].get(), v_[i * n1_ + N_].get());
  }
  mpfi_add(prev_b_.get(), a_.get(), h_.get());
  started_ = true;
}

// x's midpoint rounded to double, and an upper bound of max |x - d| over the interval: its
// width plus an ulp of d (the midpoint's own roundings are below half an ulp each), plus
// denorm_min for a d that underflows.
inline double certifier::to_double(const detail::interval& x, double& radius) const {
  const double d = mpfi_get_d(x.get());
  mpfi_get_left(scratch_lo_.get(), x.get());   // rounded down (MPFI rounds end points outward)
  mpfi_get_right(scratch_fr_.get(), x.get());  // rounded up
  mpfr_sub(scratch_fr_.get(), scratch_fr_.get(), scratch_lo_.get(), MPFR_RNDU);
  radius = (mpfr_get_d(scratch_fr_.get(), MPFR_RNDU) + std::abs(d) * std::numeric_limits<double>::epsilon() +
            std::numeric_limits<double>::denorm_min()) *
           (1 + 1e-15);
  return d;
}

// P's coefficients as doubles (cd_), each with a bound of its distance to the exact one (crad_)
// and of its magnitude (cmag_); tail_level_ separates the products done in double.
inline void certifier::coefficient_doubles() {
  double scale = 0;
  for (std::size_t q = 0; q < 3 * n1_; ++q) {
    cd_[q] = to_double(p_[q], crad_[q]);
    cmag_[q] = (std::abs(cd_[q]) + crad_[q]) * (1 + 1e-15);
    scale = std::max(scale, cmag_[q]);
  }
  tail_level_ = std::ldexp(scale * scale, -static_cast<int>(bits_ - 64 + 40 - 53));
  if (!(tail_level_ > 1e-250)) tail_level_ = 0;  // deep MPFR levels: everything in intervals
}

// Per component, a bound of the distance of P's doubles (cd_) to the exact coefficients (prad_);
// r as doubles with the same bound (rd_, rrad_).
inline void certifier::doubles_of_polynomials() {
  const std::size_t nr = 2 * N_ + 2;
  auto to_doubles = [&](const ivec& src, std::size_t n, std::vector<double>& out, std::array<double, 3>& rad) {
    for (int i = 0; i < 3; ++i) {
      rad[i] = 0;
      for (std::size_t k = 0; k < n; ++k) {
        double r = 0;
        out[i * n + k] = to_double(src[i * n + k], r);
        rad[i] += r;
      }
      rad[i] *= 1 + 1e-12;
    }
  };
  for (int i = 0; i < 3; ++i) {
    prad_[i] = 0;
    for (std::size_t k = 0; k < n1_; ++k) prad_[i] += crad_[i * n1_ + k];
    prad_[i] *= 1 + 1e-12;
  }
  // r is scaled by 2^r_scale_ to about 1 before it becomes doubles: at deep MPFR levels it lies
  // far below double's range. The integral term is linear in r, so its results are scaled back
  // exactly (signed_integral_term).
  mpfr_exp_t top = std::numeric_limits<mpfr_exp_t>::min();
  {
    mpfr_t m;
    mpfr_init2(m, bits_);
    for (const detail::interval& x : r_) {
      mpfi_mag(m, x.get());
      if (mpfr_regular_p(m)) top = std::max(top, mpfr_get_exp(m));
    }
    mpfr_clear(m);
  }
  r_scale_ = top == std::numeric_limits<mpfr_exp_t>::min() ? 0 : -static_cast<long>(top);
  for (std::size_t q = 0; q < r_.size(); ++q) mpfi_mul_2si(r_scaled_[q].get(), r_[q].get(), r_scale_);
  to_doubles(r_scaled_, nr, rd_, rrad_);
  for (int i = 0; i < 3; ++i) {  // the inexact products' share of r, scaled like r
    detail::interval scaled = r_rem_[i];
    mpfi_mul_2si(scaled.get(), scaled.get(), r_scale_);
    rrad_[i] += detail::magnitude_up(scaled) * (1 + 1e-12);
  }
}

// The nonzero entries of row i of J = DN(P) (Eq. 5): J_ik = sign P_c.
struct jacobian_entry {
  int k, c;
  double sign;
};
inline constexpr jacobian_entry jacobian_row[3][2] = {
    {{1, 2, -1}, {2, 1, -1}},  // row 1: -P3 in column 2, -P2 in column 3
    {{0, 2, 1}, {2, 0, 1}},    // row 2:  P3, P1
    {{0, 1, -1}, {1, 0, -1}},  // row 3: -P2, -P1
};

// A Picard residual bound sup|R| of a linear solution on the segment, as an error bound at its
// end: E = R + hl int J E gives |E(1)| <= sup|R| (1 + h exp(mu h) |J|).
inline void certifier::error_at_end(detail::interval& out, double supR, double mu, double h, double jmax) const {
  if (!std::isfinite(supR)) fail(outcome_kind::certify_non_finite);
  mpfi_set_d(out.get(), mu);
  mpfi_mul_d(out.get(), out.get(), h);
  mpfi_exp(out.get(), out.get());
  mpfi_mul_d(out.get(), out.get(), h);
  mpfi_mul_d(out.get(), out.get(), jmax);
  mpfi_add_ui(out.get(), out.get(), 1);
  mpfi_mul_d(out.get(), out.get(), supR);
}

// Phi' = hl J(P(s)) Phi on s in [-1, 1], Phi(-1) = I: Picard iteration in double on the Lobatto
// nodes of phi_basis_; Phi_num is the polynomial of its Chebyshev coefficients (exact doubles by
// definition). Its residual R(s) = I + hl int J Phi_num - Phi_num is bounded with every rounding
// (bounded_chebyshev.hpp); E = Phi - Phi_num solves E = R + hl int J E, so
// |E(1)| <= sup|R| (1 + h exp(mu h) |J|).
inline void certifier::variational_matrix(double hl, double mu, double jmax, double h) {
  const std::size_t m = phi_basis_.degree, m1 = m + 1;
  const double u = std::numeric_limits<double>::epsilon() / 2;
  std::vector<double> J(m1 * 9), Phi(m1 * 9), F(m1 * 9);
  for (std::size_t l = 0; l < m1; ++l) {
    double P[3];
    for (int i = 0; i < 3; ++i) P[i] = detail::clenshaw(&cd_[i * n1_], n1_, 1, phi_basis_.nodes[l]);
    double* Jl = &J[l * 9];
    std::fill(Jl, Jl + 9, 0.0);
    for (int i = 0; i < 3; ++i)
      for (const jacobian_entry& e : jacobian_row[i]) Jl[i * 3 + e.k] = e.sign * P[e.c];
  }
  for (std::size_t l = 0; l < m1; ++l)
    for (int q = 0; q < 9; ++q) Phi[l * 9 + q] = (q % 4 == 0) ? 1.0 : 0.0;
  for (int it = 0; it < 200; ++it) {
    for (std::size_t l = 0; l < m1; ++l)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          double acc = 0;
          for (int k = 0; k < 3; ++k) acc += J[l * 9 + i * 3 + k] * Phi[l * 9 + k * 3 + j];
          F[l * 9 + i * 3 + j] = acc;
        }
    double change = 0, size = 0;
    for (std::size_t l = 0; l < m1; ++l)
      for (int q = 0; q < 9; ++q) {
        double acc = 0;
        for (std::size_t k = 0; k < m1; ++k) acc += phi_basis_.integral[l * m1 + k] * F[k * 9 + q];
        const double next = ((q % 4 == 0) ? 1.0 : 0.0) + hl * acc;
        change = std::max(change, std::abs(next - Phi[l * 9 + q]));
        size = std::max(size, std::abs(next));
        Phi[l * 9 + q] = next;
      }
    if (!std::isfinite(change)) fail(outcome_kind::certify_non_finite);
    if (change <= 4 * u * size) break;
  }
  std::vector<double> phi(9 * m1);  // entry q = 3 i + j, coefficients k
  for (int q = 0; q < 9; ++q)
    for (std::size_t k = 0; k < m1; ++k) {
      double acc = 0;
      for (std::size_t l = 0; l < m1; ++l) acc += phi_basis_.coeffs[k * m1 + l] * Phi[l * 9 + q];
      phi[q * m1 + k] = acc;
    }
  double sup2 = 0;  // sum over entries of sup|R_ij|^2
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      std::array<detail::product_term, 2> terms;
      for (int t = 0; t < 2; ++t) {
        const jacobian_entry& e = jacobian_row[i][t];
        terms[t] = {e.sign, {&cd_[e.c * n1_], n1_, prad_[e.c]}, {&phi[(e.k * 3 + j) * m1], m1, 0.0}};
      }
      product_sum_.compute(hl, terms);
      const double b = detail::residual_bound(i == j ? 1.0 : 0.0, product_sum_, {&phi[(i * 3 + j) * m1], m1, 0.0});
      sup2 += b * b;
    }
  // eps_phi bounds |Phi(b, a) - Phi_num(1)|; Phi_num(1) = sum_k phi_k, in intervals.
  error_at_end(eps_phi_, std::sqrt(sup2) * (1 + 1e-12), mu, h, jmax);
  for (int q = 0; q < 9; ++q) {
    mpfi_set_ui(Phi1_[q].get(), 0);
    for (std::size_t k = 0; k < m1; ++k) mpfi_add_d(Phi1_[q].get(), Phi1_[q].get(), phi[q * m1 + k]);
  }
}

// The signed integral term of step 3, u(b) = int_a^b Phi(b, s) J(s) r(s) ds: u solves
// u = hl int J (u + r) (s from -1), computed in double by Picard iteration on Chebyshev
// coefficients (degree 2N + 1, like r), then bounded: with R_u = hl int J (u_num + r) - u_num,
// E = u - u_num solves E = R_u + hl int J E, so |E(1)| <= sup|R_u| (1 + h exp(mu h) |J|). u_num(1)
// joins r(1) as a signed vector; only |E(1)| is a ball. It is about ten times r(1) where a segment
// spans a good part of a rotation, so bounding it by norms would dominate the whole bound.
inline void certifier::signed_integral_term(double hl, double mu, double jmax, double h) {
  const std::size_t nr = 2 * N_ + 2;
  std::vector<double>& ud = ud_;
  std::vector<double> w(3 * nr);
  ud.assign(3 * nr, 0.0);
  // The iteration needs u to a few digits only, so it drops P's coefficients below 1e-9 of the
  // largest (the final residual uses them all).
  std::array<std::size_t, 3> short_length;
  for (int c = 0; c < 3; ++c) {
    double big = 0;
    for (std::size_t k = 0; k < n1_; ++k) big = std::max(big, std::abs(cd_[c * n1_ + k]));
    std::size_t n = n1_;
    while (n > 1 && std::abs(cd_[c * n1_ + n - 1]) < 1e-9 * big) --n;
    short_length[c] = n;
  }
  auto J_times = [&](int i, const double* wc, double wrad_each[3], bool full) {
    std::array<detail::product_term, 2> terms;
    for (int t = 0; t < 2; ++t) {
      const jacobian_entry& e = jacobian_row[i][t];
      terms[t] = {e.sign, {&cd_[e.c * n1_], full ? n1_ : short_length[e.c], prad_[e.c]},
                  {&wc[e.k * nr], nr, wrad_each[e.k]}};
    }
    product_sum_.compute(hl, terms);
  };
  double zero_rad[3] = {0, 0, 0};
  std::vector<double> next(3 * nr);
  for (int it = 0; it < 60; ++it) {
    for (std::size_t q = 0; q < 3 * nr; ++q) w[q] = ud[q] + rd_[q];
    double change = 0, size = 0;
    for (int i = 0; i < 3; ++i) {
      J_times(i, w.data(), zero_rad, false);
      for (std::size_t k = 0; k < nr; ++k) next[i * nr + k] = product_sum_.coeffs[k];  // truncated
    }
    for (std::size_t q = 0; q < 3 * nr; ++q) {
      change = std::max(change, std::abs(next[q] - ud[q]));
      size = std::max(size, std::abs(next[q]));
    }
    ud.swap(next);
    if (!std::isfinite(change)) fail(outcome_kind::certify_non_finite);
    if (change <= 1e-5 * size) break;  // enough: the residual bound covers the rest
  }
  // The residual of the exact polynomials: u_num exact, r = rd + (its radius).
  std::vector<double> uplusr(3 * nr);
  for (std::size_t q = 0; q < 3 * nr; ++q) uplusr[q] = ud[q] + rd_[q];
  double sup2 = 0;
  for (int i = 0; i < 3; ++i) {
    // u_num + r as a view: the sum rounded to uplusr, its error in the radius.
    double rad[3];
    for (int k = 0; k < 3; ++k)
      rad[k] = rrad_[k] + detail::gamma_of(2) * (detail::abs_sum(&ud[k * nr], nr) + detail::abs_sum(&rd_[k * nr], nr));
    J_times(i, uplusr.data(), rad, true);
    const double b = detail::residual_bound(0.0, product_sum_, {&ud[i * nr], nr, 0.0});
    sup2 += b * b;
  }
  error_at_end(eps_u_, std::sqrt(sup2) * (1 + 1e-12), mu, h, jmax);
  for (int i = 0; i < 3; ++i) {
    mpfi_set_ui(u1_[i].get(), 0);
    for (std::size_t k = 0; k < nr; ++k) mpfi_add_d(u1_[i].get(), u1_[i].get(), ud[i * nr + k]);
    mpfi_mul_2si(u1_[i].get(), u1_[i].get(), -r_scale_);  // back from r's scaling
  }
  mpfi_mul_2si(eps_u_.get(), eps_u_.get(), -r_scale_);
}

// e(b) in Phi1 B x + r(1) + u_num(1) + a ball of radius ell + eps_u + eps_phi |e(a)|; the new B is the Q of a QR
// factorisation of mid(Phi1 B) (columns by decreasing length), x the box (Q^-1 Phi1 B) x + Q^-1
// (r(1) + ball), with Q^-1 enclosed from the computed Q.
inline void certifier::lohner_step() {
  detail::interval& t = t_[0];
  ivec A = make_vec(9);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      mpfi_set_ui(A[i * 3 + j].get(), 0);
      for (int k = 0; k < 3; ++k) {
        mpfi_mul_d(t.get(), Phi1_[i * 3 + k].get(), B_[k * 3 + j]);
        mpfi_add(A[i * 3 + j].get(), A[i * 3 + j].get(), t.get());
      }
    }
  // Q from modified Gram-Schmidt on mid(A), columns by decreasing length times box width.
  double Am[9];
  for (int q = 0; q < 9; ++q) Am[q] = mpfi_get_d(A[q].get());
  std::array<int, 3> order = {0, 1, 2};
  double weight[3];
  for (int j = 0; j < 3; ++j) {
    const double len = std::hypot(Am[j], Am[3 + j], Am[6 + j]);
    weight[j] = len * detail::magnitude_up(x_[j]);
  }
  std::sort(order.begin(), order.end(), [&](int p, int q) { return weight[p] > weight[q]; });
  double Q[9];
  for (int c = 0; c < 3; ++c) {
    double v[3] = {Am[order[c]], Am[3 + order[c]], Am[6 + order[c]]};
    for (int prev = 0; prev < c; ++prev) {
      const double d = v[0] * Q[prev] + v[1] * Q[3 + prev] + v[2] * Q[6 + prev];
      for (int i = 0; i < 3; ++i) v[i] -= d * Q[i * 3 + prev];
    }
    double len = std::hypot(v[0], v[1], v[2]);
    if (!(len > 0) || !std::isfinite(len)) {
      // A degenerate column (a zero box): any unit vector orthogonal to the previous ones.
      for (int e = 0; e < 3 && !(len > 1e-3); ++e) {
        v[0] = v[1] = v[2] = 0;
        v[e] = 1;
        for (int prev = 0; prev < c; ++prev) {
          const double d = v[0] * Q[prev] + v[1] * Q[3 + prev] + v[2] * Q[6 + prev];
          for (int i = 0; i < 3; ++i) v[i] -= d * Q[i * 3 + prev];
        }
        len = std::hypot(v[0], v[1], v[2]);
      }
    }
    for (int i = 0; i < 3; ++i) Q[i * 3 + c] = v[i] / len;
  }
  // Q^-1 = (I + D)^-1 Q^T with D = Q^T Q - I: |Q^-1 - Q^T| <= delta/(1 - delta) |Q^T|_inf,
  // delta = |D|_inf (enclosed).
  detail::interval delta = make(), row = make();
  mpfi_set_ui(delta.get(), 0);
  for (int i = 0; i < 3; ++i) {
    mpfi_set_ui(row.get(), 0);
    for (int j = 0; j < 3; ++j) {
      mpfi_set_si(t.get(), i == j ? -1 : 0);
      for (int k = 0; k < 3; ++k) {
        detail::interval prod = make();
        mpfi_set_d(prod.get(), Q[k * 3 + i]);
        mpfi_mul_d(prod.get(), prod.get(), Q[k * 3 + j]);
        mpfi_add(t.get(), t.get(), prod.get());
      }
      mpfi_abs(t.get(), t.get());
      mpfi_add(row.get(), row.get(), t.get());
    }
    mpfi_union(delta.get(), delta.get(), row.get());  // its right end: the largest row sum
  }
  double qt_inf = 0;
  for (int i = 0; i < 3; ++i) qt_inf = std::max(qt_inf, std::abs(Q[i]) + std::abs(Q[3 + i]) + std::abs(Q[6 + i]));
  detail::interval slack = make(), one = make();
  mpfi_set_ui(one.get(), 1);
  mpfi_sub(one.get(), one.get(), delta.get());
  if (!(mpfi_is_strictly_pos(one.get()) > 0)) fail(outcome_kind::certify_non_finite);
  mpfi_div(slack.get(), delta.get(), one.get());
  mpfi_mul_d(slack.get(), slack.get(), qt_inf * (1 + 1e-15));
  detail::to_upper_point(slack);
  mpfi_neg(one.get(), slack.get());
  mpfi_put(slack.get(), one.get());  // [-slack, slack]
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      mpfi_set_d(Qinv_[i * 3 + j].get(), Q[j * 3 + i]);
      mpfi_add(Qinv_[i * 3 + j].get(), Qinv_[i * 3 + j].get(), slack.get());
    }
  // The local part: r(1) and the ball of radius ell + eps_phi |e(a)|, as a box.
  detail::interval ball = make();
  mpfi_mul(ball.get(), eps_phi_.get(), rho_a_.get());
  mpfi_add(ball.get(), ball.get(), ell_.get());
  mpfi_add(ball.get(), ball.get(), eps_u_.get());
  {
    detail::to_upper_point(ball);
    detail::interval negative = make();
    mpfi_neg(negative.get(), ball.get());
    mpfi_put(ball.get(), negative.get());  // [-b, b]
  }
  ivec local = make_vec(3);
  for (int i = 0; i < 3; ++i) {
    mpfi_add(local[i].get(), r1_[i].get(), u1_[i].get());
    mpfi_add(local[i].get(), local[i].get(), ball.get());
  }
  // x' = (Q^-1 A) x + Q^-1 local
  ivec C = make_vec(9);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      mpfi_set_ui(C[i * 3 + j].get(), 0);
      for (int k = 0; k < 3; ++k) {
        mpfi_mul(t.get(), Qinv_[i * 3 + k].get(), A[k * 3 + j].get());
        mpfi_add(C[i * 3 + j].get(), C[i * 3 + j].get(), t.get());
      }
    }
  ivec xn = make_vec(3);
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      mpfi_mul(t.get(), C[i * 3 + k].get(), x_[k].get());
      mpfi_add(xn[i].get(), xn[i].get(), t.get());
      mpfi_mul(t.get(), Qinv_[i * 3 + k].get(), local[k].get());
      mpfi_add(xn[i].get(), xn[i].get(), t.get());
    }
  }
  x_ = std::move(xn);
  for (int q = 0; q < 9; ++q) B_[q] = Q[q];
  // The bound must stay meaningful: beyond 2^-20 of the state it is of no use to anyone.
  detail::interval norm = make();
  box_norm(norm);
  const double size = detail::magnitude_up(norm);
  double state = 0;
  for (int i = 0; i < 3; ++i) state = std::max(state, detail::magnitude_up(psup_[i]));
  if (!(size <= std::ldexp(1.0, -20) * std::max(1.0, state))) fail(outcome_kind::certify_growth, size / std::max(1.0, state));
}

template <scalar T>
certifier::enclosure certifier::enclose(const T& tau) const {
  enclosure out{make(), make_vec(3), make(), make()};
  detail::interval dt = make(), s = make(), e = make(), t = make(), s3 = make();
  detail::set_exact(dt, tau);
  mpfi_sub(dt.get(), dt.get(), a_.get());
  // exp(mu dt) |e(a)| + sup|r| + dt exp(mu dt) (|J| sup|r| + R^2/sqrt(3))
  mpfi_mul(e.get(), mu_.get(), dt.get());
  mpfi_exp(e.get(), e.get());
  mpfi_mul(out.error.get(), e.get(), rho_a_.get());
  mpfi_add(out.error.get(), out.error.get(), rsup2_.get());
  mpfi_set_ui(s3.get(), 3);
  mpfi_sqrt(s3.get(), s3.get());
  mpfi_sqr(t.get(), R_.get());
  mpfi_div(t.get(), t.get(), s3.get());
  mpfi_mul(s.get(), jmax_.get(), rsup2_.get());
  mpfi_add(t.get(), t.get(), s.get());
  mpfi_mul(t.get(), t.get(), e.get());
  mpfi_mul(t.get(), t.get(), dt.get());
  mpfi_add(out.error.get(), out.error.get(), t.get());
  detail::to_zero_hull(out.error);
  // P = sum p_k T_k(s) at s = dt / hl - 1, summed directly: T_k from the three-term recurrence,
  // each clipped to [-1, 1] (where the exact T_k(s) lies). The recurrence's widths grow like
  // 2.4^k, but they multiply p_k, which decay faster; Clenshaw's algorithm instead multiplies the
  // coefficients' own widths by 2.4^k (2^118 at mpfr:256's degree), which would swamp the bound.
  mpfi_div(s.get(), dt.get(), hl_.get());
  mpfi_sub_ui(s.get(), s.get(), 1);
  detail::interval unit = make();
  mpfi_interv_si(unit.get(), -1, 1);
  mpfi_intersect(s.get(), s.get(), unit.get());  // the exact s lies in [-1, 1]
  ivec Tk = make_vec(n1_);
  mpfi_set_ui(Tk[0].get(), 1);
  if (n1_ > 1) mpfi_set(Tk[1].get(), s.get());
  for (std::size_t k = 2; k < n1_; ++k) {
    mpfi_mul(Tk[k].get(), Tk[k - 1].get(), s.get());
    mpfi_mul_2si(Tk[k].get(), Tk[k].get(), 1);
    mpfi_sub(Tk[k].get(), Tk[k].get(), Tk[k - 2].get());
    mpfi_intersect(Tk[k].get(), Tk[k].get(), unit.get());
  }
  for (int i = 0; i < 3; ++i) {
    mpfi_set_ui(out.P[i].get(), 0);
    for (std::size_t k = 0; k < n1_; ++k) {
      mpfi_mul(t.get(), p_[i * n1_ + k].get(), Tk[k].get());
      mpfi_add(out.P[i].get(), out.P[i].get(), t.get());
    }
  }
  // Y = |sup P|_2 + R; F = |G|_2 + (2 Y)^2 / sqrt(3) (|N(y)| <= |y|^2 / sqrt(3)).
  mpfi_set_ui(out.state.get(), 0);
  mpfi_set_ui(out.rate.get(), 0);
  for (int i = 0; i < 3; ++i) {
    mpfi_sqr(t.get(), psup_[i].get());
    mpfi_add(out.state.get(), out.state.get(), t.get());
    mpfi_sqr(t.get(), problem_.G[i].get());
    mpfi_add(out.rate.get(), out.rate.get(), t.get());
  }
  mpfi_sqrt(out.state.get(), out.state.get());
  mpfi_add(out.state.get(), out.state.get(), R_.get());
  detail::to_zero_hull(out.state);
  mpfi_sqrt(out.rate.get(), out.rate.get());
  mpfi_mul_ui(t.get(), out.state.get(), 2);
  mpfi_sqr(t.get(), t.get());
  mpfi_div(t.get(), t.get(), s3.get());
  mpfi_add(out.rate.get(), out.rate.get(), t.get());
  detail::to_zero_hull(out.rate);
  return out;
}

inline detail::interval certifier::row_radius(const enclosure& at, const std::array<std::string, 3>& printed) {
  detail::interval out = make(), t = make(), sq = make();
  mpfi_set_ui(sq.get(), 0);
  for (int i = 0; i < 3; ++i) {
    detail::set_decimal(t, printed[i]);
    mpfi_sub(t.get(), t.get(), at.P[i].get());
    mpfi_abs(t.get(), t.get());
    mpfi_sqr(t.get(), t.get());
    mpfi_add(sq.get(), sq.get(), t.get());
  }
  mpfi_sqrt(sq.get(), sq.get());
  mpfi_add(out.get(), at.error.get(), sq.get());
  detail::to_zero_hull(out);  // the upper end only: [0, sup]
  mpfi_put(max_radius_.get(), out.get());
  return out;
}

template <scalar T>
detail::interval certifier::row_radius(const T& tau, const std::array<std::string, 3>& printed) {
  return row_radius(enclose(tau), printed);
}

}  // namespace eulervop
