// The second pass of `check` against a scene: the trajectory's rows read again and handed to the
// integration one at a time, as it asks for the next sample time (segment_sampler.hpp). The rows
// are read, validated and converted to T on a thread of their own, a chunk ahead, while the
// integration evaluates the reference and compares: on a large CSV the two halves of the work,
// about equal, overlap. At most `queued` chunks wait, so nothing grows with the rows.
#pragma once

#include "commands/check/check_job.hpp"
#include "commands/check/compared_variables.hpp"
#include "commands/check/trajectory_columns.hpp"

#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/segment_sampler.hpp>

#include <fmt/format.h>

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

namespace eulervop::app {

template <scalar T>
class trajectory_stream {
 public:
  // One row, read and converted: its time as written, in tau, and its state.
  struct row {
    std::size_t line = 0;
    decimal time;
    T tau;
    vec3<T> values;
    quaternion<T> q;
  };

  // `rows`: the count of the first pass, which the second must find again; `tau_end`: the
  // integration's end, which no row may pass.
  trajectory_stream(const check_job& job, const trajectory_columns& cols, std::size_t rows,
                    const compared_variables<T>& vars, const T& tau_end)
      : job_(job), cols_(cols), expected_(rows), vars_(vars), tau_end_(tau_end) {
    unsigned bits = 0;
    if constexpr (variable_precision_scalar<T>) bits = significand_bits<T>();
    reader_ = std::thread([this, bits] { read(bits); });
  }
  ~trajectory_stream() {
    {
      const std::lock_guard lock(mutex_);
      stop_ = true;
    }
    space_.notify_all();
    reader_.join();
  }
  trajectory_stream(const trajectory_stream&) = delete;
  trajectory_stream& operator=(const trajectory_stream&) = delete;

  // The sample time source: the next row's time in tau. The reader's input_error for a row
  // reaches the integration at that row.
  sample_time_source<T> times() {
    return [this](T& tau) {
      if (next_ == chunk_.size() && !take_chunk()) return false;
      current_ = &chunk_[next_++];
      tau = current_->tau;
      return true;
    };
  }

  // The row handed out last.
  const row& current() const { return *current_; }

 private:
  static constexpr std::size_t chunk_rows = 1024, queued = 4;
  struct chunk {
    std::vector<row> rows;
    std::exception_ptr error;  // after the rows, if the reader stopped on one
    bool last = false;
  };

  void read(unsigned bits) {
    std::optional<mpfr_precision_scope> precision;
    if constexpr (variable_precision_scalar<T>) precision.emplace(bits);
    chunk c;
    try {
      const std::unique_ptr<table_rows> rows = job_.open_trajectory();
      row_reader reader{*rows, cols_};
      std::size_t read = 0;
      const auto changed = [&] { return input_error(fmt::format("{}: the file changed while it was read", rows->where())); };
      while (rows->next()) {
        row r;
        r.line = rows->line();
        r.time = reader.time();
        r.values = vec3_of<T>(reader.values());
        if (cols_.q) r.q = quaternion_of<T>(reader.attitude());
        r.tau = vars_.tau_of(r.time.template to_scalar<T>());
        if (++read > expected_ || r.tau > tau_end_) throw changed();
        c.rows.push_back(std::move(r));
        if (c.rows.size() < chunk_rows) continue;
        if (!put(std::move(c))) return;
        c = chunk{};
      }
      if (read != expected_) throw changed();
    } catch (...) {
      c.error = std::current_exception();
    }
    c.last = true;
    put(std::move(c));
  }

  // Queues a chunk; false when the stream is being closed.
  bool put(chunk c) {
    std::unique_lock lock(mutex_);
    space_.wait(lock, [this] { return stop_ || full_.size() < queued; });
    if (stop_) return false;
    full_.push_back(std::move(c));
    lock.unlock();
    ready_.notify_one();
    return true;
  }

  // The next chunk's rows in chunk_; false after the last. The reader's error, after the rows
  // before it.
  bool take_chunk() {
    for (;;) {
      if (pending_error_) std::rethrow_exception(std::exchange(pending_error_, nullptr));
      if (done_) return false;
      chunk c;
      {
        std::unique_lock lock(mutex_);
        ready_.wait(lock, [this] { return !full_.empty(); });
        c = std::move(full_.front());
        full_.pop_front();
      }
      space_.notify_one();
      chunk_ = std::move(c.rows);
      next_ = 0;
      done_ = c.last;
      pending_error_ = c.error;
      if (!chunk_.empty()) return true;
    }
  }

  const check_job& job_;
  const trajectory_columns& cols_;
  std::size_t expected_;
  const compared_variables<T>& vars_;
  T tau_end_;
  std::mutex mutex_;
  std::condition_variable ready_, space_;
  std::deque<chunk> full_;
  bool stop_ = false;
  // The consumer's side: the chunk being handed out.
  std::vector<row> chunk_;
  std::size_t next_ = 0;
  bool done_ = false;
  std::exception_ptr pending_error_;
  const row* current_ = nullptr;
  std::thread reader_;
};

}  // namespace eulervop::app
