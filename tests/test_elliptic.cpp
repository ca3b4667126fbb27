// Tests of include/eulervop/special/elliptic.hpp: sn, cn, dn, am, Z, E(u), K, E, F.
//
// Reference values (provenance): Boost.Math 1.81 evaluated in boost::multiprecision::mpfr_float at
// ref_bits = 2 * bits(T) + 256 bits, at exactly the T-rounded inputs (converted to MPFR without
// rounding):
//   K, E          boost::math::ellint_1(k), ellint_2(k)
//   sn, cn        boost::math::jacobi_elliptic(k, r, &cn, &dn) at r = u - 2qK (reduced in MPFR),
//                 signs (-1)^q
//   dn            sqrt((1-k)(1+k) + k^2 cn^2) recomputed from the reference cn: Boost's dn is the
//                 ratio cos(phi_0)/cos(phi_1 - phi_0), which is 0/0 at odd multiples of K
//                 (docs/design.md section 2)
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
#include "eulervop/special/elliptic.hpp"
#include "eulervop/special/detail/sincos_double.hpp"
#include "eulervop/special/jacobi_theta.hpp"
#include "type_test_names.hpp"

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

// Test moduli: the required extremes and a spread. k = 0 is tested separately (exactly).
template <class T>
std::vector<T> test_moduli() {
  std::vector<T> ks;
  for (const char* s : {"1e-8", "1e-3", "0.1", "0.5", "0.7071067811865476", "0.9", "0.99",
                        "0.999999", "0.999999999999"})
    ks.push_back(parse<T>(s));
  if constexpr (!std::is_same_v<T, double>) ks.push_back(1 - parse<T>("1e-30"));
  // Where the AGM stops at its first (N = 1) or second level with c_N just under the stopping
  // threshold sqrt(eps)/64 (c_1 ~ k^2/4, c_2 ~ c_1^2/4): the bottom level's first-order terms
  // in k_N are largest there (they were once missing from Z, a 1e6-ulp error at k = 3e-5).
  {
    using std::sqrt;
    const T r4 = sqrt(sqrt(eulervop::epsilon<T>()));
    ks.push_back(r4 / 8);         // c_1 ~ stop / 4
    ks.push_back(sqrt(r4) * 3 / 4);  // c_2 ~ stop / 3
  }
  std::mt19937_64 rng(20240611);
  for (int i = 0; i < (std::is_same_v<T, mpfr_real> ? 3 : 8); ++i) ks.push_back(random_unit<T>(rng));
  return ks;
}

// ---- fixture ----------------------------------------------------------------------------

template <class T>
class Elliptic : public ::testing::Test {
 protected:
  void SetUp() override {
    if constexpr (std::is_same_v<T, mpfr_real>) scope_.emplace(mpfr_test_bits);
  }
  std::optional<mpfr_precision_scope> scope_;

  static std::vector<T> moduli() { return test_moduli<T>(); }
  static int random_points() { return std::is_same_v<T, mpfr_real> ? 25 : 100; }
  static int large_points() { return std::is_same_v<T, mpfr_real> ? 10 : 40; }
};

using ScalarTypes = ::testing::Types<double, quad, mpfr_real>;
TYPED_TEST_SUITE(Elliptic, ScalarTypes, scalar_test_names);

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
using labelled_points = std::vector<std::pair<T, std::string>>;

// The evaluation of one route: the AGM route of elliptic.hpp (all six functions) by default.
template <class T>
struct agm_route {
  static constexpr bool has_am = true;
  elliptic_modulus<T> m;
  explicit agm_route(const T& k) : m(k) {}
  jacobi_values<T> operator()(const T& u) const { return jacobi_eval(u, m); }
};

template <class T, class Route = agm_route<T>>
void sweep(const T& k, const labelled_points<T>& us, worst (&w)[6], worst (&wm)[6], double ulp_bound,
           double mixed_bound) {
  const T eps = eulervop::epsilon<T>();
  const Route route(k);
  for (const auto& [u, label] : us) {
    const auto got = route(u);
    const auto e = errors_at(u, k, got, eps);
    const std::string where = describe(label, to_double(u), to_double(k));
    for (int f = 0; f < 6; ++f) {
      if (f == 3 && !Route::has_am) continue;
      w[f].note(e.ulp[f], where);
      wm[f].note(e.mixed[f], where);
      // dn is measured relative (it never vanishes), and its relative error is the ~1 ulp
      // rounding of the argument a_n u times its condition number |u dn'/dn| (up to ~|u| as
      // k -> 1, where dn ~ kc): bound ulp_bound * max(1, |u dn'/dn|).
      const double bound = f == 2 ? ulp_bound * std::max(1.0, e.dn_cond) : ulp_bound;
      EXPECT_LE(e.ulp[f], bound) << fn_names[f] << " ulp at " << where;
      if (f == 2 && ulp_bound < std::numeric_limits<double>::infinity())
        dn_per_cond.note(e.ulp[f] / std::max(1.0, e.dn_cond), where);
      EXPECT_LE(e.mixed[f], mixed_bound) << fn_names[f] << " mixed at " << where;
    }
  }
}

