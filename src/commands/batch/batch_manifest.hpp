// DIR/manifest.json of a batch (DIR/manifest-I-of-N.json for a shard): every scene's path, name,
// status, exit code, message, outputs and input hash; no timings, so reruns give identical files.
#pragma once

#include "cli/flags.hpp"
#include "commands/batch/batch_scene.hpp"

#include <optional>
#include <ostream>
#include <vector>

namespace eulervop::app {

// Writes the manifest and the summary line; returns the batch's exit code, the gravest of the
// scenes' (bad input, then numerical failure, then internal error).
int write_manifest(const batch_settings& s, const std::optional<shard_spec>& shard,
                   const std::vector<scene_task>& tasks, const std::vector<scene_outcome>& results,
                   std::ostream& standard_output);

}  // namespace eulervop::app
