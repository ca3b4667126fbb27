// The reference's attitude (reference/attitude_cascade.hpp) against the exact torque-free motion
// (vop/torque_free_attitude.hpp), and its invariant.
//
// Truth: the closed form (Landau's precession angle through Boost.Math's elliptic integral of the
// third kind; itself checked against MPFR Taylor integrations of the 7-state system in
// tests/test_torque_free_attitude.cpp), evaluated in mpfr:256 from the same inputs as the quad
// run (the quad decimals, widened exactly), so that the comparison measures the integration and
// not the rounding of the inputs. The two share the rates' frames and elliptic functions but not
// the integration of q.
// Precision and bounds:
//   - quad, 100 periods of the rates, for a generic body, k > 1, an axisymmetric body (direct
//     form) and the generic body with its moments listed in another order: <= 64 eps times the
//     angle turned (|omega0| t_end, 1600 rad for the generic body, so 2e-29 rad). The
//     attitude integrates the rates, whose rounding moves their phase by a few eps per segment
//     (the rates themselves end 6.8e-31 rad/s from the closed form on the generic body, 900
//     segments), and the attitude is the more sensitive to that phase: measured 5.7e-30 rad
//     (generic and relabelled), 2.1e-30 (k > 1), 9.4e-31 (axisymmetric), about 23 eps per radian
//     turned at worst; with --degree 52 (600 segments) the generic body ends at 1.6e-30.
//     docs/attitude.md says so. The closed form itself, in quad, is within 3.4e-31.
//   - quad, 100 periods, k = 1 - 1e-6: one ulp of one input already moves the exact attitude by
//     about 5e-26 rad there (the period depends on the modulus like 1/(k kc^2 K)), and the
//     integration's own rounding is amplified alike; bound 2e-25 rad (4 x that effect), measured
//     and printed.
//   - mpfr:256, the generic body over 10 periods: <= 1e-70 rad (eps 8.6e-78 times ~130 rad, a
//     margin of 50).
//   - the inertial angular momentum q (I omega) q* of the quad reference, torque-free: constant to
//     <= 1e-31 relative (measured about 1e-32).
#include <eulervop/vop/torque_free_attitude.hpp>
#include <eulervop/oracle.hpp>
#include <eulervop/reference/integrate.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <limits>
#include <optional>

