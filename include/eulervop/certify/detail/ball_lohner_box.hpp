// The error at a segment's start, e(a), in D dimensions, for the general path of --certify, as a
// parallelepiped M v plus a second set Q z: M and Q point matrices of doubles, v and z vectors of
// balls (Lohner 1987; Nedialkov and Jackson 2001). Across a segment, e(b) lies in
// Phi e(a) + w + [-b_i, b_i], w = r(b) + u(b) signed, and the new sets are
//   v' = (M'^-1 Phi M) v + M'^-1 mid(w),   z' = (Q'^-1 Phi Q) z + Q'^-1 (rad(w) + [-b_i, b_i]).
// M' = mid(Phi M) (the parallelepiped method), so that (M'^-1 Phi M) is the identity but for
// rounding: the flow's shear, which is large where q's error follows the rates', lives in the
// matrix and wraps nothing. (A QR form, which the certificate's former fast path kept, wraps under
// that shear: its parallelepiped's columns turn at every segment, and the boxes' corners
// accumulate; on the spacecraft with its attitude it gave radii a thousand times larger.) A ball
// added in M^-1's coordinates, though, may grow with M's condition, which a flow's shear raises
// segment by segment: on the paper's spin-up continued to tau = 360 (hard/spinup-unstable), with
// one set for both, the balls of about 1e-40 a segment grew to radii of 1.5e-29 (eight times the
// error), while the set's midpoints followed the error. So the signed terms (the residuals, the
// jumps at joins and breakpoints) enter M v with their signs, and every ball (their radii, the
// bounds of what is below them) enters the second set Q z. While Q is M and mid(Phi M)'s
// condition stays below 10^5, Q z takes the same step; otherwise Q' is mid(Phi Q) or the Q of a QR
// factorisation of it (modified Gram-Schmidt, columns by decreasing length times the size of their
// z), whichever gives the smaller image. Measured on the shipped datasets: spin-up 1.50e-29 to
// 2.02e-30 (its error about 1.9e-30), the paper scene 3.25e-31 to 3.11e-31, long-bounded and
// near-separatrix-free 4% and 2% smaller, every other largest radius the same. Should M'
// pass a condition of 10^6 (an exponentially stretching flow), M' is such a Q too. Each inverse is
// enclosed from an approximate one in double (Q^T for Q; Gaussian elimination for M') by a
// Neumann series in balls (enclose_inverse()).
// The first segment's e(a), which may be a box of initial states, starts in M v.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/small_solve.hpp>

#include <arb.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <vector>

