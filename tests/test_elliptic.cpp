// Tests of include/eulervop/elliptic.hpp: sn, cn, dn, am, Z, E(u), K, E, F.
//
// Reference values (provenance): Boost.Math 1.81 evaluated in boost::multiprecision::mpfr_float at
// ref_bits = 2 * bits(T) + 256 bits, at exactly the T-rounded inputs (converted to MPFR without
// rounding):
//   K, E          boost::math::ellint_1(k), ellint_2(k)
//   sn, cn        boost::math::jacobi_elliptic(k, r, &cn, &dn) at r = u - 2qK (reduced in MPFR),
//                 signs (-1)^q
//   dn            sqrt((1-k)(1+k) + k^2 cn^2) recomputed from the reference cn: Boost's dn is the
//                 ratio cos(phi_0)/cos(phi_1 - phi_0), which is 0/0 at odd multiples of K
//                 (DESIGN.md section 2)
//   am            q pi + atan2(sn(r), cn(r))
//   Z             boost::math::jacobi_zeta(k, am(r))
//   E(u)          boost::math::ellint_2(k, am(u))   (independent of our Z + (E/K) u)
//   F(phi)        boost::math::ellint_1(k, phi)
// The extra 256 bits cover the cancellation in Boost's 1 - k^2 sin^2 (at most log2(1/kc^2) bits;
// for the k tested here, kc >= 1e-15, under 100 bits).
//
// Error measures, all in units of epsilon<T>() (2^-52 double, 2^-112 quad, 2^-256 for MPFR 256):
//   "ulp"    |got - ref| / (eps * max(|ref|, floor_f)): relative, except near zeros, where it is
//            absolute on the function's own scale. floor = 1 for sn and cn (bounded by 1; their
//            zeros at u = jK with K rounded in T can only be hit in absolute terms); floor =
//            1 - E/K for Z (its amplitude scale, ~k^2/2 for small k); 0 for dn (>= kc > 0), am, E(u).
//   "mixed"  |got - ref| / (eps * (|ref| + |u f'(u)|)): the forward-backward error. An error within
//            C of this is what one gets from a relative perturbation of u by C eps plus a relative
//            rounding of the result by C eps. It is the measure that applies for large |u|,
//            because the reduction u - 2nK carries the rounding of K (n ulp(K) = about eps |u|):
//            that loses log2(|u|/K) bits of the input, so any bound in plain ulps would have to
//            grow like |u| |f'(u)| / |f|.
//            Derivatives: sn' = cn dn, cn' = -sn dn, dn' = -k^2 sn cn, am' = dn, Z' = dn^2 - E/K,
//            E'(u) = dn^2.
//
// Asserted bounds, in multiples of epsilon<T>() for every T (the algorithm and its rounding
// count are the same in every type; glibc, libquadmath and MPFR sin/cos/atan2 are faithful or
// better; about N + 6 roundings occur, each contributing at most eps/2, most damped):
//   |u| <= K (no reduction; random points, u = +-K exactly and 1e-6 inside, tiny u), all k from
//       1e-8 to 1 - 1e-12 (1 - 1e-30 for quad and MPFR):
//       ulp <= 8 for sn, cn, am, Z, E(u);
//       dn (relative): ulp <= 8 max(1, |u dn'/dn|). The argument a_n u of the Gauss levels is
//       rounded (~1 ulp); dn's relative condition number in u reaches ~|u| <= K as k -> 1, so
//       the plain relative error of dn can reach ~2 K ulp there (reported; ~22 in double at
//       k = 1 - 1e-12), while its absolute error stays below eps.
//       mixed <= 8 for all six.
//   |u| <= 4K (random, u = (2j+1)K exactly and +-1e-6, u = 2jK) and 10 <= |u| <= 1e5:
//       mixed <= 8 (plain ulp reported: it grows like |u| |f'| / |f|).
//   K, E: relative <= 4 ulp.  F(phi) (|phi| <= 20): mixed (w.r.t. phi) <= 8.
//   F(am(u)) = u for 1e-3 <= |u| <= 1e5: |F(am u) - u| <= 8 eps (|u| + |am| / dn(u)) (am is
//       rounded to eps |am|, and dF/dphi = 1/dn).
#include "eulervop/elliptic.hpp"

