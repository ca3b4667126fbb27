// The certificate of a streamed reference, on threads (docs/certified.md, "Threads"). While the
// reference integrates on, `workers` threads prepare the segments it has accepted (the checks
// that do not depend on earlier segments: certify/ball_certifier.hpp's ball_segment_check), and
// take what depends on order, in order: advancing the certificate through the prepared segments,
// and the row tasks (a row's radius and its line of output) between them. One worker at a time
// holds that in-order part, and a worker takes it before a new preparation whenever the oldest
// item is ready. So the output is the same bytes as checking and writing on one thread, and the
// prepared segments do not pile up behind a thread of their own: with one more thread than the
// workers for the in-order part, it got a fourth of the two cores where it needed a sixth and fell
// behind by up to 40 segments in the SciML rigid body to t = 100 (three times the checks' memory,
// 3,300 more page faults, and 2.5 ms at the end to free them).
//
// At most `max_in_flight` segments wait for a worker or are being prepared: the integration waits
// when the workers fall behind, so memory does not grow with the span, until a quarter of them
// are prepared (woken once for those, not once per item: a wake-up costs about as much as a
// row). Prepared segments may wait for the in-order part up to four times that many. The first
// failure (of a preparation, in segment order, or of an advance or a row) stops the pipeline and
// is rethrown to the caller at its next call.
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/segment.hpp>

#include <algorithm>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <pthread.h>
#include <sched.h>
#include <thread>
#include <utility>
#include <vector>

namespace eulervop::app {

// Certifier: the certifier (ball_certifier), with its `check` type, make_segment() and advance().
template <class Certifier>
class certify_pipeline {
 public:
  using check = typename Certifier::check;
  certify_pipeline(Certifier& cert, unsigned workers, std::size_t max_in_flight);
  ~certify_pipeline();
  certify_pipeline(const certify_pipeline&) = delete;
  certify_pipeline& operator=(const certify_pipeline&) = delete;

  // The next accepted segment (copied; prepared on a worker).
  template <scalar T, std::size_t D>
  void add_segment(const chebyshev_segment<T, D>& seg);
  // A task that runs after every segment added before it, and before any added after it.
  void add_row(std::function<void()> task);
  // Waits until everything added has run; rethrows the first failure.
  void finish();

 private:
  // One step of the run, in order: a segment (prepared on a worker, then advanced) or a row.
  struct item {
    std::function<void()> row;  // empty for a segment
    std::unique_ptr<check> prepared;
    std::exception_ptr failure;  // the preparation's
    bool ready = false;          // a row, or a segment whose preparation ended
  };
  struct job {
    std::function<void(check&)> prepare;
    item* slot;  // in items_, whose elements a push or pop at either end does not move
  };

  std::unique_ptr<check> take_check();
  void throw_if_failed();
  void work();  // a worker's loop: the in-order part when it is free and ready, else a preparation
  void prepare(std::unique_lock<std::mutex>& lock);
  void run_in_order(std::unique_lock<std::mutex>& lock);
  bool head_ready() const { return !items_.empty() && items_.front().ready; }

  Certifier& cert_;
  std::size_t max_in_flight_;
  std::mutex mutex_;
  // Each waits for its own condition, so that a change wakes only who can act on it.
  std::condition_variable work_ready_, item_done_;
  std::deque<job> jobs_;
  std::deque<item> items_;
  std::vector<std::unique_ptr<check>> spare_checks_;
  std::size_t segments_in_flight_ = 0;  // added, not yet advanced
  std::size_t unprepared_ = 0;          // added, not yet prepared
  std::size_t resume_in_flight_;  // a waiting integration goes on at this many unprepared
  bool room() const {             // for the integration's next segment
    return unprepared_ <= resume_in_flight_ && segments_in_flight_ < 4 * max_in_flight_;
  }
  bool stop_ = false, in_order_ = false, producer_waits_ = false;
  std::exception_ptr failure_;
  std::vector<std::thread> workers_;
};

// The pipeline's threads are CPU-bound, and with the integration there are more of them than cores.
// Under Linux's default policy a woken thread preempts a running one, and each such switch costs a
// worker its check's working set in cache: on two cores the certificate took 1.2 to 1.35 times the
// CPU it takes on one (B5 to t = 1000, 1,500 switches). SCHED_BATCH (sched(7)) marks them as batch
// work, which a wake-up does not preempt: 1.05 times, a third of the switches. Where the policy
// cannot be set, the threads run as they are (the same output either way).
inline void run_as_batch() {
#ifdef SCHED_BATCH
  const sched_param none{};
  (void)pthread_setschedparam(pthread_self(), SCHED_BATCH, &none);
#endif
}

// The threads take the caller's MPFR precision (a thread-local setting): the rows format their
// times in it, as on the caller's thread.
template <class Certifier>
certify_pipeline<Certifier>::certify_pipeline(Certifier& cert, unsigned workers, std::size_t max_in_flight)
    : cert_(cert),
      max_in_flight_(std::max<std::size_t>(max_in_flight, 1)),
      resume_in_flight_(max_in_flight_ - 1 - (max_in_flight_ - 1) / 4) {
  const unsigned digits10 = mpfr_real::thread_default_precision();
  for (unsigned w = 0; w < std::max(workers, 1u); ++w)
    workers_.emplace_back([this, digits10] {
      mpfr_real::thread_default_precision(digits10);
      run_as_batch();
      work();
    });
}

template <class Certifier>
certify_pipeline<Certifier>::~certify_pipeline() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  work_ready_.notify_all();
  item_done_.notify_all();
  for (std::thread& t : workers_) t.join();
}

