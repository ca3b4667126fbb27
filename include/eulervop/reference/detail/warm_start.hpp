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

  explicit warm_start(std::size_t degree) : n1_(degree + 1), Fd_(degree + 1), bd_(degree + 2), s_(degree + 1) {}

  // Increments at the new nodes (half length hl_new) in `warm`, in double: zero without a
  // previous segment, or where the extrapolation runs wild (worse than a cold start).
  void operator()(const picard_matrices<T>& m, const chebyshev_segment<T, D>* prev, const T& hl_new,
                  components& warm) {
    for (std::size_t i = 0; i < D; ++i) std::fill(warm[i].begin(), warm[i].end(), 0.0);
    if (!prev) return;
    const double ratio = static_cast<double>(hl_new / prev->half_length);
    // The new nodes on the previous segment's scale, s = 1 + ratio (s_j + 1), for every component.
    if (nodes_d_.size() != n1_)
      for (std::size_t j = 0; j < n1_; ++j) nodes_d_.push_back(static_cast<double>(m.basis.nodes[j]));
    for (std::size_t j = 0; j < n1_; ++j) s_[j] = 1.0 + ratio * (nodes_d_[j] + 1.0);
    double ymax = 0;
    for (std::size_t i = 0; i < D; ++i) ymax = std::max(ymax, extrapolate(m, *prev, i, warm[i]));
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
  double extrapolate(const picard_matrices<T>& m, const chebyshev_segment<T, D>& prev, std::size_t i,
                     std::vector<double>& out) {
    for (std::size_t j = 0; j < n1_; ++j) Fd_[j] = static_cast<double>(prev.values[j][i]);
    // Chebyshev coefficients of the degree-N interpolant through the node values.
    coefficients(m.C_d.data());
    double cmax = 0;
    for (std::size_t k = 0; k < n1_; ++k) cmax = std::max(cmax, std::abs(bd_[k]));
    // Coefficients at the double noise floor only amplify under extrapolation: drop them.
    for (std::size_t k = 1; k < n1_; ++k)
      if (std::abs(bd_[k]) < 1e-15 * cmax) bd_[k] = 0;
    const double p1 = clenshaw<double>(bd_.data(), n1_, 1, 1.0);
    std::size_t j = 0;
    for (; j + block <= n1_; j += block) at_new_nodes<block>(j, p1, out);
    for (; j < n1_; ++j) at_new_nodes<1>(j, p1, out);
    return cmax;
  }

  // The interpolant's value, minus p1, at the new nodes j0 .. j0 + B - 1: B Clenshaw recurrences
  // (chebyshev_basis.hpp) side by side, each with the operations of clenshaw<double> in its
  // order (the same bits). One alone is bound by the latency of its multiply, subtract and add;
  // independent ones overlap (the warm start was a tenth of a quad run on the paper scene).
  template <std::size_t B>
  [[gnu::always_inline]] void at_new_nodes(std::size_t j0, double p1, std::vector<double>& out) const {
    const double* s = &s_[j0];
    std::array<double, B> two_s, b1{}, b2{};
    for (std::size_t q = 0; q < B; ++q) two_s[q] = s[q] + s[q];
    for (std::size_t k = n1_; k-- > 1;) {
      const double c = bd_[k];
      for (std::size_t q = 0; q < B; ++q) {
        double b0 = two_s[q] * b1[q];
        b0 -= b2[q];
        b0 += c;
        b2[q] = b1[q];
        b1[q] = b0;
      }
    }
    for (std::size_t q = 0; q < B; ++q) out[j0 + q] = (s[q] * b1[q] - b2[q] + bd_[0]) - p1;
  }

  // bd_ = C Fd_ (C: values to Chebyshev coefficients, row-major), each row's sum in order over
  // the columns; four rows side by side, so that their serial sums overlap.
  void coefficients(const double* C) {
    std::size_t k = 0;
    for (; k + 4 <= n1_; k += 4) {
      const double *r0 = C + k * n1_, *r1 = r0 + n1_, *r2 = r1 + n1_, *r3 = r2 + n1_;
      double a0 = 0, a1 = 0, a2 = 0, a3 = 0;
      for (std::size_t j = 0; j < n1_; ++j) {
        a0 += r0[j] * Fd_[j];
        a1 += r1[j] * Fd_[j];
        a2 += r2[j] * Fd_[j];
        a3 += r3[j] * Fd_[j];
      }
      bd_[k] = a0;
      bd_[k + 1] = a1;
      bd_[k + 2] = a2;
      bd_[k + 3] = a3;
    }
    for (; k < n1_; ++k) {
      double a = 0;
      for (std::size_t j = 0; j < n1_; ++j) a += C[k * n1_ + j] * Fd_[j];
      bd_[k] = a;
    }
  }

  static constexpr std::size_t block = 8;

  std::size_t n1_;
  std::vector<double> Fd_, bd_;  // one component's node values, and its coefficients
  std::vector<double> nodes_d_, s_;  // the nodes in double; the new nodes on the previous scale
};

}  // namespace eulervop::detail