#include <gtest/gtest.h>

#include <boost/math/policies/policy.hpp>
#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/ellint_2.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <boost/math/special_functions/jacobi_zeta.hpp>

#include <algorithm>
#include <cstdint>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

using eulervop::elliptic_modulus;
using eulervop::jacobi_eval;
using eulervop::jacobi_values;
using eulervop::mpfr_precision_scope;
using eulervop::mpfr_real;
using eulervop::quad;

constexpr unsigned mpfr_test_bits = 256;

template <class T>
unsigned type_bits() {
  if constexpr (std::is_same_v<T, mpfr_real>)
    return eulervop::mpfr_effective_bits(mpfr_test_bits);
  else
    return static_cast<unsigned>(std::numeric_limits<T>::digits);
}
template <class T>
unsigned ref_bits() {
  return 2 * type_bits<T>() + 256;
}

// Exact conversion of a T value to an MPFR value at the current (reference) precision.
template <class T>
mpfr_real to_ref(const T& x) {
  mpfr_real r;  // current default precision
  if constexpr (std::is_same_v<T, double>) {
    mpfr_set_d(r.backend().data(), x, MPFR_RNDN);
  } else if constexpr (std::is_same_v<T, quad>) {
    // 113 bits = three doubles exactly: hi + lo + lo2.
    const double hi = static_cast<double>(x);
    const quad rest = x - quad(hi);
    const double lo = static_cast<double>(rest);
    const double lo2 = static_cast<double>(rest - quad(lo));
    mpfr_real l, l2;
    mpfr_set_d(r.backend().data(), hi, MPFR_RNDN);
    mpfr_set_d(l.backend().data(), lo, MPFR_RNDN);
    mpfr_set_d(l2.backend().data(), lo2, MPFR_RNDN);
    r += l;
    r += l2;
  } else {
    mpfr_set(r.backend().data(), x.backend().data(), MPFR_RNDN);
  }
  return r;
}

double dbl(const mpfr_real& x) { return x.convert_to<double>(); }

template <class T>
double to_double(const T& x) {
  if constexpr (std::is_same_v<T, double>)
    return x;
  else
    return x.template convert_to<double>();
}

// Uniform in [0, 1) with all bits of T random (fixed-seed engine).
template <class T>
T random_unit(std::mt19937_64& rng) {
  auto u01 = [&] { return static_cast<double>(rng() >> 11) * 0x1p-53; };
  T x = u01();
  if constexpr (!std::is_same_v<T, double>) {
    T scale = 1;
    const unsigned parts = (type_bits<T>() + 52) / 53;
    for (unsigned p = 1; p < parts; ++p) {
      scale = ldexp(scale, -53);
      x += scale * T(u01());
    }
  }
  return x;
}

template <class T>
T parse(const char* s) {
  return *eulervop::from_text<T>(s);
}

// ---- reference --------------------------------------------------------------------------

struct ref_point {
  mpfr_real sn, cn, dn, am, Z, E, e_over_k;
};

// All at the current (reference) MPFR precision.
ref_point reference(const mpfr_real& u, const mpfr_real& k) {
  using boost::math::constants::pi;
  ref_point p;
  const mpfr_real K = boost::math::ellint_1(k);
  const mpfr_real Ek = boost::math::ellint_2(k);
  p.e_over_k = Ek / K;
  const mpfr_real q = round(u / (2 * K));
  const mpfr_real r = u - 2 * q * K;
  mpfr_real cn, dn_boost;
  mpfr_real sn = boost::math::jacobi_elliptic(k, r, &cn, &dn_boost);
  const mpfr_real kc2 = (1 - k) * (1 + k);
  p.dn = sqrt(kc2 + k * k * cn * cn);
  const mpfr_real am_r = atan2(sn, cn);
  p.am = q * pi<mpfr_real>() + am_r;
  p.Z = boost::math::jacobi_zeta(k, am_r);
  p.E = boost::math::ellint_2(k, p.am);
  const bool odd = fmod(abs(q), mpfr_real(2)) == 1;
  p.sn = odd ? mpfr_real(-sn) : sn;
  p.cn = odd ? mpfr_real(-cn) : cn;
  return p;
}

