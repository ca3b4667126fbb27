// Tests of include/eulervop/vop/torque_free_attitude.hpp: the closed-form torque-free motion,
// rates and attitude, against an independent integration of the 7-state system.
//
// Truth. The 7-state system I_i w_i' = (I_j - I_k) w_j w_k, q' = 1/2 q (x) (0, w) (body axes as
// listed, the direct form of design.md 1.7: no normalization, no axis permutation, no elliptic
// function) integrated by its Taylor series in MPFR (the raw C API, written here and sharing no
// code with the closed form). Coefficients by Cauchy products of the quadratic right-hand sides;
// order N = ceil((bits - 24) ln 2 / 2) + 1; each step h is set from the last two coefficients so
// that |c_n| h^n <= 2^(24 - bits) (Jorba & Zou's rule; h/R ~ e^-2, R the distance to the nearest
// complex singularity of sn, cn, dn), rounded down to a multiple of 2^-40 and cut to land exactly
// on each check time (the check times are quad numbers; every time reached is then exact in MPFR).
// The inputs are quad numbers, converted to MPFR exactly: the truth is the motion of exactly the
// quad inputs the closed form receives.
//   - quad comparisons: truth at 160 bits (N = 49; per-step truncation 2^-136 ~ 1e-41) over
//     100 rate periods. Its accuracy is not assumed: at every check time the closed form evaluated
//     in mpfr:256 from the same quad inputs, an independent computation, must agree with it to
//     1e-33, so the truth is good to ~1e-33 at worst, 1000 times below the quad bound. (Measured:
//     <= 1e-38 for the well-conditioned bodies, 5e-36 near the separatrix, where the motion
//     amplifies the truth's roundoff by ~1e8.) A 320-bit truth over 100 periods would take ~6 times
//     longer (4.5 ms per step at order 104 against 0.75 ms).
//   - mpfr:256 comparison (generic body): truth at 320 bits (N = 104, truncation 2^-296 per step),
//     over 10 rate periods only (about 330 steps, 1.5 s; 100 periods would take 15 s).
//
// Error measures: the rotation angle between the attitudes (core/quaternion.hpp rotation_angle,
// insensitive to q vs -q) and the two-norm |w - w_truth| in rad/s, computed in the truth's
// precision.
//
// Bounds and why they hold:
//   - quad, 100 periods, generic / minor-axis / small-k / axisymmetric bodies: <= 1e-30 rad and
//     rad/s. The closed form evaluates the phases w0 + d2 sqrt(A1A2A3) t, h t / I_p and
//     2 j Pi(n) directly at t; each carries a relative rounding of a few eps = 1.9e-34 of the phase,
//     so the error grows like eps times the angle turned (~1300 rad for the generic body after
//     100 periods: measured 3.2e-31, 1.8e-31 for the minor-axis body), and nothing accumulates
//     from step to step.
//   - quad near the separatrix (kappa = 1 - 1e-6): the bound 1e-30 is NOT reachable in quad by any
//     method, and is replaced by the problem's own conditioning: one ulp of one quad input
//     (w_i or I_i) moves the exact attitude after 100 periods by up to 5e-26 rad (the period
//     4K/(d2 sqrt(A1A2A3)) depends on the modulus like 1/(kappa kc^2 K), 1e5 times more than for
//     the generic body). Asserted: error <= 4 x the largest effect of a one-ulp input change
//     (measured 3.3e-26 rad against 4.9e-26), i.e. the closed form is backward stable. Full quad
//     precision of these inputs is reached by evaluating the closed form one precision up: the
//     mpfr:256 closed form agrees with the truth to <= 1e-33 (asserted).
//   - mpfr:256, generic body, 10 periods: <= 1e-70 (eps = 8.6e-78 times ~130 rad turned;
//     measured 1.3e-75). The relabelled bodies: <= 1e-30 in quad against the mapped truth (the
//     rounding of q0' adds ~1e-34), and the same inertial L to 1e-32.
//   - angular momentum: |q (I w) q* - L(0)| / |L(0)| <= 1e-31 in quad along every run (500
//     samples): a phase error moves q and w together along the orbit and leaves L unchanged, so only
//     the rounding of one evaluation (~10 eps) shows.
//   - steady rotations (a sphere, rest, each principal axis of a triaxial body, the intermediate
//     one included): quad <= 1e-30 against the truth at t = 10 and 50.
//   - the closed form's derivatives: in MPFR at 300 bits, for every regime (k < 1 and k > 1, both
//     signs, moments in even and odd orders, axisymmetric prolate and oblate, small modulus), central
//     differences (h = 1e-25, error ~h^2 ~ 1e-50) of q and w match 1/2 q (x) (0, w) and Euler's
//     equations to <= 1e-45, at t from 0 to 1234.5 (including many reductions of the phase).
//   - double against quad over 10 periods: <= 1e-12 (eps = 2.2e-16 times ~130 rad).
//   - k = 1 exactly (I = (1, 2.5, 3), A1 = A3 = 1/2, |w1| = |w3|) and moments <= 0 throw
//     std::domain_error; the intermediate-axis rotation, also k = 1, is steady and accepted.
//
// Run time (Release, 2 cores busy with other builds): about 11 s in all, most of it the Taylor
// truths (near the separatrix 4.6 s: 6651 steps, as the period is 4 times longer).
//
// Bodies (reference values, provenance): moments I = (1.1, 2.2, 3.3) (generic, near-separatrix,
// minor-axis, small-k), omega0 (rad/s) written below as decimals and rounded to quad, except the
// near-separatrix omega0 = sqrt(A) (c1 cn u0, c1 sn u0, c2 dn u0), c2 = 1, c1 = 1 - 1e-6, u0 = 0.5,
// computed here in MPFR at 400 bits (elliptic.hpp) and rounded to quad (the test checks that the
// resulting modulus is within [0.9e-6, 1.1e-6] of 1). q0 = (0.3, -0.5, 0.7, 0.2) normalized in
// quad. The relabelled generic bodies list the moments as (3.3, 1.1, 2.2) (axes e3, e1, e2: a
// rotation by 120 degrees about (1, 1, 1), q_R = (1, 1, 1, 1)/2) and (2.2, 1.1, 3.3) (axes e2, e1,
// -e3: a rotation by 180 degrees about (1, 1, 0), q_R = (0, 1, 1, 0)/sqrt 2), with w0' = R w0 and
// q0' = q0 (x) conj(q_R); they are compared with the generic body's truth mapped the same way.
#include <eulervop/vop/torque_free_attitude.hpp>

