// The certificate of a streamed reference, on threads (docs/certified.md, "Threads"). While the
// reference integrates on, `workers` threads prepare the segments it has accepted (the checks
// that do not depend on earlier segments: certify/ball_certifier.hpp's ball_segment_check), and
// one more thread takes everything that depends on order, in order: it advances the certificate
// through the prepared segments and runs the row tasks (a row's radius and its line of output)
// between them. So the output is the same bytes as checking and writing on one thread.
//
// At most `max_in_flight` segments wait for a worker or are being prepared: the integration waits
// when the workers fall behind, so memory does not grow with the span, until a quarter of them
// are prepared (woken once for those, not once per item: a wake-up costs about as much as a
// row). Prepared segments may wait for the in-order thread up to four times that many: it is
// fast on average, but behind for a while at a time (a run of rows), and an integration waiting
// for it left both workers without work (on two cores, 20 ms of one core idle in the paper
// scene's 0.7 s, and 13 ms more with one worker on the oldest segment). The first failure
// (of a preparation, in segment order, or of an advance or a row) stops the pipeline and is
// rethrown to the caller at its next call.
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/segment.hpp>

#include <algorithm>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <pthread.h>
#include <sched.h>
#include <thread>
#include <utility>
#include <variant>
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
  using prepared = std::future<std::unique_ptr<check>>;
  using item = std::variant<prepared, std::function<void()>>;

  std::unique_ptr<check> take_check();
  void push(item next, bool is_segment);
  void throw_if_failed();
  void work();      // a worker: preparations, in the order given
  void preparation_ended();  // room for the integration
  void sequence();  // the order-dependent part

  Certifier& cert_;
  std::size_t max_in_flight_;
  std::mutex mutex_;
  // Each waits for its own condition, so that a change wakes only who can act on it.
  std::condition_variable job_ready_, item_ready_, item_done_;
  std::deque<std::packaged_task<std::unique_ptr<check>()>> jobs_;
  std::deque<item> items_;
  std::vector<std::unique_ptr<check>> spare_checks_;
  std::size_t segments_in_flight_ = 0;  // added, not yet advanced
  std::size_t unprepared_ = 0;          // added, not yet prepared
  std::size_t resume_in_flight_;  // a waiting integration goes on at this many unprepared
  bool room() const {             // for the integration's next segment
    return unprepared_ <= resume_in_flight_ && segments_in_flight_ < 4 * max_in_flight_;
  }
  bool stop_ = false, busy_ = false, producer_waits_ = false;
  std::exception_ptr failure_;
  std::vector<std::thread> workers_;
  std::thread sequencer_;
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
  for (unsigned w = 0; w < workers; ++w)
    workers_.emplace_back([this, digits10] {
      mpfr_real::thread_default_precision(digits10);
      run_as_batch();
      work();
    });
  sequencer_ = std::thread([this, digits10] {
    mpfr_real::thread_default_precision(digits10);
    run_as_batch();
    sequence();
  });
}

template <class Certifier>
certify_pipeline<Certifier>::~certify_pipeline() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  job_ready_.notify_all();
  item_ready_.notify_all();
  item_done_.notify_all();
  for (std::thread& t : workers_) t.join();
  {
    // Preparations that never ran leave broken promises, which wake the sequencer.
    const std::lock_guard<std::mutex> lock(mutex_);
    jobs_.clear();
  }
  item_ready_.notify_all();
  sequencer_.join();
}

template <class Certifier>
template <scalar T, std::size_t D>
void certify_pipeline<Certifier>::add_segment(const chebyshev_segment<T, D>& seg) {
  throw_if_failed();
  // The worker takes (or builds) the check: building one costs more than a segment's copy.
  std::packaged_task<std::unique_ptr<check>()> job([this, seg] {
    struct prepared_one {  // counted out however the preparation ends
      certify_pipeline* p;
      ~prepared_one() { p->preparation_ended(); }
    } counted{this};
    std::unique_ptr<check> c = take_check();
    c->prepare(seg);
    return c;
  });
  prepared result = job.get_future();
  {
    std::unique_lock<std::mutex> lock(mutex_);
    if (unprepared_ >= max_in_flight_ || segments_in_flight_ >= 4 * max_in_flight_) {
      producer_waits_ = true;
      item_done_.wait(lock, [this] { return room() || failure_ || stop_; });
      producer_waits_ = false;
    }
    jobs_.push_back(std::move(job));
    ++unprepared_;
  }
  job_ready_.notify_one();
  push(std::move(result), true);
}

template <class Certifier>
void certify_pipeline<Certifier>::add_row(std::function<void()> task) {
  throw_if_failed();
  push(std::move(task), false);
}

template <class Certifier>
void certify_pipeline<Certifier>::finish() {
  {
    std::unique_lock<std::mutex> lock(mutex_);
    item_done_.wait(lock, [this] { return (items_.empty() && !busy_) || failure_; });
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
void certify_pipeline<Certifier>::push(item next, bool is_segment) {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    items_.push_back(std::move(next));
    if (is_segment) ++segments_in_flight_;
  }
  item_ready_.notify_one();
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
void certify_pipeline<Certifier>::preparation_ended() {
  bool wake = false;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    --unprepared_;
    wake = producer_waits_ && room();
  }
  if (wake) item_done_.notify_all();
}

template <class Certifier>
void certify_pipeline<Certifier>::work() {
  for (;;) {
    std::packaged_task<std::unique_ptr<check>()> job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      job_ready_.wait(lock, [this] { return !jobs_.empty() || stop_; });
      if (stop_) return;
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    job();  // its exception goes to the future, which the sequencer reads in order
  }
}

template <class Certifier>
void certify_pipeline<Certifier>::sequence() {
  for (;;) {
    item next;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      item_ready_.wait(lock, [this] { return !items_.empty() || stop_; });
      if (items_.empty() || failure_) return;
      next = std::move(items_.front());
      items_.pop_front();
      busy_ = true;
    }
    std::unique_ptr<check> spare;
    std::exception_ptr failure;
    try {
      if (auto* segment = std::get_if<prepared>(&next))
        spare = cert_.advance(segment->get());
      else
        std::get<std::function<void()>>(next)();
    } catch (...) {
      failure = std::current_exception();
    }
    bool wake = false;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (std::holds_alternative<prepared>(next)) --segments_in_flight_;
      if (spare) spare_checks_.push_back(std::move(spare));
      if (failure && !failure_) failure_ = failure;
      busy_ = false;
      // Who waits on item_done_: the integration for room (add_segment), finish() for the end.
      wake = failure_ || items_.empty() || (producer_waits_ && room());
    }
    if (wake) item_done_.notify_all();
    if (failure) return;
  }
}

}  // namespace eulervop::app
