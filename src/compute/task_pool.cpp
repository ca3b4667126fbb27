#include "compute/task_pool.hpp"

#include "compute/progress.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

namespace eulervop::app {

void run_tasks(const std::vector<std::function<void()>>& tasks, int jobs, const std::string& label) {
  const std::size_t n_threads = std::min<std::size_t>(static_cast<std::size_t>(std::max(jobs, 1)), tasks.size());
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::mutex mutex;
  std::condition_variable changed;
  std::size_t done = 0, stopped = 0;
  std::exception_ptr error;
  auto worker = [&] {
    while (!failed.load()) {
      const std::size_t i = next.fetch_add(1);
      if (i >= tasks.size()) break;
      std::exception_ptr e;
      try {
        tasks[i]();
      } catch (...) {
        e = std::current_exception();
        failed = true;
      }
      {
        const std::lock_guard lock(mutex);
        ++done;
        if (e && !error) error = e;
      }
      changed.notify_one();
    }
    {
      const std::lock_guard lock(mutex);
      ++stopped;
    }
    changed.notify_one();
  };
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < n_threads; ++t) threads.emplace_back(worker);
  {
    const std::unique_ptr<progress_display> progress = open_progress(label, static_cast<double>(tasks.size()), {"task", ""});
    std::unique_lock lock(mutex);
    while (stopped < n_threads) {
      changed.wait_for(lock, std::chrono::milliseconds(100));
      if (progress) progress->update(static_cast<double>(done), 0);
    }
  }
  for (std::thread& t : threads) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace eulervop::app