namespace {

using eulervop::mpfr_real;
using eulervop::quad;
using eulervop::quaternion;
using eulervop::vec3;

vec3<quad> v(const char* a, const char* b, const char* c) { return {quad(a), quad(b), quad(c)}; }

template <class To, class From>
vec3<To> widen(const vec3<From>& x) {
  return {To(x[0]), To(x[1]), To(x[2])};
}
template <class To, class From>
quaternion<To> widen(const quaternion<From>& q) {
  return {To(q.w), To(q.x), To(q.y), To(q.z)};
}

struct body_case {
  const char* name;
  vec3<quad> moments, omega0;
};

// The reference in T over `periods` periods of the rates, against the closed form in mpfr:256 at
// 400 times; returns the largest rotation angle, and the largest relative change of L in `drift`.
template <class T>
double attitude_error(const vec3<T>& I, const vec3<T>& w0, const quaternion<T>& q0, int periods,
                      double* drift = nullptr, double* turned = nullptr) {
  const eulervop::oracle::physical_problem<T> body(I, vec3<T>{T(0), T(0), T(0)}, w0);
  const eulervop::torque_free_attitude<T> exact_T(I, w0, q0);
  const T t_end = T(periods) * exact_T.rates_period();
  if (turned) {
    using std::sqrt;
    *turned = static_cast<double>(sqrt(w0[0] * w0[0] + w0[1] * w0[1] + w0[2] * w0[2]) * t_end);
  }
  const auto rates = eulervop::body_rates<T>::of(body.scaling);
  const auto traj = eulervop::integrate_attitude(body.problem, rates, q0, body.scaling.tau_of_t(t_end));
  std::optional<eulervop::torque_free_attitude<mpfr_real>> exact;
  std::vector<quaternion<mpfr_real>> truth;
  std::vector<vec3<mpfr_real>> truth_w;
  std::vector<T> times;
  for (int k = 0; k <= 400; ++k) times.push_back(t_end * T(k) / T(400));
  {
    const eulervop::mpfr_precision_scope scope(256);
    exact.emplace(widen<mpfr_real>(I), widen<mpfr_real>(w0), widen<mpfr_real>(q0));
    for (const T& t : times) {
      truth.push_back(exact->attitude(mpfr_real(t)));
      truth_w.push_back(exact->omega(mpfr_real(t)));
    }
  }
  const eulervop::mpfr_precision_scope scope(256);
  mpfr_real worst = 0, Lmax = 0, wmax = 0;
  vec3<T> L0{};
  for (std::size_t k = 0; k < times.size(); ++k) {
    const auto y = traj(body.scaling.tau_of_t(times[k]));
    const quaternion<T> q{y[3], y[4], y[5], y[6]};
    const mpfr_real a = eulervop::rotation_angle(truth[k], widen<mpfr_real>(q));
    if (a > worst) worst = a;
    const vec3<T> w = body.scaling.omega_of_Omega(vec3<T>{y[0], y[1], y[2]});
    for (int i = 0; i < 3; ++i) wmax = std::max(wmax, mpfr_real(abs(truth_w[k][i] - mpfr_real(w[i]))));
    const vec3<T> L = eulervop::rotate(q, vec3<T>{I[0] * w[0], I[1] * w[1], I[2] * w[2]});
    if (k == 0) L0 = L;
    mpfr_real d = 0, n = 0;
    for (int i = 0; i < 3; ++i) {
      d += (mpfr_real(L[i]) - mpfr_real(L0[i])) * (mpfr_real(L[i]) - mpfr_real(L0[i]));
      n += mpfr_real(L0[i]) * mpfr_real(L0[i]);
    }
    Lmax = std::max(Lmax, mpfr_real(sqrt(d / n)));
  }
  if (drift) *drift = static_cast<double>(Lmax);
  std::cout << "  (rates: max |omega - exact| = " << static_cast<double>(wmax) << " rad/s over " << traj.segments()
            << " segments)\n";
  return static_cast<double>(worst);
}

const quaternion<quad>& q0() {
  static const quaternion<quad> q = eulervop::normalized(quaternion<quad>{quad("0.3"), quad("-0.5"), quad("0.7"), quad("0.2")});
  return q;
}

TEST(AttitudeReference, MatchesTheClosedFormInQuadOver100Periods) {
  const body_case cases[] = {
      {"generic (1.1, 2.2, 3.3)", v("1.1", "2.2", "3.3"), v("0.9", "-0.45", "0.6")},
      {"k > 1 (minor axis)", v("1.1", "2.2", "3.3"), v("1.2", "0.3", "0.25")},
      {"axisymmetric (1, 1, 2), direct form", v("1", "1", "2"), v("0.3", "-0.2", "0.6")},
      {"moments listed (3.3, 1.1, 2.2)", v("3.3", "1.1", "2.2"), v("0.6", "0.9", "-0.45")},
  };
  for (const body_case& c : cases) {
    double drift = 0, turned = 0;
    const double err = attitude_error<quad>(c.moments, c.omega0, q0(), 100, &drift, &turned);
    const double bound = 64 * static_cast<double>(std::numeric_limits<quad>::epsilon()) * turned;
    std::cout << "[ attitude ] " << c.name << ": " << err << " rad after " << turned << " rad turned (bound " << bound
              << "), L drift " << drift << "\n";
    EXPECT_LE(err, bound) << c.name;
    EXPECT_LE(drift, 1e-31) << c.name;
  }
}

// k = 1 - 1e-6: omega0 = sqrt(A) (c1 cn u0, c1 sn u0, c2 dn u0) with c2 = 1, c1 = 1 - 1e-6, u0 =
// 0.5, evaluated in mpfr:256 and rounded to quad (as tests/test_torque_free_attitude.cpp).
TEST(AttitudeReference, NearTheSeparatrixAsAccurateAsTheInputsAllow) {
  vec3<quad> w0;
  {
    const eulervop::mpfr_precision_scope scope(256);
    const eulervop::physical_scaling<mpfr_real> s{eulervop::principal_axes<mpfr_real>(widen<mpfr_real>(v("1.1", "2.2", "3.3")))};
    const mpfr_real c2 = 1, c1 = 1 - mpfr_real("1e-6"), u0("0.5");
    const auto j = eulervop::jacobi_eval(u0, eulervop::elliptic_modulus<mpfr_real>(c1 / c2));
    const vec3<mpfr_real> Om = {c1 * j.cn, c1 * j.sn, c2 * j.dn};
    const vec3<mpfr_real> w = s.omega_of_Omega(Om);
    w0 = {quad(w[0]), quad(w[1]), quad(w[2])};
  }
  const double err = attitude_error<quad>(v("1.1", "2.2", "3.3"), w0, q0(), 100);
  std::cout << "[ attitude ] k = 1 - 1e-6: " << err << " rad\n";
  EXPECT_LE(err, 2e-25);
}

TEST(AttitudeReference, MatchesTheClosedFormInMpfr256) {
  const eulervop::mpfr_precision_scope scope(256);
  const double err = attitude_error<mpfr_real>(widen<mpfr_real>(v("1.1", "2.2", "3.3")),
                                               widen<mpfr_real>(v("0.9", "-0.45", "0.6")),
                                               widen<mpfr_real>(q0()), 10);
  std::cout << "[ attitude ] mpfr:256 generic, 10 periods: " << err << " rad\n";
  EXPECT_LE(err, 1e-70);
}

}  // namespace