namespace eulervop::detail {

// The largest condition number (in the infinity norm) at which the signed part's matrix is
// mid(Phi M_s) itself.
inline constexpr double parallelepiped_condition = 1e6;
// The condition up to which the balls' set takes mid(Phi Q) without trying a QR factor. Measured
// on the shipped scenes: at 10^5 no largest radius grew; at 10^3 the gravity-gradient libration's
// grew 1.5 times (a QR step taken for a smaller image then, which wrapped later).
inline constexpr double balls_condition = 1e5;

// M^-1 enclosed from an approximate inverse X (both point matrices of doubles, row-major): with
// E = I - X M in balls and d >= |E|_inf below 1,
//   M^-1 = (I - E)^-1 X = X + E X + E^2 (I - E)^-1 X,  |E^2 (I - E)^-1 X|_inf <= d^2 / (1 - d) |X|_inf
// (the Neumann series; Rump, "Verification methods: Rigorous results using floating-point
// arithmetic", Acta Numerica 19, 2010, section 10), so each entry lies in X + E X widened by that
// bound. false where d is not below 1. E and E X are taken at 64 bits: E's entries are near
// 2^-52 |X| |M| and E X a correction of that size, whose own last bits move no radius of the box
// (measured: every shipped scene's radii the same as at 128 bits).
inline bool enclose_inverse(const std::vector<double>& M, const std::vector<double>& X, std::size_t D,
                            std::vector<ball>& inv) {
  const auto n = static_cast<slong>(D);
  std::vector<ball> Mb(D * D), Xb(D * D), E(D * D);
  for (std::size_t q = 0; q < D * D; ++q) {
    arb_set_d(Mb[q].get(), M[q]);
    arb_set_d(Xb[q].get(), X[q]);
  }
  const ball one(1);
  mag_value d, x_norm, row, m;
  for (std::size_t i = 0; i < D; ++i) {
    mag_zero(row.m);
    for (std::size_t j = 0; j < D; ++j) {
      arb_dot(E[i * D + j].get(), i == j ? one.get() : nullptr, 1, Xb[i * D].get(), 1, Mb[j].get(), n, n, 64);
      arb_get_mag(m.m, E[i * D + j].get());
      mag_add(row.m, row.m, m.m);
    }
    mag_max(d.m, d.m, row.m);
    mag_zero(row.m);
    for (std::size_t j = 0; j < D; ++j) {
      arb_get_mag(m.m, Xb[i * D + j].get());
      mag_add(row.m, row.m, m.m);
    }
    mag_max(x_norm.m, x_norm.m, row.m);
  }
  if (!mag_is_finite(d.m) || !mag_is_finite(x_norm.m) || mag_cmp_2exp_si(d.m, 0) >= 0) return false;
  mag_value tail, gap;
  mag_one(gap.m);
  mag_sub_lower(gap.m, gap.m, d.m);
  mag_mul(tail.m, d.m, d.m);
  mag_mul(tail.m, tail.m, x_norm.m);
  mag_div(tail.m, tail.m, gap.m);
  inv.assign(D * D, ball());
  for (std::size_t i = 0; i < D; ++i)
    for (std::size_t j = 0; j < D; ++j) {
      ball& x = inv[i * D + j];
      arb_dot(x.get(), Xb[i * D + j].get(), 0, E[i * D].get(), 1, Xb[j].get(), n, n, 64);
      arb_add_error_mag(x.get(), tail.m);
    }
  return true;
}

// The inverse of the point matrix M (row-major) in balls, from Gaussian elimination in double;
// false if it is singular or its condition exceeds `limit` (|M|_inf |M^-1|_inf, from the
// enclosure).
inline bool enclose_general_inverse(const std::vector<double>& M, std::size_t D, double limit, std::vector<ball>& inv,
                                    double* condition = nullptr) {
  std::vector<double> X;
  if (!approximate_inverse(M, D, X) || !enclose_inverse(M, X, D, inv)) return false;
  double norm = 0, inv_norm = 0;
  mag_value e;
  for (std::size_t i = 0; i < D; ++i) {
    double row = 0, inv_row = 0;
    for (std::size_t j = 0; j < D; ++j) {
      row += std::abs(M[i * D + j]);
      arb_get_mag(e.m, inv[i * D + j].get());
      inv_row += mag_get_d(e.m);
    }
    norm = std::max(norm, row);
    inv_norm = std::max(inv_norm, inv_row);
  }
  if (condition) *condition = norm * inv_norm;
  return norm * inv_norm <= limit;
}

class ball_lohner_box {
 public:
  ball_lohner_box(std::size_t dimension, slong prec)
      : D_(dimension), prec_(prec), set_(dimension), balls_(dimension) {}

  // The first segment's: e(a) itself, M = I; the second set empty.
  void start(const std::vector<ball>& e0) {
    set_.identity();
    set_.v = e0;
    balls_.identity();
    for (ball& x : balls_.v) arb_zero(x.get());
  }
  // Adds `jump` to e (the jump between two segments' polynomials at their join, a breakpoint's):
  // its midpoint to M v, its radius to Q z.
  void join(const std::vector<ball>& jump) {
    std::vector<ball> mid, rad;
    split(jump, mid, rad);
    set_.add(mid, prec_);
    balls_.add(rad, prec_);
  }
  // An upper bound of |W e|_2 over the set, W = diag(weight) (powers of two).
  void norm(mag_t out, const std::vector<double>& weight) const {
    std::vector<ball> e;
    image_of_identity(e);
    mag_t m;
    mag_init(m);
    mag_zero(out);
    for (std::size_t i = 0; i < D_; ++i) {
      arb_get_mag(m, e[i].get());
      mag_mul_2exp_si(m, m, std::ilogb(weight[i]));
      mag_addmul(out, m, m);
    }
    mag_sqrt(out, out);
    mag_clear(m);
  }
  // e componentwise.
  void image_of_identity(std::vector<ball>& out) const {
    out.assign(D_, ball());
    set_.image_add(out, prec_);
    balls_.image_add(out, prec_);
  }
  // Phi e componentwise, for a D x D matrix of balls Phi: (Phi M) v for each set, so that the
  // image keeps what M holds of the flow's shear.
  void image(const std::vector<ball>& Phi, std::vector<ball>& out, slong prec) const {
    out.assign(D_, ball());
    std::vector<ball> A(D_ * D_);
    const auto D = static_cast<slong>(D_);
    for (const part* p : {&set_, &balls_}) {
      p->times(Phi, A, prec);
      for (std::size_t i = 0; i < D_; ++i)
        arb_dot(out[i].get(), out[i].get(), 0, A[i * D_].get(), 1, p->v[0].get(), 1, D, prec);
    }
  }
  // To the segment's end: e(b) in Phi1 e(a) + w + [-b_i, b_i] in each component. False when a new
  // matrix's inverse cannot be enclosed.
  bool step(const std::vector<ball>& Phi1, const std::vector<ball>& w, const std::vector<mag_value>& b);