template <class T>
void report(const std::string& what, worst (&w)[6], worst (&wm)[6], ::testing::Test* t, const std::string& key,
            bool with_am = true) {
  std::map<std::string, worst> t1, t2;
  for (int f = 0; f < 6; ++f) {
    if (f == 3 && !with_am) continue;
    t1[fn_names[f]] = w[f];
    t2[fn_names[f]] = wm[f];
    t->RecordProperty("worst_ulp_" + key + "_" + fn_names[f], std::to_string(w[f].ulp));
    t->RecordProperty("worst_mixed_" + key + "_" + fn_names[f], std::to_string(wm[f].ulp));
  }
  print_table("[" + type_name<T>() + "] " + what + ": worst error in ulp (absolute for sn, cn; Z on scale 1-E/K)", t1);
  print_table("[" + type_name<T>() + "] " + what + ": worst mixed forward-backward error in eps", t2);
}

// ---- evaluation points, shared by the AGM route and the theta route ---------------------

// |u| <= K, where no reduction happens (r = u exactly): random points, u = +-K exactly
// (cn = 0, dn = kc: the 0/0 of Boost's ratio) and 1e-6 inside, u = 1e-6, -1e-20, 0.5.
template <class T>
labelled_points<T> half_period_points(const T& K, std::mt19937_64& rng, int n_random) {
  const T delta = parse<T>("1e-6");
  labelled_points<T> us;
  for (int i = 0; i < n_random; ++i) us.push_back({(2 * random_unit<T>(rng) - 1) * K, "random"});
  us.push_back({K, "K"});
  us.push_back({T(-K), "-K"});
  us.push_back({K - delta, "K-1e-6"});
  us.push_back({T(-K + delta), "-K+1e-6"});
  for (const char* s : {"1e-6", "-1e-20", "0.5"}) us.push_back({parse<T>(s), "small"});
  return us;
}

// |u| <= 4K: random points, u = (2j+1)K exactly and 1e-6 either side (j = -2..1), u = 2jK.
template <class T>
labelled_points<T> four_period_points(const T& K, std::mt19937_64& rng, int n_random) {
  const T delta = parse<T>("1e-6");
  labelled_points<T> us;
  for (int i = 0; i < n_random; ++i) us.push_back({(2 * random_unit<T>(rng) - 1) * 4 * K, "random"});
  for (int j = -2; j <= 1; ++j) {
    const T odd = (2 * j + 1) * K;
    us.push_back({odd, "(2j+1)K"});
    us.push_back({odd + delta, "(2j+1)K+1e-6"});
    us.push_back({odd - delta, "(2j+1)K-1e-6"});
    us.push_back({T(2 * j * K), "2jK"});
  }
  return us;
}

// 10 <= |u| <= 1e5, log-uniform with random sign, and the last odd multiple of K below 1e5.
template <class T>
labelled_points<T> large_argument_points(const T& K, std::mt19937_64& rng, int n_random) {
  using std::exp;
  using std::floor;
  using std::log;
  labelled_points<T> us;
  for (int i = 0; i < n_random; ++i) {
    const T mag = exp(log(T(10)) * (1 + 4 * random_unit<T>(rng)));
    us.push_back({random_unit<T>(rng) < T(1) / 2 ? T(-mag) : mag, "large"});
  }
  const T j = floor((T(100000) / K - 1) / 2);
  const T odd = (2 * j + 1) * K;
  us.push_back({odd, "(2j+1)K"});
  us.push_back({T(-odd), "-(2j+1)K"});
  us.push_back({T(odd + parse<T>("1e-6")), "(2j+1)K+1e-6"});
  return us;
}