#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/special/elliptic.hpp>

#include <boost/math/constants/constants.hpp>
#include <gtest/gtest.h>
#include <mpfr.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using eulervop::mpfr_precision_scope;
using eulervop::mpfr_real;
using eulervop::quad;
using eulervop::quaternion;
using eulervop::torque_free_attitude;
using eulervop::vec3;

// ---------------------------------------------------------------------------------------------
// The truth: Taylor series of the 7-state system in MPFR.

// MPFR variables of one precision, initialized and cleared together.
class mpfr_block {
 public:
  mpfr_block(std::size_t n, mpfr_prec_t prec) : v_(n) {
    for (auto& x : v_) {
      mpfr_init2(&x, prec);
      mpfr_set_zero(&x, 1);
    }
  }
  ~mpfr_block() {
    for (auto& x : v_) mpfr_clear(&x);
  }
  mpfr_block(const mpfr_block&) = delete;
  mpfr_block& operator=(const mpfr_block&) = delete;
  mpfr_ptr operator[](std::size_t i) { return &v_[i]; }

 private:
  std::vector<__mpfr_struct> v_;
};

// y = (w1, w2, w3, q.w, q.x, q.y, q.z), t = 0 at the start.
class taylor_truth {
 public:
  taylor_truth(mpfr_prec_t bits, const std::array<mpfr_srcptr, 3>& I, const std::array<mpfr_srcptr, 7>& y0)
      : N_(static_cast<int>(std::ceil((static_cast<double>(bits) - 24) * 0.5 * std::log(2.0))) + 1),
        log2_tol_(24 - static_cast<double>(bits)),
        c_(7 * static_cast<std::size_t>(N_ + 1), bits),
        a_(3, bits),
        s_(4, bits) {
    for (int i = 0; i < 3; ++i) {
      mpfr_sub(s_[0], I[(i + 1) % 3], I[(i + 2) % 3], MPFR_RNDN);
      mpfr_div(a_[i], s_[0], I[i], MPFR_RNDN);
    }
    for (int c = 0; c < 7; ++c) mpfr_set(at(c, 0), y0[c], MPFR_RNDN);
  }

  long steps() const { return steps_; }
  mpfr_srcptr component(int c) { return at(c, 0); }

  // Advances to exactly `target` (>= the current time).
  void advance_to(mpfr_srcptr target) {
    mpfr_ptr t = s_[2];
    while (mpfr_cmp(t, target) < 0) {
      coefficients();
      double log2_h = 10;  // h <= 1024
      for (int n = N_ - 1; n <= N_; ++n) {
        double log2_c = -1e300;
        for (int c = 0; c < 7; ++c) {
          if (mpfr_zero_p(at(c, n))) continue;
          long e = 0;
          const double m = mpfr_get_d_2exp(&e, at(c, n), MPFR_RNDN);
          log2_c = std::max(log2_c, std::log2(std::fabs(m)) + static_cast<double>(e));
        }
        if (log2_c > -1e299) log2_h = std::min(log2_h, (log2_tol_ - log2_c) / n);
      }
      const double h = std::ldexp(std::floor(std::ldexp(std::exp2(log2_h), 40)), -40);
      mpfr_ptr step = s_[0];
      mpfr_set_d(step, h, MPFR_RNDN);
      mpfr_add(s_[1], t, step, MPFR_RNDN);  // exact: multiples of 2^-40 or of ulp(target)
      if (mpfr_cmp(s_[1], target) >= 0) {
        mpfr_sub(step, target, t, MPFR_RNDN);
        mpfr_set(t, target, MPFR_RNDN);
      } else {
        mpfr_set(t, s_[1], MPFR_RNDN);
      }
      for (int c = 0; c < 7; ++c) {  // Horner
        mpfr_ptr acc = s_[1];
        mpfr_set(acc, at(c, N_), MPFR_RNDN);
        for (int n = N_ - 1; n >= 0; --n) {
          mpfr_mul(acc, acc, step, MPFR_RNDN);
          mpfr_add(acc, acc, at(c, n), MPFR_RNDN);
        }
        mpfr_set(at(c, 0), acc, MPFR_RNDN);
      }
      ++steps_;
    }
  }

