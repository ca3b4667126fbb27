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
#include <eulervop/reference/detail/double4.hpp>

#include <cstddef>
#include <cstring>
#include <vector>

// x86-64 with GCC or Clang: the product also compiled for AVX, chosen at run time.
#if defined(__x86_64__) && defined(__GNUC__)
#define EULERVOP_DD_AVX 1
#else
#define EULERVOP_DD_AVX 0
#endif

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
    interleave();
  }

  std::size_t rows() const { return rows_; }
  std::size_t cols() const { return cols_; }

  // y[r] = sum_k A[r][k] x[k] as y_hi[r] + y_lo[r], rows [first_row, rows). Not const: it
  // splits x into scratch storage (one object per thread). Compiled for AVX too, chosen at run
  // time where the processor has it (no fused multiply-add either way: the same bits).
  void multiply(const double* x_hi, const double* x_lo, double* y_hi, double* y_lo,
                std::size_t first_row = 0) {
#if EULERVOP_DD_AVX
    static const bool avx = __builtin_cpu_supports("avx");
    if (avx) return multiply_avx(x_hi, x_lo, y_hi, y_lo, first_row);
#endif
    multiply_body(x_hi, x_lo, y_hi, y_lo, first_row);
  }

 private:
  // Rows in blocks of four, the last 4 nb rows of the matrix: block b holds rows
  // first_block_row_ + 4 b .. + 3, stored column by column, the four rows' entries of a column
  // side by side (one double4 each), for the four rows' sums in the lanes of one vector.
  static constexpr std::size_t lanes = 4;

#if EULERVOP_DD_AVX
  [[gnu::target("avx")]] void multiply_avx(const double* x_hi, const double* x_lo, double* y_hi, double* y_lo,
                                           std::size_t first_row) {
    multiply_body(x_hi, x_lo, y_hi, y_lo, first_row);
  }
#endif

  [[gnu::always_inline]] void multiply_body(const double* x_hi, const double* x_lo, double* y_hi, double* y_lo,
                                            std::size_t first_row) {
    for (std::size_t k = 0; k < cols_; ++k) split(x_hi[k], x1_[k], x2_[k]);
    std::size_t r = first_row;
    // The rows before the blocks, and those of a block that first_row cuts, one by one.
    for (; r < rows_ && (r < first_block_row_ || (r - first_block_row_) % lanes != 0); ++r)
      row(r, x_hi, x_lo, y_hi[r], y_lo[r]);
    for (; r < rows_; r += lanes) block(r, x_hi, x_lo, y_hi + r, y_lo + r);
  }

  // Row r: Dot2's sum (Ogita, Rump & Oishi), the products split exactly, in the order of k.
  [[gnu::always_inline]] void row(std::size_t r, const double* x_hi, const double* x_lo, double& y_hi,
                                  double& y_lo) const {
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
    y_hi = hi;
    y_lo = c - (hi - s);
  }

  // Rows r .. r + 3 (a block's first row r), each lane the operations of row() on its row: the
  // four serial sums overlap instead of each waiting on its own additions.
  [[gnu::always_inline]] void block(std::size_t r, const double* x_hi, const double* x_lo, double* y_hi,
                                    double* y_lo) const {
    const std::size_t base = (r - first_block_row_) * cols_;  // lanes * (block index) * cols_
    const double* h = &bhi_[base];
    const double* l = &blo_[base];
    const double* a1 = &bh1_[base];
    const double* a2 = &bh2_[base];
    double4 s{}, c{};
    for (std::size_t k = 0; k < cols_; ++k) {
      double4 hk, lk, a1k, a2k;
      std::memcpy(&hk, h + lanes * k, sizeof hk);
      std::memcpy(&lk, l + lanes * k, sizeof lk);
      std::memcpy(&a1k, a1 + lanes * k, sizeof a1k);
      std::memcpy(&a2k, a2 + lanes * k, sizeof a2k);
      const double xh = x_hi[k], xl = x_lo[k], x1 = x1_[k], x2 = x2_[k];
      const double4 p = hk * xh;
      const double4 e = ((a1k * x1 - p) + a1k * x2 + a2k * x1) + a2k * x2;
      const double4 t = s + p;
      const double4 bb = t - s;
      const double4 err = (s - (t - bb)) + (p - bb);
      s = t;
      c += err + e + (hk * xl + lk * xh);
    }
    const double4 hi = s + c;
    const double4 lo = c - (hi - s);
    for (std::size_t q = 0; q < lanes; ++q) {
      y_hi[q] = hi[q];
      y_lo[q] = lo[q];
    }
  }

  // The block copies of hi_, lo_, h1_, h2_ (see above).
  void interleave() {
    const std::size_t nb = rows_ / lanes;
    first_block_row_ = rows_ - lanes * nb;
    for (std::vector<double>* v : {&bhi_, &blo_, &bh1_, &bh2_}) v->assign(lanes * nb * cols_, 0.0);
    for (std::size_t b = 0; b < nb; ++b)
      for (std::size_t k = 0; k < cols_; ++k)
        for (std::size_t q = 0; q < lanes; ++q) {
          const std::size_t from = (first_block_row_ + lanes * b + q) * cols_ + k;
          const std::size_t to = (b * cols_ + k) * lanes + q;
          bhi_[to] = hi_[from];
          blo_[to] = lo_[from];
          bh1_[to] = h1_[from];
          bh2_[to] = h2_[from];
        }
  }

  std::size_t rows_ = 0, cols_ = 0;
  std::vector<double> hi_, lo_, h1_, h2_;
  std::size_t first_block_row_ = 0;
  std::vector<double> bhi_, blo_, bh1_, bh2_;
  std::vector<double> x1_, x2_;
};

}  // namespace eulervop::detail
