// The dense output evaluated at sample times known in advance, as the segments arrive, keeping
// only the latest segment: memory does not grow with the span.
#pragma once

#include <eulervop/reference/segment.hpp>

#include <cstddef>
#include <functional>
#include <stdexcept>
#include <utility>
#include <vector>

namespace eulervop {

// Receives each accepted segment in order, with the Lobatto nodes s_j of the run (the same for
// every segment). The segment is only valid during the call.
template <scalar T, std::size_t D = 3>
using segment_sink = std::function<void(const chebyshev_segment<T, D>& segment, const std::vector<T>& nodes)>;

// Sees a segment before the integrator accepts it; false refuses it (it is shortened and solved
// again).
template <scalar T, std::size_t D = 3>
using segment_check = std::function<bool(const chebyshev_segment<T, D>& segment, const std::vector<T>& nodes)>;

// Sample times in non-decreasing order. Each sample comes from the same segment
// dense_trajectory would use (the last one starting at or before it), so the values are
// identical. `emit(index, tau, y)` receives them in order.
template <scalar T, std::size_t D = 3>
class segment_sampler {
 public:
  using emit_function = std::function<void(std::size_t index, const T& tau, const std::array<T, D>& y)>;

  segment_sampler(const std::vector<T>& taus, emit_function emit) : taus_(taus), emit_(std::move(emit)) {
    for (std::size_t i = 1; i < taus_.size(); ++i)
      if (taus_[i] < taus_[i - 1]) throw std::invalid_argument("segment_sampler: sample times must not decrease");
  }

  // The sink to pass to chebyshev_picard::run_segments.
  void operator()(const chebyshev_segment<T, D>& seg, const std::vector<T>& nodes) {
    if (!held_) {
      if (next_ < taus_.size() && taus_[next_] < seg.tau_begin)
        throw std::out_of_range("segment_sampler: a sample time precedes the integrated span");
      nodes_ = nodes;
      held_ = true;
    } else {
      emit_before(seg.tau_begin);
    }
    last_ = seg;
  }

  // After the run: the samples up to the end of the last segment. Throws std::out_of_range if a
  // sample lies beyond it.
  void finish() {
    if (!held_) throw std::logic_error("segment_sampler: no segment was integrated");
    for (; next_ < taus_.size() && taus_[next_] <= last_.tau_end; ++next_)
      emit_(next_, taus_[next_], evaluate_segment(last_, nodes_, taus_[next_]));
    if (next_ < taus_.size()) throw std::out_of_range("segment_sampler: a sample time lies beyond the integrated span");
  }

 private:
  void emit_before(const T& tau) {
    for (; next_ < taus_.size() && taus_[next_] < tau; ++next_)
      emit_(next_, taus_[next_], evaluate_segment(last_, nodes_, taus_[next_]));
  }

  const std::vector<T>& taus_;
  emit_function emit_;
  std::size_t next_ = 0;
  bool held_ = false;
  chebyshev_segment<T, D> last_;
  std::vector<T> nodes_;
};

}  // namespace eulervop