 private:
  mpfr_ptr at(int c, int n) { return c_[static_cast<std::size_t>(c * (N_ + 1) + n)]; }

  // acc +-= sum_{m=0}^{n} x[m] y[n-m]
  void cauchy(mpfr_ptr acc, int x, int y, int n, bool subtract) {
    mpfr_ptr p = s_[3];
    for (int m = 0; m <= n; ++m) {
      mpfr_mul(p, at(x, m), at(y, n - m), MPFR_RNDN);
      if (subtract)
        mpfr_sub(acc, acc, p, MPFR_RNDN);
      else
        mpfr_add(acc, acc, p, MPFR_RNDN);
    }
  }

  // Coefficients 1..N from coefficient 0: (n+1) w_i[n+1] = a_i (w_j w_k)[n],
  // 2 (n+1) q[n+1] = (q (x) (0, w))[n].
  void coefficients() {
    for (int n = 0; n < N_; ++n) {
      for (int i = 0; i < 3; ++i) {
        mpfr_ptr acc = at(i, n + 1);
        mpfr_set_zero(acc, 1);
        cauchy(acc, (i + 1) % 3, (i + 2) % 3, n, false);
        mpfr_mul(acc, acc, a_[i], MPFR_RNDN);
        mpfr_div_ui(acc, acc, static_cast<unsigned long>(n + 1), MPFR_RNDN);
      }
      mpfr_ptr w = at(3, n + 1), x = at(4, n + 1), y = at(5, n + 1), z = at(6, n + 1);
      for (mpfr_ptr r : {w, x, y, z}) mpfr_set_zero(r, 1);
      // (w, x, y, z) (x) (0, o1, o2, o3):
      //   w: -x o1 - y o2 - z o3;  x: w o1 + y o3 - z o2;  y: w o2 - x o3 + z o1;  z: w o3 + x o2 - y o1
      cauchy(w, 4, 0, n, true), cauchy(w, 5, 1, n, true), cauchy(w, 6, 2, n, true);
      cauchy(x, 3, 0, n, false), cauchy(x, 5, 2, n, false), cauchy(x, 6, 1, n, true);
      cauchy(y, 3, 1, n, false), cauchy(y, 4, 2, n, true), cauchy(y, 6, 0, n, false);
      cauchy(z, 3, 2, n, false), cauchy(z, 4, 1, n, false), cauchy(z, 5, 0, n, true);
      for (mpfr_ptr r : {w, x, y, z}) mpfr_div_ui(r, r, static_cast<unsigned long>(2 * (n + 1)), MPFR_RNDN);
    }
  }

  int N_;
  double log2_tol_;
  mpfr_block c_, a_, s_;  // s_: step, scratch, time, product
  long steps_ = 0;
};

struct state {
  vec3<mpfr_real> omega;
  quaternion<mpfr_real> q;
};

// The truth at each of `times` (increasing, >= 0), as mpfr_real of `bits` bits: call under an
// mpfr_precision_scope(bits), and compare under it.
std::vector<state> truth_at(unsigned bits, const vec3<quad>& I, const vec3<quad>& w0, const quaternion<quad>& q0,
                            const std::vector<quad>& times, long* steps = nullptr) {
  const mpfr_prec_t prec = static_cast<mpfr_prec_t>(eulervop::mpfr_effective_bits(bits));
  const std::array<mpfr_real, 3> Im = {mpfr_real(I[0]), mpfr_real(I[1]), mpfr_real(I[2])};
  const std::array<mpfr_real, 7> ym = {mpfr_real(w0[0]), mpfr_real(w0[1]), mpfr_real(w0[2]), mpfr_real(q0.w),
                                       mpfr_real(q0.x),  mpfr_real(q0.y),  mpfr_real(q0.z)};
  std::array<mpfr_srcptr, 3> Ip;
  std::array<mpfr_srcptr, 7> yp;
  for (int i = 0; i < 3; ++i) Ip[i] = Im[i].backend().data();
  for (int i = 0; i < 7; ++i) yp[i] = ym[i].backend().data();
  taylor_truth truth(prec, Ip, yp);
  std::vector<state> out;
  for (const quad& t : times) {
    const mpfr_real tm(t);  // exact
    truth.advance_to(tm.backend().data());
    std::array<mpfr_real, 7> y;
    for (int c = 0; c < 7; ++c) mpfr_set(y[c].backend().data(), truth.component(c), MPFR_RNDN);
    out.push_back({{y[0], y[1], y[2]}, {y[3], y[4], y[5], y[6]}});
  }
  if (steps) *steps = truth.steps();
  return out;
}

// ---------------------------------------------------------------------------------------------
// Conversions and error measures (in the current MPFR precision).

template <class T>
quaternion<mpfr_real> to_mpfr(const quaternion<T>& q) {
  return {mpfr_real(q.w), mpfr_real(q.x), mpfr_real(q.y), mpfr_real(q.z)};
}
template <class T>
vec3<mpfr_real> to_mpfr(const vec3<T>& v) {
  return {mpfr_real(v[0]), mpfr_real(v[1]), mpfr_real(v[2])};
}
template <class To>
quaternion<To> quaternion_from(const quaternion<quad>& q) {
  return {To(q.w), To(q.x), To(q.y), To(q.z)};
}
template <class To>
vec3<To> vec_from(const vec3<quad>& v) {
  return {To(v[0]), To(v[1]), To(v[2])};
}

