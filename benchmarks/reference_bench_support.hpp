// What the reference benchmarks share (bench_reference.cpp, bench_problems.cpp): Boost.Odeint on
// Boost.Multiprecision scalars, the wall clock, full-precision text, progress lines on standard
// error, and the directory where the truths are cached.
#pragma once

#include <eulervop/core/scalar.hpp>

#include <boost/multiprecision/float128.hpp>
#include <boost/multiprecision/mpfr.hpp>
#include <boost/numeric/odeint.hpp>

#include <array>
#include <cstddef>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <ios>
#include <string>
#include <system_error>
#include <utility>

namespace eulervop::bench {

// Boost.Odeint's value type for the MPFR peer: expression templates off, since odeint mixes plain
// values with abs(...) in std::max and friends, which does not deduce with Boost.Multiprecision
// expression templates. (float128 is Boost's number<float128_backend, et_off> already.)
using odeint_mpfr = boost::multiprecision::number<boost::multiprecision::mpfr_float_backend<0>,
                                                  boost::multiprecision::et_off>;

}  // namespace eulervop::bench

// odeint's extract_value_type recurses into number::value_type, which for a real number is the
// number itself: it never ends (docs/design.md section 2). Stop the recursion at the scalar.
namespace boost::numeric::odeint::detail {
template <>
struct extract_value_type<eulervop::quad, void> {
  typedef eulervop::quad type;
};
template <>
struct extract_value_type<eulervop::bench::odeint_mpfr, void> {
  typedef eulervop::bench::odeint_mpfr type;
};
}  // namespace boost::numeric::odeint::detail

namespace eulervop::bench {

using clock_type = std::chrono::steady_clock;

inline double seconds_since(clock_type::time_point t0) {
  return std::chrono::duration<double>(clock_type::now() - t0).count();
}

// Full-precision text of an odeint MPFR value (round-trip, like eulervop::to_text).
inline std::string text_of(const odeint_mpfr& x) {
  const unsigned digits = static_cast<unsigned>(std::ceil(x.precision() * 3.3219280948873623 * 0.30102999566398120)) + 3;
  return x.str(static_cast<std::streamsize>(digits), std::ios_base::scientific);
}
inline std::string text_of(const quad& x) { return to_text(x); }
inline std::string text_of(const mpfr_real& x) { return to_text(x); }

// A line on standard error at most every 2 s: how far a long integration has come.
class progress_printer {
 public:
  explicit progress_printer(std::string label) : label_(std::move(label)), t0_(clock_type::now()) {}
  void operator()(double tau, std::size_t segments) {
    const double s = seconds_since(t0_);
    if (s - last_ >= 2.0) {
      std::fprintf(stderr, "  %s: tau = %.2f, %zu segments, after %.0f s\n", label_.c_str(), tau, segments, s);
      last_ = s;
    }
  }

 private:
  std::string label_;
  clock_type::time_point t0_;
  double last_ = 0;
};

// The truths are cached next to the executable (the working directory if that is unknown).
inline std::filesystem::path executable_dir() {
  std::error_code ec;
  auto p = std::filesystem::canonical("/proc/self/exe", ec);
  return ec ? std::filesystem::current_path() : p.parent_path();
}

// The peer every reference benchmark compares with: Boost.Odeint's bulirsch_stoer on a state of
// D components (3 rates, or 7 with the attitude coupled), abs = rel = tol.
template <class V, std::size_t D = 3>
auto bulirsch_stoer_maker() {
  return [](const V& tol) { return boost::numeric::odeint::bulirsch_stoer<std::array<V, D>, V>(tol, tol); };
}

}  // namespace eulervop::bench
