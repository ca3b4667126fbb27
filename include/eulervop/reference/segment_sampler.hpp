// The dense output evaluated at sample times known in advance, as the segments arrive, keeping
// only the latest segment: memory does not grow with the span.
#pragma once

#include <eulervop/reference/detail/segment_series.hpp>
#include <eulervop/reference/segment.hpp>

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <type_traits>
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

// The sample times, in non-decreasing order, one at a time: next(tau) sets the next one and
// returns true, or returns false when there is none. A sampler asks for sample i + 1 only after it
// has emitted sample i, so the source may produce each time as it is asked (a file read row by
// row): the times need not be held in memory at all.
template <scalar T>
using sample_time_source = std::function<bool(T& tau)>;

// A source over times held in a vector (which must outlive it).
template <scalar T>
sample_time_source<T> times_in(const std::vector<T>& taus) {
  return [&taus, next = std::size_t(0)](T& tau) mutable {
    if (next == taus.size()) return false;
    tau = taus[next++];
    return true;
  };
}

// Sample times in non-decreasing order. Each sample comes from the same segment
// dense_trajectory would use (the last one starting at or before it). `emit(index, tau, y)`
// receives them in order.
//
// In quad, the first few samples of a segment are evaluated by the barycentric formula
// (evaluate_segment); from the (series_after + 1)-th on, the segment is turned into Chebyshev
// series once and each sample costs integer arithmetic only (detail/segment_series.hpp), so a
// million samples take about a second. The two agree with the exact interpolant to a few units in
// the last place of the segment's increment (tests/test_segment_series.cpp); which one a sample
// gets depends only on the sample times, so a run is deterministic. Other types always take
// evaluate_segment.
template <scalar T, std::size_t D = 3>
class segment_sampler {
 public:
  using emit_function = std::function<void(std::size_t index, const T& tau, const std::array<T, D>& y)>;
  static constexpr std::size_t series_after = 4;

  segment_sampler(sample_time_source<T> source, emit_function emit)
      : source_(std::move(source)), emit_(std::move(emit)) {
    pull();
  }
  segment_sampler(const std::vector<T>& taus, emit_function emit) : segment_sampler(times_in(taus), std::move(emit)) {}

  // The sink to pass to chebyshev_picard::run_segments.
  void operator()(const chebyshev_segment<T, D>& seg, const std::vector<T>& nodes) {
    if (!held_) {
      if (pending_ && *pending_ < seg.tau_begin)
        throw std::out_of_range("segment_sampler: a sample time precedes the integrated span");
      nodes_ = nodes;
      held_ = true;
    } else {
      emit_before(seg.tau_begin, false);
    }
    last_ = seg;
    in_segment_ = 0;
    series_.reset();
  }

  // After the run: the samples up to the end of the last segment. Throws std::out_of_range if a
  // sample lies beyond it.
  void finish() {
    if (!held_) throw std::logic_error("segment_sampler: no segment was integrated");
    emit_before(last_.tau_end, true);
    if (pending_) throw std::out_of_range("segment_sampler: a sample time lies beyond the integrated span");
  }

 private:
  // Emits the pending samples before `tau` (up to it when `inclusive`), each before the next is asked for.
  void emit_before(const T& tau, bool inclusive) {
    while (pending_ && (*pending_ < tau || (inclusive && *pending_ <= tau))) {
      const T at = *pending_;
      emit_(next_, at, evaluate(at));
      ++next_;
      pull();
    }
  }

  void pull() {
    T tau;
    if (!source_(tau)) {
      pending_.reset();
      return;
    }
    if (pending_ && tau < *pending_) throw std::invalid_argument("segment_sampler: sample times must not decrease");
    pending_ = std::move(tau);
  }

  std::array<T, D> evaluate(const T& tau) {
    if constexpr (std::is_same_v<T, quad>) {
      if (++in_segment_ > series_after) {
        if (!transform_) transform_ = std::make_unique<detail::lobatto_transform_quad>(nodes_.size() - 1);
        if (!series_) series_.emplace(last_, nodes_, *transform_);
        return (*series_)(tau);
      }
    }
    return evaluate_segment(last_, nodes_, tau);
  }

  sample_time_source<T> source_;
  emit_function emit_;
  std::optional<T> pending_;  // the next sample time, asked for but not yet emitted
  std::size_t next_ = 0;      // its index
  bool held_ = false;
  chebyshev_segment<T, D> last_;
  std::vector<T> nodes_;
  std::size_t in_segment_ = 0;  // samples emitted from last_
  std::unique_ptr<detail::lobatto_transform_quad> transform_;
  std::optional<detail::segment_series_quad<D>> series_;
};

}  // namespace eulervop