// ---- error bookkeeping ------------------------------------------------------------------

struct worst {
  double ulp = 0;
  std::string where;
  void note(double e, const std::string& w) {
    if (!(e <= ulp)) {  // also records NaN
      ulp = e;
      where = w;
    }
  }
};

// Errors of one evaluation in both measures, for the six functions.
struct eval_errors {
  double ulp[6];
  double mixed[6];
  double dn_cond;  // |u dn'(u) / dn(u)|, the relative condition number of dn in u
};
const char* const fn_names[6] = {"sn", "cn", "dn", "am", "Z", "E(u)"};

template <class T>
eval_errors errors_at(const T& u, const T& k, const jacobi_values<T>& got, const T& eps_t) {
  eval_errors out{};
  mpfr_precision_scope scope(ref_bits<T>());
  const mpfr_real ur = to_ref(u), kr = to_ref(k), eps = to_ref(eps_t);
  const ref_point p = reference(ur, kr);
  const mpfr_real k2 = kr * kr;
  const mpfr_real dn2 = p.dn * p.dn;
  const mpfr_real* refs[6] = {&p.sn, &p.cn, &p.dn, &p.am, &p.Z, &p.E};
  const T* gots[6] = {&got.sn, &got.cn, &got.dn, &got.am, &got.Z, &got.E};
  const mpfr_real derivs[6] = {p.cn * p.dn, -p.sn * p.dn, -k2 * p.sn * p.cn, p.dn, dn2 - p.e_over_k, dn2};
  const mpfr_real floors[6] = {mpfr_real(1), mpfr_real(1), mpfr_real(0), mpfr_real(0), 1 - p.e_over_k,
                               mpfr_real(0)};
  out.dn_cond = dbl(abs(ur * derivs[2] / p.dn));
  for (int f = 0; f < 6; ++f) {
    const mpfr_real err = abs(to_ref(*gots[f]) - *refs[f]);
    const mpfr_real a = abs(*refs[f]);
    const mpfr_real s_ulp = eps * (a > floors[f] ? a : floors[f]);
    const mpfr_real s_mixed = eps * (a + abs(ur * derivs[f]));
    out.ulp[f] = err == 0 ? 0.0 : dbl(err / s_ulp);
    out.mixed[f] = err == 0 ? 0.0 : dbl(err / s_mixed);
  }
  return out;
}

template <class T>
std::string type_name() {
  if constexpr (std::is_same_v<T, double>) return "double";
  else if constexpr (std::is_same_v<T, quad>) return "quad";
  else return "mpfr" + std::to_string(mpfr_test_bits);
}

// ---- fixture ----------------------------------------------------------------------------

template <class T>
class Elliptic : public ::testing::Test {
 protected:
  void SetUp() override {
    if constexpr (std::is_same_v<T, mpfr_real>) scope_.emplace(mpfr_test_bits);
  }
  std::optional<mpfr_precision_scope> scope_;

  // Test moduli: the required extremes and a spread. k = 0 is tested separately (exactly).
  static std::vector<T> moduli() {
    std::vector<T> ks;
    for (const char* s : {"1e-8", "1e-3", "0.1", "0.5", "0.7071067811865476", "0.9", "0.99",
                          "0.999999", "0.999999999999"})
      ks.push_back(parse<T>(s));
    if constexpr (!std::is_same_v<T, double>) ks.push_back(1 - parse<T>("1e-30"));
    std::mt19937_64 rng(20240611);
    for (int i = 0; i < (std::is_same_v<T, mpfr_real> ? 3 : 8); ++i) ks.push_back(random_unit<T>(rng));
    return ks;
  }
  static int random_points() { return std::is_same_v<T, mpfr_real> ? 25 : 100; }
  static int large_points() { return std::is_same_v<T, mpfr_real> ? 10 : 40; }
};

