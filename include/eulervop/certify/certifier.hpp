// A proven bound on the distance between the reference of Eq. 5 and the exact solution
// (docs/certified.md explains the method and what it assumes).
//
// The reference is a continuous-in-spirit piecewise polynomial P: on each segment, the degree-N
// interpolant of the stored node values (chebyshev_segment). Those values define P exactly, so
// everything below is a statement about a known polynomial, checked in interval arithmetic with
// outward rounding (MPFI) at a working precision above the reference's. Per segment:
//   1. P's coefficients are enclosed (detail/node_transform.hpp, detail/segment_polynomial.hpp),
//      and its Picard residual r(tau) = P(a) + int_a^tau f(P) - P(tau), a polynomial of degree
//      2N + 1 as f is quadratic, with them (detail/picard_residual.hpp);
//   2. the error e = y - P obeys e(tau) = e(a) + r(tau) + int_a^tau (J e + N(e)), J = DN(P) and N
//      the quadratic part; a Gronwall argument gives an a-priori bound R of |e| on the segment
//      (detail/a_priori_bound.hpp, with the problem's bounds of J and N, model/euler_problem.hpp);
//   3. integrating by parts with the variational matrix Phi' = J Phi (Phi(a) = I),
//        e(b) = Phi(b, a) e(a) + r(b) + int_a^b Phi(b, s) [J(s) r(s) + N(e(s))] ds,
//      where Phi(b, a) and the signed term int Phi J r are computed in double and enclosed by
//      their own Picard residuals (detail/variational_matrix.hpp,
//      detail/signed_integral_term.hpp);
//   4. e(a) is kept as a parallelepiped B [x] and moved across segments by Lohner's QR method
//      (detail/lohner_box.hpp), so the bound grows like the flow's sensitivity rather than like
//      exp(int mu).
// A row inside a segment gets row_enclosure.hpp's bound; a physical scene's rows in rad/s,
// omega_radius.hpp's.
//
// Steps 1, 3 and 4 and the bounds of J do not depend on the segments before (prepared_segment);
// only e(a), the a-priori bound and the box do (certifier::advance). A caller may prepare
// segments on other threads and advance them in order; add_segment does both in turn.
#pragma once

#include <eulervop/certify/detail/a_priori_bound.hpp>
#include <eulervop/certify/detail/bounded_chebyshev.hpp>
#include <eulervop/certify/detail/linearized_flow.hpp>
#include <eulervop/certify/detail/lohner_box.hpp>
#include <eulervop/certify/detail/node_transform.hpp>
#include <eulervop/certify/detail/picard_residual.hpp>
#include <eulervop/certify/detail/segment_polynomial.hpp>
#include <eulervop/certify/detail/signed_integral_term.hpp>
#include <eulervop/certify/detail/variational_matrix.hpp>
#include <eulervop/certify/exact_problem.hpp>
#include <eulervop/certify/interval.hpp>
#include <eulervop/certify/row_enclosure.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/torque.hpp>
#include <eulervop/reference/segment.hpp>