template <class Certifier>
template <scalar T, std::size_t D>
void certify_pipeline<Certifier>::add_segment(const chebyshev_segment<T, D>& seg) {
  throw_if_failed();
  // The worker takes (or builds) the check: building one costs more than a segment's copy.
  std::function<void(check&)> prepare = [seg](check& c) { c.prepare(seg); };
  {
    std::unique_lock<std::mutex> lock(mutex_);
    if (unprepared_ >= max_in_flight_ || segments_in_flight_ >= 4 * max_in_flight_) {
      producer_waits_ = true;
      item_done_.wait(lock, [this] { return room() || failure_ || stop_; });
      producer_waits_ = false;
    }
    items_.emplace_back();
    jobs_.push_back({std::move(prepare), &items_.back()});
    ++unprepared_;
    ++segments_in_flight_;
  }
  work_ready_.notify_one();
}

template <class Certifier>
void certify_pipeline<Certifier>::add_row(std::function<void()> task) {
  throw_if_failed();
  bool wake = false;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    items_.emplace_back();
    items_.back().row = std::move(task);
    items_.back().ready = true;
    wake = items_.size() == 1 && !in_order_;  // else who ends the item before it takes this one
  }
  if (wake) work_ready_.notify_one();
}

template <class Certifier>
void certify_pipeline<Certifier>::finish() {
  {
    std::unique_lock<std::mutex> lock(mutex_);
    item_done_.wait(lock, [this] { return (items_.empty() && !in_order_) || failure_; });
  }
  throw_if_failed();
}

template <class Certifier>
auto certify_pipeline<Certifier>::take_check() -> std::unique_ptr<check> {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!spare_checks_.empty()) {
      std::unique_ptr<check> c = std::move(spare_checks_.back());
      spare_checks_.pop_back();
      return c;
    }
  }
  return cert_.make_segment();
}

template <class Certifier>
void certify_pipeline<Certifier>::throw_if_failed() {
  std::exception_ptr failure;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    failure = failure_;
  }
  if (failure) std::rethrow_exception(failure);
}

template <class Certifier>
void certify_pipeline<Certifier>::work() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    if (stop_ || failure_) return;
    if (!in_order_ && head_ready())
      run_in_order(lock);
    else if (!jobs_.empty())
      prepare(lock);
    else
      work_ready_.wait(lock);
  }
}

// The oldest unprepared segment, prepared with the lock released. Its failure is kept in its item
// for the in-order part, which reports it only if nothing before it failed.
template <class Certifier>
void certify_pipeline<Certifier>::prepare(std::unique_lock<std::mutex>& lock) {
  job next = std::move(jobs_.front());
  jobs_.pop_front();
  lock.unlock();
  std::unique_ptr<check> c;
  std::exception_ptr failure;
  try {
    c = take_check();
    next.prepare(*c);
  } catch (...) {
    failure = std::current_exception();
  }
  lock.lock();
  next.slot->prepared = std::move(c);
  next.slot->failure = failure;
  next.slot->ready = true;
  --unprepared_;
  if (producer_waits_ && room()) item_done_.notify_all();
}

// The ready items from the oldest on, each with the lock released; the in-order part is this
// thread's until the oldest is not ready (then the next worker to end a preparation takes it).
template <class Certifier>
void certify_pipeline<Certifier>::run_in_order(std::unique_lock<std::mutex>& lock) {
  in_order_ = true;
  while (head_ready() && !failure_ && !stop_) {
    item next = std::move(items_.front());
    items_.pop_front();
    lock.unlock();
    std::unique_ptr<check> spare;
    std::exception_ptr failure = next.failure;
    if (!failure) {
      try {
        if (next.row)
          next.row();
        else
          spare = cert_.advance(std::move(next.prepared));
      } catch (...) {
        failure = std::current_exception();
      }
    }
    lock.lock();
    if (!next.row) --segments_in_flight_;
    if (spare) spare_checks_.push_back(std::move(spare));
    if (failure && !failure_) failure_ = failure;
    if (producer_waits_ && room()) item_done_.notify_all();
  }
  in_order_ = false;
  // Who waits: finish() for the end, the integration for a failure, the other workers to stop.
  if (items_.empty() || failure_) item_done_.notify_all();
  if (failure_) work_ready_.notify_all();
}

}  // namespace eulervop::app