// The three sweeps for one route over the moduli ks. Bounds: |u| <= K plain ulp <= 8 (dn: times
// its condition number) and mixed <= 8; beyond, where reduced arguments carry the rounding of K
// (it loses log2(|u|/K) bits of u), mixed <= 8 with plain ulp reported.
template <class T, class Route = agm_route<T>>
void sweep_all(const std::vector<T>& ks, int n_random, int n_large, ::testing::Test* t, const std::string& tag) {
  dn_per_cond = worst{};
  const double inf = std::numeric_limits<double>::infinity();
  worst w[3][6], wm[3][6];
  std::mt19937_64 rng_half(12345), rng_four(4242), rng_large(777);
  for (const T& k : ks) {
    const T K = elliptic_modulus<T>(k).K();
    sweep<T, Route>(k, half_period_points(K, rng_half, n_random), w[0], wm[0], 8, 8);
    sweep<T, Route>(k, four_period_points(K, rng_four, n_random), w[1], wm[1], inf, 8);
    sweep<T, Route>(k, large_argument_points(K, rng_large, n_large), w[2], wm[2], inf, 8);
  }
  report<T>(tag + "|u| <= K", w[0], wm[0], t, tag + "halfperiod", Route::has_am);
  std::cout << "[" << type_name<T>() << "] " << tag << "|u| <= K: worst dn relative error / max(1, |u dn'/dn|): "
            << dn_per_cond.ulp << "  at " << dn_per_cond.where << "\n";
  report<T>(tag + "|u| <= 4K", w[1], wm[1], t, tag + "fourperiods", Route::has_am);
  report<T>(tag + "10 <= |u| <= 1e5", w[2], wm[2], t, tag + "large", Route::has_am);
}

