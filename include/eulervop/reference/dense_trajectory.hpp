// The reference solution on its whole span, evaluable anywhere in it to full precision.
#pragma once

#include <eulervop/reference/segment.hpp>

#include <algorithm>
#include <stdexcept>
#include <utility>
#include <vector>

namespace eulervop {

// It keeps every segment, so its memory grows with the span; a caller who knows its sample times
// in advance can use segment_sampler instead, which keeps one.
template <scalar T, std::size_t D = 3>
class dense_trajectory {
 public:
  dense_trajectory() = default;
  dense_trajectory(std::vector<chebyshev_segment<T, D>> segs, std::vector<T> nodes)
      : segs_(std::move(segs)), nodes_(std::move(nodes)) {}

  const T& tau_begin() const { return segs_.front().tau_begin; }
  const T& tau_end() const { return segs_.back().tau_end; }
  std::size_t segments() const { return segs_.size(); }
  const std::vector<chebyshev_segment<T, D>>& segment_list() const { return segs_; }

  // y(tau), from the last segment whose start is <= tau. Throws std::out_of_range outside
  // [tau_begin, tau_end].
  std::array<T, D> operator()(const T& tau) const {
    if (segs_.empty() || !(tau >= tau_begin() && tau <= tau_end()))
      throw std::out_of_range("dense_trajectory: tau outside the integrated span");
    auto it = std::upper_bound(segs_.begin(), segs_.end(), tau,
                               [](const T& t, const chebyshev_segment<T, D>& s) { return t < s.tau_begin; });
    return evaluate_segment(*(it - 1), nodes_, tau);
  }

 private:
  std::vector<chebyshev_segment<T, D>> segs_;
  std::vector<T> nodes_;
};

}  // namespace eulervop
