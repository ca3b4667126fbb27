// Independent tasks run on a few threads, with a progress line drawn by the calling thread.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace eulervop::app {

// Runs `tasks` on `jobs` threads (a shared queue, taken in the given order), drawing progress
// labelled `label` in the calling thread. The first exception of any task is rethrown after all
// threads have stopped; no new task starts after one has failed.
void run_tasks(const std::vector<std::function<void()>>& tasks, int jobs, const std::string& label);

}  // namespace eulervop::app