TYPED_TEST(Elliptic, WithinEightUlpAndMixedErrorAtAnyArgument) {
  using T = TypeParam;
  sweep_all<T>(this->moduli(), this->random_points(), this->large_points(), this, "");
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


// ---- the theta route (jacobi_theta.hpp: double, 0 <= k <= 0.99) ------------------------
// The same references, points and bounds as the AGM route above, except am (not computed).

struct theta_route {
  static constexpr bool has_am = false;
  eulervop::theta_modulus m;
  explicit theta_route(double k) : m(k) {}
  jacobi_values<double> operator()(double u) const {
    jacobi_values<double> j;
    j.am = std::numeric_limits<double>::quiet_NaN();
    eulervop::theta_eval(u, m, j);
    return j;
  }
};

std::vector<double> theta_moduli() {
  std::vector<double> ks;
  for (double k : test_moduli<double>())
    if (eulervop::theta_modulus::covers(k)) ks.push_back(k);
  ks.push_back(eulervop::theta_modulus::max_k);  // the slowest-converging series
  return ks;
}

TEST(ThetaDouble, SameBoundsAsTheAgmRoute) {
  sweep_all<double, theta_route>(theta_moduli(), 100, 40, this, "theta ");
}

TEST(ThetaDouble, CompleteIntegralsAgainstBoostMpfr) {
  const double eps = eulervop::epsilon<double>();
  worst wk, we, wr;
  for (double k : theta_moduli()) {
    const eulervop::theta_modulus m(k);
    mpfr_precision_scope scope(ref_bits<double>());
    const mpfr_real kr = to_ref(k), e = to_ref(eps);
    const mpfr_real K = boost::math::ellint_1(kr), E = boost::math::ellint_2(kr);
    const double ek = dbl(abs(to_ref(m.K()) - K) / (e * K));
    const double ee = dbl(abs(to_ref(m.E()) - E) / (e * E));
    // pi/(2K) is the rate of v in u: its error times |u| is the phase error at large u.
    const mpfr_real rate = boost::math::constants::half_pi<mpfr_real>() / K;
    const double er = dbl(abs(to_ref(m.pi_over_2K()) - rate) / (e * rate));
    wk.note(ek, describe("K", 0, k));
    we.note(ee, describe("E", 0, k));
    wr.note(er, describe("pi/2K", 0, k));
    EXPECT_LE(ek, 4) << "K at k=" << k;
    EXPECT_LE(ee, 4) << "E at k=" << k;
    EXPECT_LE(er, 4) << "pi/(2K) at k=" << k;
  }
  print_table("[double] theta route: complete integrals, worst relative error in eps",
              {{"K(k)", wk}, {"E(k)", we}, {"pi/(2K)", wr}});
}

TEST(ThetaDouble, ZeroModulusIsExactlyCircular) {
  const eulervop::theta_modulus m(0);
  EXPECT_EQ(m.q(), 0.0);
  EXPECT_EQ(m.K(), boost::math::constants::half_pi<double>());
  EXPECT_EQ(m.e_over_k(), 1.0);
  // u = 100000 + 1/7 is reduced by 31831 pi in two parts; the result is within an ulp of
  // sin/cos of the unreduced argument (which glibc reduces exactly).
  for (double u : {0.0, 1.0 / 3, -7.0, 100000 + 1.0 / 7}) {
    jacobi_values<double> j;
    eulervop::theta_eval(u, m, j);
    EXPECT_NEAR(j.sn, std::sin(u), 2 * std::abs(u) * 1e-16 + 1e-300) << u;
    EXPECT_NEAR(j.cn, std::cos(u), 2 * std::abs(u) * 1e-16 + 1e-300) << u;
    EXPECT_EQ(j.dn, 1.0);
    EXPECT_EQ(j.Z, 0.0);
    EXPECT_EQ(j.E, u);
  }
}

TEST(ThetaDouble, DomainErrorsCarryTheValue) {
  for (double bad : {-0.1, 0.995, 1.0}) {
    try {
      eulervop::theta_modulus m(bad);
      FAIL() << "no exception for k = " << bad;
    } catch (const std::domain_error& e) {
      EXPECT_NE(std::string(e.what()).find(eulervop::to_text<double>(bad)), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(eulervop::theta_modulus(std::numeric_limits<double>::quiet_NaN()), std::domain_error);
}

// The inline sin/cos of the theta route against MPFR: within 1 ulp on the kernel's interval
// |x| <= pi/4 (no reduction), and for reduced arguments (|x| up to 1e7, and beside multiples of
// pi/2) within 2 eps (|f| + |x f'|), the rounding of x itself carried through the reduction.
TEST(ThetaDouble, SinCosAgainstMpfr) {
  std::mt19937_64 rng(2718);
  const double eps = eulervop::epsilon<double>();
  double worst_kernel = 0, worst_reduced = 0;
  std::vector<double> xs;
  for (int i = 0; i < 20000; ++i) xs.push_back((2 * random_unit<double>(rng) - 1) * 0.7853981633974483);
  for (double x : {0.0, 1e-300, -1e-20, 1e-8, 0.7853981633974483, -0.7853981633974483}) xs.push_back(x);
  const std::size_t n_kernel = xs.size();
  for (int i = 0; i < 20000; ++i) {
    const double mag = std::exp(std::log(10.0) * (7 * random_unit<double>(rng)));  // 1 .. 1e7
    xs.push_back(random_unit<double>(rng) < 0.5 ? -mag : mag);
  }
  for (int j = -40; j <= 40; ++j) {
    if (j == 0) continue;  // x = 0 is a kernel point above
    const double x = j * 1.5707963267948966;
    xs.push_back(x);
    xs.push_back(std::nextafter(x, 1e9));
    xs.push_back(std::nextafter(x, -1e9));
  }
  mpfr_precision_scope scope(ref_bits<double>());
  for (std::size_t i = 0; i < xs.size(); ++i) {
    double s = 0, c = 0;
    eulervop::detail::sincos_double(xs[i], s, c);
    const mpfr_real xr = to_ref(xs[i]);
    const mpfr_real rs = sin(xr), rc = cos(xr);
    if (i < n_kernel) {
      const double es = rs == 0 ? (s == 0 ? 0.0 : 1e300) : dbl(abs(to_ref(s) - rs) / abs(rs)) / eps;
      const double ec = dbl(abs(to_ref(c) - rc) / abs(rc)) / eps;
      worst_kernel = std::max({worst_kernel, es, ec});
      EXPECT_LE(es, 1) << "sin at x=" << xs[i];
      EXPECT_LE(ec, 1) << "cos at x=" << xs[i];
    } else {
      const mpfr_real ax = abs(xr);
      const double es = dbl(abs(to_ref(s) - rs) / (abs(rs) + ax * abs(rc))) / eps;
      const double ec = dbl(abs(to_ref(c) - rc) / (abs(rc) + ax * abs(rs))) / eps;
      worst_reduced = std::max({worst_reduced, es, ec});
      EXPECT_LE(es, 2) << "sin at x=" << xs[i];
      EXPECT_LE(ec, 2) << "cos at x=" << xs[i];
    }
  }
  std::cout << "[double] sincos_double: worst relative error on |x| <= pi/4 " << worst_kernel
            << " ulp; worst mixed error beyond " << worst_reduced << " eps\n";
}

}  // namespace
