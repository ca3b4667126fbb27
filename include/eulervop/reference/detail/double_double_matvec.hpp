// y = A x in double-double arithmetic (about 106 bits), for a matrix given as the sum of two
// doubles per entry and a vector given as hi + lo doubles.
//
// Used by the reference integrator for the wide residual whose only job is to drive the next
// correction to ~1e-32 relative: double-double is an order of magnitude cheaper than soft-float
// quad there, and the following residual in the full wide type decides convergence, so the
// result never rests on this one (docs/design.md section 3.2, mixed precision).
//
// Products are exact by Dekker's splitting (Dekker 1971; no hardware FMA assumed), sums by
// Knuth's TwoSum; the low-order cross terms are accumulated in plain double (Ogita, Rump &
// Oishi 2005, "Dot2"): error ~ n u^2 sum |a_k x_k| + u^2 |y|.
#pragma once

#include <eulervop/core/error_free.hpp>
#include <eulervop/core/scalar.hpp>

#include <cstddef>
#include <vector>

namespace eulervop::detail {

class double_double_matrix {
 public:
  double_double_matrix() = default;
  // Entries of a row-major rows x cols matrix, from any type convertible to double whose value
  // minus its double rounding is again convertible (quad, MPFR).
  template <scalar T>
  double_double_matrix(const std::vector<T>& a, std::size_t rows, std::size_t cols)
      : rows_(rows), cols_(cols), hi_(a.size()), lo_(a.size()), h1_(a.size()), h2_(a.size()),
        x1_(cols), x2_(cols) {
    for (std::size_t i = 0; i < a.size(); ++i) {
      const double_double v = to_double_double(a[i]);
      hi_[i] = v.hi;
      lo_[i] = v.lo;
      split(hi_[i], h1_[i], h2_[i]);
    }
  }

  std::size_t rows() const { return rows_; }
  std::size_t cols() const { return cols_; }

  // y[r] = sum_k A[r][k] x[k] as y_hi[r] + y_lo[r], rows [first_row, rows). Not const: it
  // splits x into scratch storage (one object per thread).
  void multiply(const double* x_hi, const double* x_lo, double* y_hi, double* y_lo,
                std::size_t first_row = 0) {
    for (std::size_t k = 0; k < cols_; ++k) split(x_hi[k], x1_[k], x2_[k]);
    for (std::size_t r = first_row; r < rows_; ++r) {
      const double* h = &hi_[r * cols_];
      const double* l = &lo_[r * cols_];
      const double* a1 = &h1_[r * cols_];
      const double* a2 = &h2_[r * cols_];
      double s = 0, c = 0;
      for (std::size_t k = 0; k < cols_; ++k) {
        const double p = h[k] * x_hi[k];
        const double x1 = x1_[k], x2 = x2_[k];
        const double e = ((a1[k] * x1 - p) + a1[k] * x2 + a2[k] * x1) + a2[k] * x2;  // p + e = h x exactly
        const double t = s + p;
        const double bb = t - s;
        const double err = (s - (t - bb)) + (p - bb);  // s + p = t + err exactly
        s = t;
        c += err + e + (h[k] * x_lo[k] + l[k] * x_hi[k]);
      }
      const double hi = s + c;
      y_hi[r] = hi;
      y_lo[r] = c - (hi - s);
    }
  }

 private:
  std::size_t rows_ = 0, cols_ = 0;
  std::vector<double> hi_, lo_, h1_, h2_;
  std::vector<double> x1_, x2_;
};

}  // namespace eulervop::detail