double distance(const vec3<mpfr_real>& a, const vec3<mpfr_real>& b) {
  mpfr_real s = 0;
  for (int i = 0; i < 3; ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return static_cast<double>(sqrt(s));
}
double angle(const quaternion<mpfr_real>& a, const quaternion<mpfr_real>& b) {
  return static_cast<double>(eulervop::rotation_angle(a, b));
}

vec3<quad> quad_vec(const char* a, const char* b, const char* c) { return {quad(a), quad(b), quad(c)}; }

const quaternion<quad>& generic_q0() {
  static const quaternion<quad> q = eulervop::normalized(quaternion<quad>{quad("0.3"), quad("-0.5"), quad("0.7"), quad("0.2")});
  return q;
}

const vec3<quad> moments_123 = quad_vec("1.1", "2.2", "3.3");

// Check times: these fractions of t_end, rounded to quad.
std::vector<quad> check_times(const quad& t_end) {
  std::vector<quad> t;
  for (const char* f : {"0.0137", "0.1", "0.2311", "0.377", "0.5", "0.618", "0.7777", "0.9", "1"})
    t.push_back(t_end * quad(f));
  return t;
}

// max_t |q(t) (I w(t)) q(t)* - L| / |L| over `samples` times in [0, t_end] (quad).
double momentum_drift(const vec3<quad>& I, const torque_free_attitude<quad>& body, const quad& t_end, int samples = 500) {
  const vec3<quad>& L = body.angular_momentum();
  const quad Ln = sqrt(L[0] * L[0] + L[1] * L[1] + L[2] * L[2]);
  double worst = 0;
  for (int s = 0; s <= samples; ++s) {
    const quad t = t_end * s / samples;
    const vec3<quad> w = body.omega(t);
    const vec3<quad> Lt = eulervop::rotate(body.attitude(t), vec3<quad>{I[0] * w[0], I[1] * w[1], I[2] * w[2]});
    quad d = 0;
    for (int i = 0; i < 3; ++i) d += (Lt[i] - L[i]) * (Lt[i] - L[i]);
    worst = std::max(worst, static_cast<double>(sqrt(d) / Ln));
  }
  return worst;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The largest errors of the quad closed form (angle, |dw|) against the truth, and of the mpfr:256
// closed form from the same quad inputs (the truth's own check).
struct errors {
  double quad_angle = 0, quad_omega = 0, mpfr_angle = 0, mpfr_omega = 0;
};

constexpr unsigned quad_truth_bits = 160;

// The closed form in quad and in mpfr:256 against the truth (160 bits) at check_times(t_end),
// printed and returned; the truth too, when asked.
errors compare_quad(const char* name, const vec3<quad>& I, const vec3<quad>& w0, const quaternion<quad>& q0,
                    const quad& t_end, std::vector<state>* truth_out = nullptr) {
  const auto start = std::chrono::steady_clock::now();
  const torque_free_attitude<quad> body(I, w0, q0);
  const std::vector<quad> times = check_times(t_end);
  std::optional<torque_free_attitude<mpfr_real>> wide;
  {
    mpfr_precision_scope s256(256);
    wide.emplace(vec_from<mpfr_real>(I), vec_from<mpfr_real>(w0), quaternion_from<mpfr_real>(q0));
  }
  mpfr_precision_scope scope(quad_truth_bits);
  long steps = 0;
  const std::vector<state> truth = truth_at(quad_truth_bits, I, w0, q0, times, &steps);
  errors e;
  for (std::size_t i = 0; i < times.size(); ++i) {
    const quad& t = times[i];
    e.quad_angle = std::max(e.quad_angle, angle(truth[i].q, to_mpfr(body.attitude(t))));
    e.quad_omega = std::max(e.quad_omega, distance(truth[i].omega, to_mpfr(body.omega(t))));
    quaternion<mpfr_real> qw;
    vec3<mpfr_real> ww;
    {
      mpfr_precision_scope s256(256);
      qw = wide->attitude(mpfr_real(t));
      ww = wide->omega(mpfr_real(t));
    }
    e.mpfr_angle = std::max(e.mpfr_angle, angle(truth[i].q, qw));
    e.mpfr_omega = std::max(e.mpfr_omega, distance(truth[i].omega, ww));
  }
  std::printf("%-26s t_end %9.3f (%ld Taylor steps): quad angle %.2e rad, |dw| %.2e; mpfr:256 angle %.2e, |dw| %.2e; "
              "%.2f s\n",
              name, static_cast<double>(t_end), steps, e.quad_angle, e.quad_omega, e.mpfr_angle, e.mpfr_omega,
              seconds_since(start));
  if (truth_out) *truth_out = truth;
  return e;
}

// ---------------------------------------------------------------------------------------------

// The generic body in quad over 100 rate periods, and the same body with its axes relabelled
// (an even and an odd permutation): the same inertial motion.
TEST(TorqueFreeAttitude, GenericBodyInQuadOver100PeriodsAndRelabelledAxes) {
  const vec3<quad> w0 = quad_vec("0.9", "-0.45", "0.6");
  const quaternion<quad>& q0 = generic_q0();
  const torque_free_attitude<quad> body(moments_123, w0, q0);
  ASSERT_EQ(body.kind(), torque_free_attitude<quad>::motion::triaxial);
  EXPECT_FALSE(body.minor_axis());
  const quad t_end = 100 * body.rates_period();
  std::vector<state> truth;
  const errors e = compare_quad("generic (1.1, 2.2, 3.3)", moments_123, w0, q0, t_end, &truth);
  EXPECT_LE(e.mpfr_angle, 1e-33);
  EXPECT_LE(e.mpfr_omega, 1e-33);
  EXPECT_LE(e.quad_angle, 1e-30);
  EXPECT_LE(e.quad_omega, 1e-30);
  const double drift = momentum_drift(moments_123, body, t_end);
  std::printf("  angular momentum drift %.2e\n", drift);
  EXPECT_LE(drift, 1e-31);

  // Relabellings: v' = R v, q' = q (x) conj(q_R).
  struct relabelling {
    const char* name;
    std::array<int, 3> from;    // listed axis i is the generic body's axis from[i] ...
    std::array<int, 3> sign;    // ... times sign[i]
    quaternion<quad> qR;        // v' = q_R v q_R*
  };
  const quad half = quad(1) / 2, r2 = sqrt(quad(2)) / 2;
  const relabelling cases[] = {
      {"relabelled (3.3, 1.1, 2.2)", {2, 0, 1}, {1, 1, 1}, {half, half, half, half}},
      {"relabelled (2.2, 1.1, 3.3)", {1, 0, 2}, {1, 1, -1}, {quad(0), r2, r2, quad(0)}},
  };
  const std::vector<quad> times = check_times(t_end);
  for (const relabelling& r : cases) {
    vec3<quad> I, w;
    for (int i = 0; i < 3; ++i) {
      I[i] = moments_123[r.from[i]];
      w[i] = r.sign[i] * w0[r.from[i]];
    }
    // q_R really is the relabelling: q_R e_j q_R* = R e_j.
    for (int j = 0; j < 3; ++j) {
      vec3<quad> ej{}, Re{};
      ej[j] = 1;
      for (int i = 0; i < 3; ++i) Re[i] = r.from[i] == j ? quad(r.sign[i]) : quad(0);
      const vec3<quad> got = eulervop::rotate(r.qR, ej);
      for (int i = 0; i < 3; ++i) ASSERT_LE(abs(got[i] - Re[i]), 1e-33) << r.name;
    }
    const quaternion<quad> q0r = q0 * eulervop::conjugate(r.qR);
    const torque_free_attitude<quad> relabelled(I, w, q0r);
    mpfr_precision_scope scope(quad_truth_bits);
    const quaternion<mpfr_real> qR = to_mpfr(r.qR);
    double ea = 0, ew = 0;
    for (std::size_t k = 0; k < times.size(); ++k) {
      vec3<mpfr_real> wt;
      for (int i = 0; i < 3; ++i) wt[i] = r.sign[i] * truth[k].omega[r.from[i]];
      ea = std::max(ea, angle(truth[k].q * eulervop::conjugate(qR), to_mpfr(relabelled.attitude(times[k]))));
      ew = std::max(ew, distance(wt, to_mpfr(relabelled.omega(times[k]))));
    }
    const vec3<mpfr_real> dL = to_mpfr(relabelled.angular_momentum());
    const double Ldiff = distance(dL, to_mpfr(body.angular_momentum()));
    std::printf("%-26s quad angle %.2e rad, |dw| %.2e; |L' - L| %.2e\n", r.name, ea, ew, Ldiff);
    EXPECT_LE(ea, 1e-30) << r.name;
    EXPECT_LE(ew, 1e-30) << r.name;
    EXPECT_LE(Ldiff, 1e-32) << r.name;
  }
}

// The generic body in mpfr:256 against a 320-bit truth, over 10 rate periods.
TEST(TorqueFreeAttitude, GenericBodyInMpfr256Over10Periods) {
  const auto start = std::chrono::steady_clock::now();
  const vec3<quad> w0 = quad_vec("0.9", "-0.45", "0.6");
  const quaternion<quad>& q0 = generic_q0();
  std::optional<torque_free_attitude<mpfr_real>> body;
  mpfr_real period;
  {
    mpfr_precision_scope s256(256);
    body.emplace(vec_from<mpfr_real>(moments_123), vec_from<mpfr_real>(w0), quaternion_from<mpfr_real>(q0));
    period = body->rates_period();
  }
  const quad t_end = 10 * quad(period);
  const std::vector<quad> times = check_times(t_end);
  mpfr_precision_scope scope(320);
  long steps = 0;
  const std::vector<state> truth = truth_at(320, moments_123, w0, q0, times, &steps);
  double ea = 0, ew = 0;
  for (std::size_t k = 0; k < times.size(); ++k) {
    quaternion<mpfr_real> q;
    vec3<mpfr_real> w;
    {
      mpfr_precision_scope s256(256);
      q = body->attitude(mpfr_real(times[k]));
      w = body->omega(mpfr_real(times[k]));
    }
    ea = std::max(ea, angle(truth[k].q, q));
    ew = std::max(ew, distance(truth[k].omega, w));
  }
  std::printf("generic, mpfr:256, t_end %.3f (%ld Taylor steps at 320 bits): angle %.2e rad, |dw| %.2e; %.2f s\n",
              static_cast<double>(t_end), steps, ea, ew, seconds_since(start));
  EXPECT_LE(ea, 1e-70);
  EXPECT_LE(ew, 1e-70);
}

// Near the separatrix (kappa = 1 - 1e-6): quad is as accurate as its inputs allow, and the closed
// form one precision up reaches full quad precision.
TEST(TorqueFreeAttitude, NearSeparatrixIsBackwardStableInQuad) {
  vec3<quad> w0;
  {
    mpfr_precision_scope s(400);
    const eulervop::physical_scaling<mpfr_real> scaling{eulervop::principal_axes<mpfr_real>(vec_from<mpfr_real>(moments_123))};
    const mpfr_real c2 = 1, c1 = 1 - mpfr_real("1e-6");
    const auto j = eulervop::jacobi_eval(mpfr_real("0.5"), eulervop::elliptic_modulus<mpfr_real>(c1 / c2));
    const vec3<mpfr_real> w = scaling.omega_of_Omega({c1 * j.cn, c1 * j.sn, c2 * j.dn});
    for (int i = 0; i < 3; ++i) w0[i] = quad(w[i]);
  }
  const quaternion<quad>& q0 = generic_q0();
  const torque_free_attitude<quad> body(moments_123, w0, q0);
  ASSERT_EQ(body.kind(), torque_free_attitude<quad>::motion::triaxial);
  EXPECT_GE(1 - body.modulus(), 0.9e-6);
  EXPECT_LE(1 - body.modulus(), 1.1e-6);
  const quad t_end = 100 * body.rates_period();
  const errors e = compare_quad("near separatrix", moments_123, w0, q0, t_end);
  EXPECT_LE(e.mpfr_angle, 1e-33);
  EXPECT_LE(e.mpfr_omega, 1e-33);

  // The conditioning: the largest change of the exact motion at t_end when one quad input moves
  // by one ulp (closed form in mpfr:256, which the truth has just confirmed).
  double spread_angle = 0, spread_omega = 0;
  {
    mpfr_precision_scope s256(256);
    const auto make = [&](const vec3<quad>& I, const vec3<quad>& w) {
      return torque_free_attitude<mpfr_real>(vec_from<mpfr_real>(I), vec_from<mpfr_real>(w), quaternion_from<mpfr_real>(q0));
    };
    const auto base = make(moments_123, w0);
    const mpfr_real t(t_end);
    const auto qb = base.attitude(t);
    const auto wb = base.omega(t);
    for (int input = 0; input < 6; ++input) {
      vec3<quad> I = moments_123, w = w0;
      quad& x = input < 3 ? w[input] : I[input - 3];
      x = boost::multiprecision::nextafter(x, quad(10));
      const auto p = make(I, w);
      spread_angle = std::max(spread_angle, angle(qb, p.attitude(t)));
      spread_omega = std::max(spread_omega, distance(wb, p.omega(t)));
    }
  }
  std::printf("  one-ulp input changes move the exact motion at t_end by up to %.2e rad, %.2e rad/s\n", spread_angle,
              spread_omega);
  EXPECT_LE(e.quad_angle, 4 * spread_angle);
  EXPECT_LE(e.quad_omega, 4 * spread_omega);
  const double drift = momentum_drift(moments_123, body, t_end);
  std::printf("  angular momentum drift %.2e\n", drift);
  EXPECT_LE(drift, 1e-31);
}

// k > 1: rotation near the minor axis, the reciprocal-modulus regime; and tiny moduli in both
// regimes (nearly steady rotation about the major and the minor axis).
TEST(TorqueFreeAttitude, MinorAxisAndSmallModuliInQuadOver100Periods) {
  struct body_case {
    const char* name;
    vec3<quad> w0;
    bool minor;
  };
  const body_case cases[] = {
      {"minor axis (k > 1)", quad_vec("1.2", "0.3", "0.25"), true},
      {"small k (major axis)", quad_vec("1e-6", "2e-6", "0.6"), false},
      {"small 1/k (minor axis)", quad_vec("0.6", "2e-6", "1e-6"), true},
  };
  for (const body_case& c : cases) {
    const torque_free_attitude<quad> body(moments_123, c.w0, generic_q0());
    ASSERT_EQ(body.kind(), torque_free_attitude<quad>::motion::triaxial) << c.name;
    EXPECT_EQ(body.minor_axis(), c.minor) << c.name;
    const quad t_end = 100 * body.rates_period();
    const errors e = compare_quad(c.name, moments_123, c.w0, generic_q0(), t_end);
    EXPECT_LE(e.mpfr_angle, 1e-33) << c.name;
    EXPECT_LE(e.mpfr_omega, 1e-33) << c.name;
    EXPECT_LE(e.quad_angle, 1e-30) << c.name;
    EXPECT_LE(e.quad_omega, 1e-30) << c.name;
    const double drift = momentum_drift(moments_123, body, t_end);
    std::printf("  angular momentum drift %.2e\n", drift);
    EXPECT_LE(drift, 1e-31) << c.name;
  }
}

// Axisymmetric bodies, prolate (1, 1, 2) and oblate with the symmetry axis listed second
// (2, 1, 2), over 100 precession periods 2 pi I_perp / h.
TEST(TorqueFreeAttitude, AxisymmetricBodiesInQuadOver100PrecessionPeriods) {
  const vec3<quad> w0 = quad_vec("0.9", "-0.45", "0.6");
  for (const vec3<quad>& I : {quad_vec("1", "1", "2"), quad_vec("2", "1", "2")}) {
    const torque_free_attitude<quad> body(I, w0, generic_q0());
    ASSERT_EQ(body.kind(), torque_free_attitude<quad>::motion::axisymmetric);
    const int perp = I[0] == I[1] ? 0 : 1;
    quad h2 = 0;
    for (int i = 0; i < 3; ++i) h2 += I[i] * w0[i] * I[i] * w0[i];
    const quad t_end = 100 * 2 * boost::math::constants::pi<quad>() * I[perp] / sqrt(h2);
    const std::string name = "axisymmetric (" + std::to_string(static_cast<int>(I[0])) + ", " +
                             std::to_string(static_cast<int>(I[1])) + ", " + std::to_string(static_cast<int>(I[2])) + ")";
    const errors e = compare_quad(name.c_str(), I, w0, generic_q0(), t_end);
    EXPECT_LE(e.mpfr_angle, 1e-33) << name;
    EXPECT_LE(e.mpfr_omega, 1e-33) << name;
    EXPECT_LE(e.quad_angle, 1e-30) << name;
    EXPECT_LE(e.quad_omega, 1e-30) << name;
    const double drift = momentum_drift(I, body, t_end);
    std::printf("  angular momentum drift %.2e\n", drift);
    EXPECT_LE(drift, 1e-31) << name;
  }
}

// Steady rotations, each exact: a sphere, a body at rest, and a triaxial body spinning about each
// principal axis (the intermediate one, on the separatrix, included).
TEST(TorqueFreeAttitude, SteadyRotationsAreExact) {
  using motion = torque_free_attitude<quad>::motion;
  struct steady_case {
    const char* name;
    vec3<quad> I, w0;
    motion kind;
  };
  const steady_case cases[] = {
      {"sphere", quad_vec("2", "2", "2"), quad_vec("0.9", "-0.45", "0.6"), motion::steady},
      {"at rest", moments_123, quad_vec("0", "0", "0"), motion::steady},
      {"major axis", moments_123, quad_vec("0", "0", "-0.6"), motion::steady},
      {"intermediate axis", moments_123, quad_vec("0", "0.45", "0"), motion::steady},
      {"minor axis", moments_123, quad_vec("0.7", "0", "0"), motion::steady},
      // The axisymmetric formula, with its spin and precession about the same axis.
      {"axisymmetric, along e_p", quad_vec("1", "1", "2"), quad_vec("0", "0", "0.6"), motion::axisymmetric},
      {"axisymmetric, across e_p", quad_vec("1", "1", "2"), quad_vec("0.3", "-0.2", "0"), motion::axisymmetric},
  };
  const std::vector<quad> times = {quad(10), quad(50)};
  for (const steady_case& c : cases) {
    const torque_free_attitude<quad> body(c.I, c.w0, generic_q0());
    EXPECT_EQ(body.kind(), c.kind) << c.name;
    mpfr_precision_scope scope(quad_truth_bits);
    const std::vector<state> truth = truth_at(quad_truth_bits, c.I, c.w0, generic_q0(), times);
    for (std::size_t k = 0; k < times.size(); ++k) {
      EXPECT_LE(angle(truth[k].q, to_mpfr(body.attitude(times[k]))), 1e-30) << c.name;
      EXPECT_LE(distance(truth[k].omega, to_mpfr(body.omega(times[k]))), 1e-30) << c.name;
    }
  }
}

// In MPFR at 300 bits, in every regime: q(0) = q0, w(0) = w0, and central differences of the
// closed form satisfy q' = 1/2 q (x) (0, w) and Euler's equations at t up to 1234.5.
TEST(TorqueFreeAttitude, DerivativesSatisfyTheEquationsOfMotionInEveryRegime) {
  mpfr_precision_scope scope(300);
  using R = mpfr_real;
  const auto v = [](const char* a, const char* b, const char* c) { return vec3<R>{R(a), R(b), R(c)}; };
  struct regime {
    const char* name;
    vec3<R> I, w0;
  };
  const regime regimes[] = {
      {"k<1, sigma +1", v("1", "2", "3"), v("0.9", "-0.45", "0.6")},
      {"k<1, sigma -1", v("1", "2", "3"), v("0.9", "-0.45", "-0.6")},
      {"k>1, sigma +1", v("1", "2", "3"), v("1.2", "0.3", "0.25")},
      {"k>1, sigma -1", v("1", "2", "3"), v("-1.2", "0.3", "0.25")},
      {"(3, 1, 2), k<1", v("3", "1", "2"), v("0.6", "0.9", "-0.45")},
      {"(2, 1, 3), k<1", v("2", "1", "3"), v("-0.45", "0.9", "-0.6")},
      {"(2, 1, 3), k>1", v("2", "1", "3"), v("0.3", "-1.2", "0.25")},
      {"(3, 2, 1), k>1", v("3", "2", "1"), v("0.3", "0.3", "-1.2")},
      {"near the separatrix", v("1", "2", "3"), v("0.70710678", "0.1", "0.40824829")},
      {"small k", v("1", "2", "3"), v("1e-20", "1e-21", "0.6")},
      {"small 1/k", v("1", "2", "3"), v("0.6", "1e-21", "1e-20")},
      {"axisymmetric (1, 1, 2)", v("1", "1", "2"), v("0.9", "-0.45", "0.6")},
      {"axisymmetric (2, 2, 1)", v("2", "2", "1"), v("0.9", "-0.45", "0.6")},
      {"axisymmetric (2, 1, 2)", v("2", "1", "2"), v("0.9", "-0.45", "0.6")},
  };
  const quaternion<R> q0 = eulervop::normalized(quaternion<R>{R("0.3"), R("-0.5"), R("0.7"), R("0.2")});
  const R h("1e-25");
  for (const regime& r : regimes) {
    const torque_free_attitude<R> body(r.I, r.w0, q0);
    EXPECT_LE(angle(body.attitude(R(0)), q0), 1e-85) << r.name;
    EXPECT_LE(distance(body.omega(R(0)), r.w0), 1e-85) << r.name;
    double worst_q = 0, worst_w = 0;
    for (const char* ts : {"0.3", "1.7", "5.5", "13.1", "77.7", "1234.5"}) {
      const R t(ts);
      const quaternion<R> qp = body.attitude(t + h), qm = body.attitude(t - h), q = body.attitude(t);
      const vec3<R> w = body.omega(t), wp = body.omega(t + h), wm = body.omega(t - h);
      const quaternion<R> dq = eulervop::attitude_rate(q, w);
      const R d[4] = {(qp.w - qm.w) / (2 * h) - dq.w, (qp.x - qm.x) / (2 * h) - dq.x, (qp.y - qm.y) / (2 * h) - dq.y,
                      (qp.z - qm.z) / (2 * h) - dq.z};
      for (const R& x : d) worst_q = std::max(worst_q, static_cast<double>(abs(x)));
      for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3, k = (i + 2) % 3;
        const R euler = (r.I[j] - r.I[k]) / r.I[i] * w[j] * w[k];
        worst_w = std::max(worst_w, static_cast<double>(abs((wp[i] - wm[i]) / (2 * h) - euler)));
      }
    }
    EXPECT_LE(worst_q, 1e-45) << r.name;
    EXPECT_LE(worst_w, 1e-45) << r.name;
  }
}

// The separatrix itself (k = 1 exactly) is refused; so are moments that are not positive.
// I = (1, 2.5, 3) has A1 = A3 = 1/2 exactly, so w1 = +-w3 gives c1 = c2 exactly.
TEST(TorqueFreeAttitude, RefusesTheSeparatrixAndBadMoments) {
  const vec3<quad> I = quad_vec("1", "2.5", "3");
  EXPECT_THROW(torque_free_attitude<quad>(I, quad_vec("0.5", "0.3", "0.5"), generic_q0()), std::domain_error);
  EXPECT_THROW(torque_free_attitude<quad>(I, quad_vec("0.5", "0.3", "-0.5"), generic_q0()), std::domain_error);
  EXPECT_THROW(torque_free_attitude<quad>(I, quad_vec("0.5", "0", "0.5"), generic_q0()), std::domain_error);
  EXPECT_NO_THROW(torque_free_attitude<quad>(I, quad_vec("0", "0.3", "0"), generic_q0()));  // steady
  EXPECT_NO_THROW(torque_free_attitude<quad>(I, quad_vec("0.5", "0.3", "0.4999"), generic_q0()));
  EXPECT_THROW(torque_free_attitude<quad>(quad_vec("0", "1", "2"), quad_vec("0.5", "0.3", "0.5"), generic_q0()),
               std::domain_error);
  EXPECT_THROW(torque_free_attitude<quad>(quad_vec("-1", "1", "2"), quad_vec("0.5", "0.3", "0.5"), generic_q0()),
               std::domain_error);
}

// double: the same closed form, to double precision (against quad, 10 periods).
TEST(TorqueFreeAttitude, DoubleAgreesWithQuad) {
  const vec3<quad> w0 = quad_vec("0.9", "-0.45", "0.6");
  const torque_free_attitude<quad> qbody(moments_123, w0, generic_q0());
  const torque_free_attitude<double> dbody(vec3<double>{1.1, 2.2, 3.3}, vec3<double>{0.9, -0.45, 0.6},
                                           quaternion<double>{static_cast<double>(generic_q0().w),
                                                              static_cast<double>(generic_q0().x),
                                                              static_cast<double>(generic_q0().y),
                                                              static_cast<double>(generic_q0().z)});
  const double t_end = 10 * static_cast<double>(qbody.rates_period());
  for (int s = 0; s <= 50; ++s) {
    const double t = t_end * s / 50;
    const quaternion<double> qd = dbody.attitude(t);
    const quaternion<quad> qq = qbody.attitude(quad(t));
    EXPECT_LE(static_cast<double>(eulervop::rotation_angle(qq, quaternion<quad>{quad(qd.w), quad(qd.x), quad(qd.y), quad(qd.z)})),
              1e-12);
    const vec3<double> wd = dbody.omega(t);
    const vec3<quad> wq = qbody.omega(quad(t));
    for (int i = 0; i < 3; ++i) EXPECT_LE(std::fabs(wd[i] - static_cast<double>(wq[i])), 1e-12);
  }
}

}  // namespace