 private:
  // One set M v: M a point matrix of doubles (row-major; Mb the same numbers as exact balls, for
  // Arb's dot products), v balls, Minv an enclosure of M^-1.
  struct part {
    explicit part(std::size_t D) : D(D), M(D * D), Mb(D * D), v(D), Minv(D * D) { identity(); }
    void identity() {
      std::vector<double> I(D * D, 0.0);
      for (std::size_t q = 0; q < D * D; ++q) arb_zero(Minv[q].get());
      for (std::size_t i = 0; i < D; ++i) {
        I[i * D + i] = 1;
        arb_one(Minv[i * D + i].get());
      }
      set_matrix(I);
    }
    void set_matrix(const std::vector<double>& m) {
      M = m;
      for (std::size_t q = 0; q < D * D; ++q) arb_set_d(Mb[q].get(), M[q]);
    }
    // v += M^-1 x.
    void add(const std::vector<ball>& x, slong prec) {
      for (std::size_t i = 0; i < D; ++i)
        for (std::size_t k = 0; k < D; ++k) arb_addmul(v[i].get(), Minv[i * D + k].get(), x[k].get(), prec);
    }
    // out += M v.
    void image_add(std::vector<ball>& out, slong prec) const {
      for (std::size_t i = 0; i < D; ++i)
        arb_dot(out[i].get(), out[i].get(), 0, Mb[i * D].get(), 1, v[0].get(), 1, static_cast<slong>(D), prec);
    }
    // A = Phi M.
    void times(const std::vector<ball>& Phi, std::vector<ball>& A, slong prec) const {
      for (std::size_t i = 0; i < D; ++i)
        for (std::size_t j = 0; j < D; ++j)
          arb_dot(A[i * D + j].get(), nullptr, 0, Phi[i * D].get(), 1, Mb[j].get(), static_cast<slong>(D),
                  static_cast<slong>(D), prec);
    }
    // An upper bound of sum_i |(M v)_i| (in double, for a comparison only).
    double width() const {
      double out = 0;
      for (std::size_t k = 0; k < D; ++k) {
        double col = 0;
        for (std::size_t i = 0; i < D; ++i) col += std::abs(M[i * D + k]);
        out += col * magnitude_up(v[k]);
      }
      return out;
    }
    std::size_t D;
    std::vector<double> M;
    std::vector<ball> Mb, v, Minv;
  };

  // Moves p across the segment with A = Phi M_p: p.M = Mnew, p.v = (Mnew^-1 A) v + Mnew^-1 local.
  bool move(part& p, const std::vector<ball>& A, const std::vector<double>& Mnew, const std::vector<ball>& local);
  void orthogonal_factor(const std::vector<ball>& A, const std::vector<ball>& v, std::vector<double>& Q) const;
  bool enclose_orthogonal_inverse(const std::vector<double>& Q, std::vector<ball>& inv) const;

  // x's midpoints (exact) and radii (as balls 0 +- rad).
  static void split(const std::vector<ball>& x, std::vector<ball>& mid, std::vector<ball>& rad) {
    mid.assign(x.size(), ball());
    rad.assign(x.size(), ball());
    for (std::size_t i = 0; i < x.size(); ++i) {
      arf_set(arb_midref(mid[i].get()), arb_midref(x[i].get()));
      mag_set(arb_radref(rad[i].get()), arb_radref(x[i].get()));
    }
  }

  std::size_t D_;
  slong prec_;
  part set_;     // M v: the signed part
  part balls_;  // Q z: the balls
};

// Q from modified Gram-Schmidt on mid(A), columns by decreasing length times the size of v.
inline void ball_lohner_box::orthogonal_factor(const std::vector<ball>& A, const std::vector<ball>& v,
                                               std::vector<double>& Q) const {
  const std::size_t D = D_;
  std::vector<double> Am(D * D);
  for (std::size_t q = 0; q < D * D; ++q) Am[q] = arf_get_d(arb_midref(A[q].get()), ARF_RND_NEAR);
  std::vector<std::size_t> order(D);
  std::iota(order.begin(), order.end(), 0);
  std::vector<double> weight(D);
  for (std::size_t j = 0; j < D; ++j) {
    double len = 0;
    for (std::size_t i = 0; i < D; ++i) len += Am[i * D + j] * Am[i * D + j];
    weight[j] = std::sqrt(len) * magnitude_up(v[j]);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t p, std::size_t q) { return weight[p] > weight[q]; });
  Q.assign(D * D, 0.0);
  std::vector<double> x(D);
  const auto orthogonalize = [&](std::size_t c) {
    for (std::size_t prev = 0; prev < c; ++prev) {
      double d = 0;
      for (std::size_t i = 0; i < D; ++i) d += x[i] * Q[i * D + prev];
      for (std::size_t i = 0; i < D; ++i) x[i] -= d * Q[i * D + prev];
    }
  };
  const auto length = [&] {
    double s = 0;
    for (double y : x) s += y * y;
    return std::sqrt(s);
  };
  for (std::size_t c = 0; c < D; ++c) {
    for (std::size_t i = 0; i < D; ++i) x[i] = Am[i * D + order[c]];
    orthogonalize(c);
    double len = length();
    // A degenerate column (a zero set): a unit vector orthogonal to the previous ones.
    if (!(len > 0) || !std::isfinite(len))
      for (std::size_t e = 0; e < D && !(len > 1e-3 && std::isfinite(len)); ++e) {
        std::fill(x.begin(), x.end(), 0.0);
        x[e] = 1;
        orthogonalize(c);
        len = length();
      }
    for (std::size_t i = 0; i < D; ++i) Q[i * D + c] = x[i] / len;
  }
}