#include <mpfi.h>
#include <mpfr.h>

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace eulervop {

// The part of one segment's check that does not depend on the segments before it (steps 1, 3
// and 4 above, and the bounds of J): P enclosed, its residual, Phi and u. It owns all its scratch,
// so checks of different segments may be prepared on different threads.
class prepared_segment {
 public:
  prepared_segment(mpfr_prec_t bits, std::size_t degree, const detail::node_transform& transform,
                   std::shared_ptr<const detail::integral_term_nodes> nodes, const exact_problem& problem,
                   const detail::jacobian_rows& rows);

  // Fails (numerical_failure, certification_failed) on a value that is not finite.
  template <scalar T>
  void prepare(const chebyshev_segment<T>& seg);

  detail::segment_polynomial P;
  detail::picard_residual residual;
  detail::segment_bounds bounds;  // mu, jmax, rsup2 here; rho_a, R and ell in certifier::advance
  detail::variational_matrix phi;
  detail::signed_integral_term u;

 private:
  exact_problem problem_;
  detail::jacobian_rows rows_;
  detail::node_transform transform_;
  detail::integrated_products sums_;
};

inline prepared_segment::prepared_segment(mpfr_prec_t bits, std::size_t degree,
                                          const detail::node_transform& transform,
                                          std::shared_ptr<const detail::integral_term_nodes> nodes,
                                          const exact_problem& problem, const detail::jacobian_rows& rows)
    : P(bits, degree), residual(bits, degree, problem.torque.G, unit_coefficients(problem)),
      u(std::move(nodes)), problem_(problem), rows_(rows), transform_(transform) {}

template <scalar T>
void prepared_segment::prepare(const chebyshev_segment<T>& seg) {
  P.place(seg);
  P.load(seg);
  P.enclose(transform_);
  residual.compute(P);
  bounds.linear(problem_, P, residual.rsup);
  const detail::linear_growth growth = bounds.growth(P);
  phi.compute(P, rows_, growth, sums_);
  u.compute(P, residual, phi, rows_, growth, sums_);
}

class certifier {
 public:
  using check = prepared_segment;
  // `bits`: the working precision (the reference's bits + 64 or more); `degree`: the reference's
  // N; `problem`: the exact data (exact_problem.hpp), with coefficients a of -1, 0 or 1
  // (std::invalid_argument otherwise), as Eq. 5. Only a constant torque is certified: the
  // residual's f is then quadratic, and the bounds of J hold.
  template <class Torque>
    requires is_constant_torque_v<Torque>
  certifier(mpfr_prec_t bits, std::size_t degree, const euler_problem<interval, Torque>& problem);

  // Checks the next accepted segment of the reference (in order) and moves the error bound to
  // its end. Throws numerical_failure (certification_failed) where the bound cannot be proven.
  template <scalar T>
  void add_segment(const chebyshev_segment<T>& seg) {
    if (!spare_) spare_ = make_segment();
    spare_->prepare(seg);
    spare_ = advance(std::move(spare_));
  }

  // The same in two parts, for callers that prepare on other threads: an empty check (safe to
  // call from any thread, as it only reads what the constructor set), and the next segment's
  // prepared check, in order. advance returns the previous segment's check, for reuse (null at
  // the first). Rows then refer to the latest advanced segment.
  std::unique_ptr<prepared_segment> make_segment() const {
    return std::make_unique<prepared_segment>(bits_, degree_, transform_, integral_nodes_, problem_, jacobian_);
  }
  std::unique_ptr<prepared_segment> advance(std::unique_ptr<prepared_segment> prepared);

  // The enclosure at tau in the latest segment.
  template <scalar T>
  row_enclosure enclose(const T& tau) const {
    return detail::enclose_row(tau, problem_, current_->P, current_->bounds);
  }

  // An upper bound of |y(tau) - printed|_2 (Eq. 20's norm), for tau in the latest segment, the
  // row printed as the decimals `printed` (three texts). Also raises max_radius().
  template <scalar T>
  interval row_radius(const T& tau, const std::array<std::string, 3>& printed) {
    return row_radius(enclose(tau), printed);
  }
  // The same from an enclosure at that tau.
  interval row_radius(const row_enclosure& at, const std::array<std::string, 3>& printed) {
    interval out = eulervop::row_radius(at, printed);
    mpfi_put(max_radius_.get(), out.get());
    return out;
  }

  // The largest row radius so far (an upper bound: the interval's right end).
  const interval& max_radius() const { return max_radius_; }

 private:
  template <class Torque>
  static exact_problem with_constant_torque(const euler_problem<interval, Torque>& problem);

  mpfr_prec_t bits_;
  std::size_t degree_;
  exact_problem problem_;
  detail::jacobian_rows jacobian_;
  detail::node_transform transform_;  // copied into every check
  std::shared_ptr<const detail::integral_term_nodes> integral_nodes_;  // shared by every check
  std::unique_ptr<prepared_segment> current_, spare_;
  // The box and the ball that widens it hold errors far below the state: detail::error_bits.
  detail::lohner_box box_;
  // The joins: P(b) of the previous segment and b, exactly.
  std::vector<interval> prev_end_;
  interval prev_b_;
  bool started_ = false;
  interval ball_, scratch_, max_radius_;
};

template <class Torque>
  requires is_constant_torque_v<Torque>
certifier::certifier(mpfr_prec_t bits, std::size_t degree, const euler_problem<interval, Torque>& problem)
    : bits_(bits), degree_(degree), problem_(with_constant_torque(problem)),
      jacobian_(detail::jacobian_pattern(unit_coefficients(problem_))), transform_(bits, degree),
      integral_nodes_(std::make_shared<const detail::integral_term_nodes>(degree)), box_(detail::error_bits),
      prev_end_(3, interval::zero(bits)), prev_b_(interval::zero(bits)), ball_(interval::zero(detail::error_bits)),
      scratch_(interval::zero(detail::error_bits)), max_radius_(interval::zero(bits)) {}

// The problem with its torque as the one vector it is.
template <class Torque>
exact_problem certifier::with_constant_torque(const euler_problem<interval, Torque>& problem) {
  const interval_precision_scope scope(problem.Omega0[0].bits());
  exact_problem p;
  p.torque.G = problem.torque.value(problem.tau0, problem.Omega0);
  p.Omega0 = problem.Omega0;
  p.tau0 = problem.tau0;
  p.form = problem.form;
  p.a = problem.a;
  return p;
}

inline std::unique_ptr<prepared_segment> certifier::advance(std::unique_ptr<prepared_segment> prepared) {
  prepared_segment& c = *prepared;
  detail::segment_polynomial& P = c.P;
  // The segment must start exactly where the previous one ended (a + 2 hl, exact at these bits).
  if (started_ && !detail::same_point(prev_b_, P.a)) P.fail(outcome_kind::certify_segment_gap);
  // The error at the start: the scene's exact initial state minus P(a), or the previous box
  // plus the jump between the two segments' polynomials there (TwoSum compensation leaves one).
  if (!started_) {
    box_.start(problem_.Omega0, P);
  } else {
    for (int i = 0; i < 3; ++i) {
      mpfi_sub(prev_end_[i].get(), prev_end_[i].get(), P.X0[i].get());
      mpfi_sub(prev_end_[i].get(), prev_end_[i].get(), P.v_first[i].get());
    }
    box_.join(prev_end_);
  }
  box_.norm(c.bounds.rho_a);
  c.bounds.a_priori(problem_, P);
  // The local part's ball: the quadratic term, and the errors of Phi (times |e(a)|) and of u.
  mpfi_mul(ball_.get(), c.phi.eps.get(), c.bounds.rho_a.get());
  mpfi_add(ball_.get(), ball_.get(), c.bounds.ell.get());
  mpfi_add(ball_.get(), ball_.get(), c.u.eps.get());
  detail::to_symmetric_hull(ball_, scratch_);
  box_.step(c.phi.Phi1, c.residual.r1, c.u.u1, ball_, P);
  for (int i = 0; i < 3; ++i) mpfi_add(prev_end_[i].get(), P.X0[i].get(), P.v_last[i].get());
  mpfi_add(prev_b_.get(), P.a.get(), P.h.get());
  started_ = true;
  std::swap(current_, prepared);
  return prepared;
}

}  // namespace eulervop
