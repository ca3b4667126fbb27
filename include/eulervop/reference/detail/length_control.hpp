// The reference integrator's degree and its segment length (its step-size control).
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/settings.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <type_traits>

namespace eulervop {

namespace detail {

// log|x| in double for any T, also where |x| underflows double (MPFR at thousands of bits).
template <scalar T>
double log_abs(const T& x) {
  using std::frexp;
  using std::abs;
  using std::log;
  if constexpr (std::is_same_v<T, quad>) {
    // A normal binary128 from its bits: m = significand 2^-113 in [1/2, 1), whose double is the
    // integer's conversion (rounded to nearest, ties to even, as the soft-float one) times 2^-113;
    // the same value as the frexp below, without the library calls.
    unsigned __int128 bits;
    std::memcpy(&bits, &x.backend().value(), sizeof bits);
    const int biased = static_cast<int>(bits >> 112) & 0x7fff;
    if (biased != 0 && biased != 0x7fff) {
      const unsigned __int128 significand = (bits & ((static_cast<unsigned __int128>(1) << 112) - 1)) |
                                            (static_cast<unsigned __int128>(1) << 112);
      return std::log(static_cast<double>(significand) * 0x1p-113) + (biased - 16382) * 0.69314718055994531;
    }
  }
  if (x == 0) return -std::numeric_limits<double>::infinity();
  int e = 0;
  T m = frexp(T(abs(x)), &e);
  return std::log(static_cast<double>(m)) + e * 0.69314718055994531;
}

// Default Chebyshev degree: the truncation term of a segment is ~ rho^-N for a Bernstein ellipse
// rho; the cost per unit tau is ~ N^2 / L(rho), minimal near N ln(rho) = 1.9 N, hence
// N ~ digits * ln(10) / 1.9 ~ 1.2 digits (the constant was then tuned on the paper scene).
inline unsigned default_degree(unsigned bits) {
  const double digits = bits * 0.30102999566398120;
  return static_cast<unsigned>(std::clamp(std::lround(1.2 * digits), 12L, 600L));
}

// The bits the run must resolve: those of T, or fewer when a looser tolerance is asked. The
// default degree follows them, so a loose tolerance gets short cheap segments rather than long
// ones on which the Picard sweeps stop contracting.
template <scalar T>
unsigned effective_bits(const picard_settings& s) {
  const unsigned bits = significand_bits<T>();
  if (!(s.tolerance > 0)) return bits;
  const double tol_bits = -std::log2(s.tolerance);
  return static_cast<unsigned>(std::clamp(tol_bits, 8.0, static_cast<double>(bits)));
}

// The segment length of the reference integrator (its step-size control). After a converged
// segment the length follows the tail estimate's excess over the tolerance: the terms decay like
// rho^-(N+1), so the length scales by exp(-excess / (N+1)), times a safety factor of 0.85 (0.8
// after a refusal). The tail varies along an orbit, and with 0.9 a quarter of the segments of a
// long weakly torqued run were refused (each costing a whole solve); 0.85 refuses under 10% there
// for 2-4% more segments on the paper scene (docs/benchmarks.md). After a failed iteration it halves, and the length that failed caps
// growth, relaxing by 5% per accepted segment, so the tail estimate cannot push segments back
// into non-convergence every step.
class segment_length_control {
 public:
  segment_length_control(double first, std::size_t degree)
      : length_(first), nodes_(static_cast<double>(degree + 1)) {}

  double length() const { return length_; }

  // A segment of length `used` converged with the tail estimate's excess (the log of estimate
  // over tolerance): accepted unless the excess exceeds 8.
  bool converged(double used, double excess_log) {
    if (excess_log > std::log(8.0)) {
      next_ = used * std::max(0.2, 0.8 * std::exp(-excess_log / nodes_));
      return false;
    }
    next_ = used * std::clamp(0.85 * std::exp(-excess_log / nodes_), 0.5, 2.0);
    return true;
  }
  // The Picard iteration did not converge on a segment of length `used`.
  void failed(double used) {
    next_ = used * 0.5;
    cap_ = 0.8 * used;
  }
  // After a refused segment starting at tau: takes the shorter length, or returns false when the
  // length collapsed (below 1e-14 relative) or more than 40 segments in a row were refused.
  bool retry(double tau) {
    if (++refusals_ > 40 || next_ < 1e-14 * std::max(1.0, std::abs(tau))) return false;
    length_ = next_;
    return true;
  }
  void accepted() {
    refusals_ = 0;
    cap_ *= 1.05;
    length_ = std::min(next_, cap_);
  }

 private:
  double length_;
  double nodes_;  // N + 1
  double next_ = 0;
  double cap_ = std::numeric_limits<double>::infinity();
  int refusals_ = 0;
};

}  // namespace detail

}  // namespace eulervop