// Q's inverse from Q^T.
inline bool ball_lohner_box::enclose_orthogonal_inverse(const std::vector<double>& Q, std::vector<ball>& inv) const {
  const std::size_t D = D_;
  std::vector<double> QT(D * D);
  for (std::size_t i = 0; i < D; ++i)
    for (std::size_t j = 0; j < D; ++j) QT[i * D + j] = Q[j * D + i];
  return enclose_inverse(Q, QT, D, inv);
}

inline bool ball_lohner_box::move(part& p, const std::vector<ball>& A, const std::vector<double>& Mnew,
                                  const std::vector<ball>& local) {
  const std::size_t D = D_;
  const auto n = static_cast<slong>(D);
  std::vector<ball> C(D * D), next(D);
  for (std::size_t i = 0; i < D; ++i)
    for (std::size_t j = 0; j < D; ++j)
      arb_dot(C[i * D + j].get(), nullptr, 0, p.Minv[i * D].get(), 1, A[j].get(), n, n, prec_);
  for (std::size_t i = 0; i < D; ++i) {
    arb_dot(next[i].get(), nullptr, 0, C[i * D].get(), 1, p.v[0].get(), 1, n, prec_);
    arb_dot(next[i].get(), next[i].get(), 0, p.Minv[i * D].get(), 1, local[0].get(), 1, n, prec_);
  }
  p.v.swap(next);
  p.set_matrix(Mnew);
  return true;
}

inline bool ball_lohner_box::step(const std::vector<ball>& Phi1, const std::vector<ball>& w,
                                  const std::vector<mag_value>& b) {
  const std::size_t D = D_;
  std::vector<ball> signed_part, local, A(D * D);
  split(w, signed_part, local);
  for (std::size_t i = 0; i < D; ++i) arb_add_error_mag(local[i].get(), b[i].m);
  set_.times(Phi1, A, prec_);
  std::vector<double> M(D * D);
  for (std::size_t q = 0; q < D * D; ++q) M[q] = arf_get_d(arb_midref(A[q].get()), ARF_RND_NEAR);
  // Where the two sets share their matrix and its condition is small, the balls' set takes the
  // same step (the same A, M' and inverse).
  const bool shared = balls_.M == set_.M;
  double condition = 0;
  if (!enclose_general_inverse(M, D, parallelepiped_condition, set_.Minv, &condition)) {
    condition = parallelepiped_condition * 2;
    orthogonal_factor(A, set_.v, M);
    if (!enclose_orthogonal_inverse(M, set_.Minv)) return false;
  }
  if (shared && condition <= balls_condition) {
    balls_.Minv = set_.Minv;
    move(balls_, A, M, local);
    move(set_, A, M, signed_part);
    return true;
  }
  move(set_, A, M, signed_part);
  // The balls' set: by mid(Phi Q) where its condition stays below balls_condition (the balls then
  // grow by at most that factor), else by mid(Phi Q) or a QR factor of it, whichever image is the
  // smaller.
  balls_.times(Phi1, A, prec_);
  for (std::size_t q = 0; q < D * D; ++q) M[q] = arf_get_d(arb_midref(A[q].get()), ARF_RND_NEAR);
  part by_parallelepiped = balls_;
  const bool parallelepiped =
      enclose_general_inverse(M, D, parallelepiped_condition, by_parallelepiped.Minv, &condition);
  if (parallelepiped) {
    move(by_parallelepiped, A, M, local);
    if (condition <= balls_condition) {
      balls_ = std::move(by_parallelepiped);
      return true;
    }
  }
  orthogonal_factor(A, balls_.v, M);
  if (!enclose_orthogonal_inverse(M, balls_.Minv)) return false;
  move(balls_, A, M, local);
  if (parallelepiped && !(balls_.width() < by_parallelepiped.width())) balls_ = std::move(by_parallelepiped);
  return true;
}

}  // namespace eulervop::detail
