// The first iterate of a segment: the previous segment's interpolant extrapolated to the new
// nodes (docs/design.md section 3.2, warm starts).
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/detail/chebyshev_basis.hpp>
#include <eulervop/reference/detail/picard_matrices.hpp>
#include <eulervop/reference/segment.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace eulervop::detail {

template <scalar T, std::size_t D>
class warm_start {
 public:
  using components = std::array<std::vector<double>, D>;

  explicit warm_start(std::size_t degree) : n1_(degree + 1), Fd_(degree + 1), bd_(degree + 2) {}

  // Increments at the new nodes (half length hl_new) in `warm`, in double: zero without a
  // previous segment, or where the extrapolation runs wild (worse than a cold start).
  void operator()(const picard_matrices<T>& m, const chebyshev_segment<T, D>* prev, const T& hl_new,
                  components& warm) {
    for (std::size_t i = 0; i < D; ++i) std::fill(warm[i].begin(), warm[i].end(), 0.0);
    if (!prev) return;
    const double ratio = static_cast<double>(hl_new / prev->half_length);
    double ymax = 0;
    for (std::size_t i = 0; i < D; ++i) ymax = std::max(ymax, extrapolate(m, *prev, i, ratio, warm[i]));
    for (std::size_t i = 0; i < D; ++i)
      for (std::size_t j = 0; j < n1_; ++j)
        if (!std::isfinite(warm[i][j]) || std::abs(warm[i][j]) > 8 * (1 + ratio) * ymax + 1) {
          for (std::size_t c = 0; c < D; ++c) std::fill(warm[c].begin(), warm[c].end(), 0.0);
          return;
        }
  }

 private:
  // Component i of the previous segment's interpolant at the new nodes, minus its value at the
  // previous segment's end. Returns the largest Chebyshev coefficient.
  double extrapolate(const picard_matrices<T>& m, const chebyshev_segment<T, D>& prev, std::size_t i, double ratio,
                     std::vector<double>& out) {
    for (std::size_t j = 0; j < n1_; ++j) Fd_[j] = static_cast<double>(prev.values[j][i]);
    // Chebyshev coefficients of the degree-N interpolant through the node values.
    double cmax = 0;
    for (std::size_t k = 0; k < n1_; ++k) {
      const double* row = &m.C_d[k * n1_];
      double a = 0;
      for (std::size_t j = 0; j < n1_; ++j) a += row[j] * Fd_[j];
      bd_[k] = a;
      cmax = std::max(cmax, std::abs(a));
    }
    // Coefficients at the double noise floor only amplify under extrapolation: drop them.
    for (std::size_t k = 1; k < n1_; ++k)
      if (std::abs(bd_[k]) < 1e-15 * cmax) bd_[k] = 0;
    const double p1 = clenshaw<double>(bd_.data(), n1_, 1, 1.0);
    for (std::size_t j = 0; j < n1_; ++j) {
      const double s = 1.0 + ratio * (static_cast<double>(m.basis.nodes[j]) + 1.0);
      out[j] = clenshaw<double>(bd_.data(), n1_, 1, s) - p1;
    }
    return cmax;
  }

  std::size_t n1_;
  std::vector<double> Fd_, bd_;  // one component's node values, and its coefficients
};

}  // namespace eulervop::detail