using ScalarTypes = ::testing::Types<double, quad, mpfr_real>;
TYPED_TEST_SUITE(Elliptic, ScalarTypes);

void print_table(const std::string& title, const std::map<std::string, worst>& table) {
  std::ostringstream os;
  os << title << "\n";
  for (const auto& [name, w] : table)
    os << "    " << std::left << std::setw(10) << name << std::right << std::setw(10) << std::setprecision(3)
       << w.ulp << "  at " << w.where << "\n";
  std::cout << os.str();
}

std::string describe(const std::string& label, double u, double k) {
  std::ostringstream os;
  os << label << " u=" << std::setprecision(17) << u << " k=" << k;
  return os.str();
}

// ---- tests ------------------------------------------------------------------------------

TYPED_TEST(Elliptic, DomainErrorsCarryTheValue) {
  using T = TypeParam;
  for (const T& bad : {T(-1) / 10, T(1), T(3) / 2}) {
    try {
      elliptic_modulus<T> m(bad);
      FAIL() << "no exception for k = " << eulervop::to_text<T>(bad);
    } catch (const std::domain_error& e) {
      EXPECT_NE(std::string(e.what()).find(eulervop::to_text<T>(bad)), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(elliptic_modulus<T>(std::numeric_limits<double>::quiet_NaN()), std::domain_error);
}

TYPED_TEST(Elliptic, ZeroModulusIsExactlyCircular) {
  using T = TypeParam;
  using std::cos;
  using std::sin;
  const elliptic_modulus<T> m(T(0));
  const T half_pi = boost::math::constants::half_pi<T>();
  EXPECT_EQ(m.K(), half_pi);
  EXPECT_EQ(m.E(), half_pi);
  EXPECT_EQ(m.e_over_k(), T(1));
  EXPECT_EQ(m.kc(), T(1));
  for (const T& u : {T(0), T(1) / 3, T(-7), T(100000) + T(1) / 7}) {
    const auto j = jacobi_eval(u, m);
    EXPECT_EQ(j.sn, sin(u));
    EXPECT_EQ(j.cn, cos(u));
    EXPECT_EQ(j.dn, T(1));
    EXPECT_EQ(j.am, u);
    EXPECT_EQ(j.Z, T(0));
    EXPECT_EQ(j.E, u);
    EXPECT_EQ(eulervop::elliptic_f(u, m), u);
  }
}

TYPED_TEST(Elliptic, CompleteIntegralsAgainstBoostMpfr) {
  using T = TypeParam;
  const T eps = eulervop::epsilon<T>();
  worst wk, we;
  for (const T& k : this->moduli()) {
    const elliptic_modulus<T> m(k);
    ASSERT_LE(m.levels(), elliptic_modulus<T>::max_levels);
    mpfr_precision_scope scope(ref_bits<T>());
    const mpfr_real kr = to_ref(k), e = to_ref(eps);
    const mpfr_real K = boost::math::ellint_1(kr), E = boost::math::ellint_2(kr);
    const double ek = dbl(abs(to_ref(m.K()) - K) / (e * K));
    const double ee = dbl(abs(to_ref(m.E()) - E) / (e * E));
    wk.note(ek, describe("K", 0, to_double(k)));
    we.note(ee, describe("E", 0, to_double(k)));
    EXPECT_LE(ek, 4) << "K at k=" << eulervop::to_text<T>(k);
    EXPECT_LE(ee, 4) << "E at k=" << eulervop::to_text<T>(k);
  }
  print_table("[" + type_name<T>() + "] complete integrals, worst relative error in eps",
              {{"K(k)", wk}, {"E(k)", we}});
  this->RecordProperty("worst_ulp_K", std::to_string(wk.ulp));
  this->RecordProperty("worst_ulp_E", std::to_string(we.ulp));
}

// Evaluates at every (u, label) for modulus k and folds the errors into the running worst.
worst dn_per_cond;  // worst relative dn error / max(1, |u dn'/dn|), reported by the half-period test

template <class T>
void sweep(const T& k, const std::vector<std::pair<T, std::string>>& us, worst (&w)[6], worst (&wm)[6],
           double ulp_bound, double mixed_bound) {
  const T eps = eulervop::epsilon<T>();
  const elliptic_modulus<T> m(k);
  for (const auto& [u, label] : us) {
    const auto got = jacobi_eval(u, m);
    const auto e = errors_at(u, k, got, eps);
    const std::string where = describe(label, to_double(u), to_double(k));
    for (int f = 0; f < 6; ++f) {
      w[f].note(e.ulp[f], where);
      wm[f].note(e.mixed[f], where);
      // dn is measured relative (it never vanishes), and its relative error is the ~1 ulp
      // rounding of the argument a_n u times its condition number |u dn'/dn| (up to ~|u| as
      // k -> 1, where dn ~ kc): bound ulp_bound * max(1, |u dn'/dn|).
      const double bound = f == 2 ? ulp_bound * std::max(1.0, e.dn_cond) : ulp_bound;
      EXPECT_LE(e.ulp[f], bound) << fn_names[f] << " ulp at " << where;
      if (f == 2) dn_per_cond.note(e.ulp[f] / std::max(1.0, e.dn_cond), where);
      EXPECT_LE(e.mixed[f], mixed_bound) << fn_names[f] << " mixed at " << where;
    }
  }
}

template <class T>
void report(const std::string& what, worst (&w)[6], worst (&wm)[6], ::testing::Test* t, const std::string& key) {
  std::map<std::string, worst> t1, t2;
  for (int f = 0; f < 6; ++f) {
    t1[fn_names[f]] = w[f];
    t2[fn_names[f]] = wm[f];
    t->RecordProperty("worst_ulp_" + key + "_" + fn_names[f], std::to_string(w[f].ulp));
    t->RecordProperty("worst_mixed_" + key + "_" + fn_names[f], std::to_string(wm[f].ulp));
  }
  print_table("[" + type_name<T>() + "] " + what + ": worst error in ulp (absolute for sn, cn; Z on scale 1-E/K)", t1);
  print_table("[" + type_name<T>() + "] " + what + ": worst mixed forward-backward error in eps", t2);
}

// |u| <= K, where no reduction happens (r = u exactly): plain ulp. Random points, u = +-K exactly
// (cn = 0, dn = kc: the 0/0 of Boost's ratio) and 1e-6 inside, u = 1e-6, -1e-20, 0.5.
TYPED_TEST(Elliptic, WithinEightUlpOverHalfPeriod) {
  using T = TypeParam;
  dn_per_cond = worst{};
  std::mt19937_64 rng(12345);
  worst w[6], wm[6];
  const T delta = parse<T>("1e-6");
  for (const T& k : this->moduli()) {
    const T K = elliptic_modulus<T>(k).K();
    std::vector<std::pair<T, std::string>> us;
    for (int i = 0; i < this->random_points(); ++i) us.push_back({(2 * random_unit<T>(rng) - 1) * K, "random"});
    us.push_back({K, "K"});
    us.push_back({T(-K), "-K"});
    us.push_back({K - delta, "K-1e-6"});
    us.push_back({T(-K + delta), "-K+1e-6"});
    for (const char* s : {"1e-6", "-1e-20", "0.5"}) us.push_back({parse<T>(s), "small"});
    sweep(k, us, w, wm, 8, 8);
  }
  report<T>("|u| <= K", w, wm, this, "halfperiod");
  std::cout << "[" << type_name<T>() << "] |u| <= K: worst dn relative error / max(1, |u dn'/dn|): "
            << dn_per_cond.ulp << "  at " << dn_per_cond.where << "\n";
}

// |u| <= 4K: random points, u = (2j+1)K exactly and 1e-6 either side (j = -2..1), u = 2jK.
// Reduced arguments carry the rounding of K: bound in the mixed measure (plain ulp reported).
TYPED_TEST(Elliptic, MixedErrorOverFourPeriods) {
  using T = TypeParam;
  std::mt19937_64 rng(4242);
  worst w[6], wm[6];
  const T delta = parse<T>("1e-6");
  for (const T& k : this->moduli()) {
    const T K = elliptic_modulus<T>(k).K();
    std::vector<std::pair<T, std::string>> us;
    for (int i = 0; i < this->random_points(); ++i)
      us.push_back({(2 * random_unit<T>(rng) - 1) * 4 * K, "random"});
    for (int j = -2; j <= 1; ++j) {
      const T odd = (2 * j + 1) * K;
      us.push_back({odd, "(2j+1)K"});
      us.push_back({odd + delta, "(2j+1)K+1e-6"});
      us.push_back({odd - delta, "(2j+1)K-1e-6"});
      us.push_back({T(2 * j * K), "2jK"});
    }
    sweep(k, us, w, wm, std::numeric_limits<double>::infinity(), 8);
  }
  report<T>("|u| <= 4K", w, wm, this, "fourperiods");
}

// |u| up to 1e5: the reduction carries the rounding of K (it loses log2(|u|/K) bits of u);
// bound in the mixed measure, plain ulp reported (it grows like |u|).
TYPED_TEST(Elliptic, LargeArgumentsMixedError) {
  using T = TypeParam;
  using std::exp;
  using std::floor;
  using std::log;
  std::mt19937_64 rng(777);
  worst w[6], wm[6];
  for (const T& k : this->moduli()) {
    const T K = elliptic_modulus<T>(k).K();
    std::vector<std::pair<T, std::string>> us;
    for (int i = 0; i < this->large_points(); ++i) {
      // log-uniform magnitude in [10, 1e5], random sign
      const T mag = exp(log(T(10)) * (1 + 4 * random_unit<T>(rng)));
      us.push_back({random_unit<T>(rng) < T(1) / 2 ? T(-mag) : mag, "large"});
    }
    // the last odd multiple of K below 1e5, and 1e-6 beside it
    const T j = floor((T(100000) / K - 1) / 2);
    const T odd = (2 * j + 1) * K;
    us.push_back({odd, "(2j+1)K"});
    us.push_back({T(-odd), "-(2j+1)K"});
    us.push_back({T(odd + parse<T>("1e-6")), "(2j+1)K+1e-6"});
    sweep(k, us, w, wm, std::numeric_limits<double>::infinity(), 8);
  }
  report<T>("10 <= |u| <= 1e5", w, wm, this, "large");
}

// am(u) is continuous: no jumps of pi across the branch points u = (2j+1)K.
TYPED_TEST(Elliptic, AmplitudeIsContinuous) {
  using T = TypeParam;
  for (const char* ks : {"0.5", "0.999999999999"}) {
    const elliptic_modulus<T> m(parse<T>(ks));
    for (int j = -3; j <= 3; ++j) {
      const T centre = (2 * j + 1) * m.K();
      const T h = m.K() / 64;
      T prev = jacobi_eval(T(centre - 8 * h), m).am;
      for (int i = -7; i <= 8; ++i) {
        const T u = centre + i * h;
        const T am = jacobi_eval(u, m).am;
        // am' = dn in (0, 1]: increments lie in (0, h].
        EXPECT_GT(am, prev) << "k=" << ks << " j=" << j << " i=" << i;
        EXPECT_LE(am - prev, h * (1 + 64 * eulervop::epsilon<T>())) << "k=" << ks << " j=" << j << " i=" << i;
        prev = am;
      }
      // straddling the branch point by the smallest steps
      const T a = jacobi_eval(centre, m).am;
      const T pi = boost::math::constants::pi<T>();
      EXPECT_NEAR(to_double(a), to_double(T(j * pi + pi / 2)), 1e-12);
    }
  }
}

// F(am(u), k) = u over many periods, and F against Boost.Math ellint_1 in MPFR.
TYPED_TEST(Elliptic, IncompleteFirstKind) {
  using T = TypeParam;
  using std::abs;
  using std::exp;
  using std::log;
  const T eps = eulervop::epsilon<T>();
  std::mt19937_64 rng(99);
  double worst_rt = 0, worst_f = 0;
  std::string where_rt, where_f;
  for (const T& k : this->moduli()) {
    const elliptic_modulus<T> m(k);
    for (int i = 0; i < this->large_points(); ++i) {
      const T mag = exp(log(T(10)) * (-3 + 8 * random_unit<T>(rng)));  // 1e-3 .. 1e5
      const T u = random_unit<T>(rng) < T(1) / 2 ? T(-mag) : mag;
      const auto j = jacobi_eval(u, m);
      const T back = eulervop::elliptic_f(j.am, m);
      const double r = to_double(T(abs(back - u) / (eps * (abs(u) + abs(j.am) / j.dn))));
      if (r > worst_rt) worst_rt = r, where_rt = describe("F(am u)", to_double(u), to_double(k));
      EXPECT_LE(r, 8) << describe("F(am u) - u", to_double(u), to_double(k));
    }
    for (int i = 0; i < this->random_points() / 5; ++i) {
      const T phi = (2 * random_unit<T>(rng) - 1) * 20;
      const T f = eulervop::elliptic_f(phi, m);
      mpfr_precision_scope scope(ref_bits<T>());
      const mpfr_real kr = to_ref(k), pr = to_ref(phi);
      const mpfr_real ref = boost::math::ellint_1(kr, pr);
      const mpfr_real s = sin(pr);
      const mpfr_real dfdphi = 1 / sqrt((1 - kr) * (1 + kr) + kr * kr * (1 - s) * (1 + s));
      const double r = dbl(abs(to_ref(f) - ref) / (to_ref(eps) * (abs(ref) + abs(pr) * dfdphi)));
      if (r > worst_f) worst_f = r, where_f = describe("F(phi)", to_double(phi), to_double(k));
      EXPECT_LE(r, 8) << describe("F(phi)", to_double(phi), to_double(k));
    }
  }
  std::cout << "[" << type_name<T>() << "] F(am(u)) - u, worst |err| / (eps (|u| + |am|/dn)): " << worst_rt
            << "  at " << where_rt << "\n";
  std::cout << "[" << type_name<T>() << "] F(phi) vs ellint_1, worst mixed error in eps: " << worst_f << "  at "
            << where_f << "\n";
  this->RecordProperty("worst_roundtrip", std::to_string(worst_rt));
  this->RecordProperty("worst_mixed_F", std::to_string(worst_f));
}

// Boost.Math's own dn, in double without promotion, next to ours at u = K: the pitfall this
// header exists to avoid (informative, plus a check that ours is right there).
TEST(EllipticDouble, DnAtOddMultiplesOfK) {
  using namespace boost::math::policies;
  using no_promote = policy<promote_double<false>>;
  for (double k : {0.5, 0.9, 0.999999999999}) {
    const elliptic_modulus<double> m(k);
    for (int j : {0, 1, 5}) {
      const double u = (2 * j + 1) * m.K();
      const auto ours = jacobi_eval(u, m);
      double cn_b = 0, dn_b = 0;
      boost::math::jacobi_elliptic(k, u, &cn_b, &dn_b, no_promote());
      const auto e = errors_at(u, k, ours, eulervop::epsilon<double>());
      std::cout << "[double] u=(2*" << j << "+1)K k=" << k << ": dn ours " << std::setprecision(17) << ours.dn
                << " (" << std::setprecision(3) << e.ulp[2] << " ulp), Boost " << std::setprecision(17) << dn_b
                << ", kc " << m.kc() << "\n";
      EXPECT_LE(e.ulp[2], 8);
    }
  }
}

}  // namespace
