// Many samples on one segment of quad dense output: the segment's node values turned into a
// Chebyshev series once, then each sample by Clenshaw's recurrence in 128-bit fixed point.
//
// The barycentric formula of evaluate_segment (segment.hpp) costs N+1 soft-float quad divisions
// per sample, about 5 us at N = 41. A check of a million rows puts a thousand or more samples on
// each segment, so a transform per segment, (N+1)^2 exact integer products, pays for itself after
// a few samples; after it a sample costs N steps of integer arithmetic per component.
//
// Accuracy: the coefficients come from an exact integer matrix product rounded once
// (fixed_point_matrix, |error| <= 2^-116 (N+1) max_j |M_kj| max|v|). The recurrence
// b_k = c_k + 2 s b_{k+1} - b_{k+2} runs on integers scaled so that (N+1) sum|c_k| < 2^124, which
// bounds every |b_k| (b_k = sum_j c_j U_{j-k}(s) and |U_m| <= m + 1 on [-1, 1]); each product is
// rounded to the nearest unit, and a unit error in b_k reaches the sum multiplied by at most
// |U_k(s)| <= k + 1. tests/test_segment_series.cpp measures both forms against the interpolant
// evaluated exactly in 256-bit MPFR.
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/detail/chebyshev_basis.hpp>
#include <eulervop/reference/detail/fixed_point_matvec.hpp>
#include <eulervop/reference/segment.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace eulervop::detail {

// round(a b 2^-shift) for signed integers with |a| <= 2^126, |b| < 2^125 and 64 < shift < 128, by
// 64-bit halves: a b = ah bh 2^128 + (ah bl + bh al) 2^64 + al bl.
inline __int128 product_shifted(__int128 a, __int128 b, int shift) {
  const auto ah = static_cast<std::int64_t>(a >> 64), bh = static_cast<std::int64_t>(b >> 64);
  const auto al = static_cast<std::uint64_t>(a), bl = static_cast<std::uint64_t>(b);
  const __int128 high = static_cast<__int128>(ah) * bh;  // |high| < 2^124
  // a b 2^-64, its lowest bits dropped (below one unit of 2^-64 of the result's scale).
  const __int128 middle = static_cast<__int128>(ah) * static_cast<__int128>(bl) +
                          static_cast<__int128>(bh) * static_cast<__int128>(al) +
                          static_cast<__int128>((static_cast<unsigned __int128>(al) * bl) >> 64);
  const int s = shift - 64;
  return (high << (64 - s)) + ((middle + (static_cast<__int128>(1) << (s - 1))) >> s);
}

// The Lobatto-to-Chebyshev transform of one run's nodes, as an integer matrix (built once).
class lobatto_transform_quad {
 public:
  explicit lobatto_transform_quad(std::size_t degree)
      : degree_(degree), matrix_(lobatto_to_chebyshev<quad>(degree, lobatto_cosines<quad>(degree)), degree + 1,
                                 degree + 1) {}
  std::size_t degree() const { return degree_; }
  // c = M v for one component's node values (not const: the matrix splits v in scratch storage).
  void apply(const quad* v, quad* c) { matrix_.multiply(v, c); }

 private:
  std::size_t degree_;
  fixed_point_matrix<quad> matrix_;
};

// One segment's increments as D Chebyshev series with integer coefficients, evaluated anywhere in
// the segment; the stored value is returned exactly at a node, as evaluate_segment does.
template <std::size_t D>
class segment_series_quad {
 public:
  segment_series_quad(const chebyshev_segment<quad, D>& seg, const std::vector<quad>& nodes,
                      lobatto_transform_quad& transform)
      : seg_(&seg), nodes_(&nodes), n1_(nodes.size()), coefficients_(D * n1_) {
    std::vector<quad> v(n1_), c(n1_);
    for (std::size_t i = 0; i < D; ++i) {
      for (std::size_t j = 0; j < n1_; ++j) v[j] = seg.values[j][i];
      transform.apply(v.data(), c.data());
      scale_[i] = shift_for(c);
      for (std::size_t k = 0; k < n1_; ++k)
        coefficients_[i * n1_ + k] = scale_[i] ? fixed_point_matrix<quad>::scaled_integer(c[k], scale_[i]) : 0;
    }
  }

  std::array<quad, D> operator()(const quad& tau) const {
    const chebyshev_segment<quad, D>& seg = *seg_;
    std::array<quad, D> out;
    quad s = (tau - seg.tau_begin) / seg.half_length - 1;
    if (greater_value(s, quad(1))) s = 1;
    const std::size_t hit = node_at(tau, s);
    if (hit < n1_) {
      for (std::size_t i = 0; i < D; ++i) out[i] = seg.base[i] + (seg.base_lo[i] + seg.values[hit][i]);
      return out;
    }
    const __int128 S = fixed_point_matrix<quad>::scaled_integer(s, 126);  // |s| <= 1
    for (std::size_t i = 0; i < D; ++i) out[i] = seg.base[i] + (seg.base_lo[i] + component(i, S));
    return out;
  }

 private:
  // The shift that brings (N+1) sum_k |c_k| below 2^124 (0 when every c_k is 0).
  int shift_for(const std::vector<quad>& c) const {
    double sum = 0;
    for (const quad& x : c) sum += std::abs(static_cast<double>(x));
    if (!(sum > 0)) return 0;
    int e = 0;
    (void)std::frexp(sum * 1.0000001 * static_cast<double>(n1_), &e);  // < 2^e, double rounding covered
    return 124 - e;
  }

  // The node s equals exactly, or n1_ (the start of the segment is node 0 by its time).
  std::size_t node_at(const quad& tau, const quad& s) const {
    if (equal_values(tau, seg_->tau_begin)) return 0;
    const std::vector<quad>& x = *nodes_;
    const auto it = std::lower_bound(x.begin(), x.end(), s, [](const quad& a, const quad& b) { return greater_value(b, a); });
    return it != x.end() && equal_values(*it, s) ? static_cast<std::size_t>(it - x.begin()) : n1_;
  }

  // Clenshaw: sum_k c_k T_k(s) = c_0 + s b_1 - b_2, b_k = c_k + 2 s b_{k+1} - b_{k+2}.
  quad component(std::size_t i, __int128 S) const {
    if (!scale_[i]) return 0;
    const __int128* c = &coefficients_[i * n1_];
    __int128 b1 = 0, b2 = 0;
    for (std::size_t k = n1_ - 1; k >= 1; --k) {
      const __int128 b0 = c[k] + product_shifted(S, b1, 125) - b2;
      b2 = b1;
      b1 = b0;
    }
    const __int128 sum = c[0] + product_shifted(S, b1, 126) - b2;
    return fixed_point_matrix<quad>::rounded(sum >> 64, static_cast<std::uint64_t>(sum), -scale_[i]);
  }

  const chebyshev_segment<quad, D>* seg_;
  const std::vector<quad>* nodes_;
  std::size_t n1_;
  std::vector<__int128> coefficients_;  // D rows of N+1
  std::array<int, D> scale_{};
};

}  // namespace eulervop::detail
