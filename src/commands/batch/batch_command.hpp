// `eulervop batch SCENES... --out-dir DIR [--jobs N] [--shard i/n] [--report] [--verify] [--certify]`:
// `reference` (and optionally `report`) for many scenes, in-process.
//
// Each scene SCENE.toml writes DIR/SCENE/reference.csv (and DIR/SCENE/report/errors.csv,
// summary.json with --report). The reference CSVs carry no wall-clock lines, so two runs (any
// --jobs) give byte-identical files. Per-scene timings go to stderr only ("batch: NAME ok (S s)").
//
// DIR/manifest.json (DIR/manifest-I-of-N.json with --shard I/N, so array tasks sharing DIR do
// not overwrite each other) lists, sorted by path: path, name, status (ok | failed |
// skipped-up-to-date), exit_code (0, 2 bad input, 3 numerical failure, 1 internal error),
// message, outputs and the input hash. A scene is skipped when DIR/SCENE/.batch-hash holds the
// FNV-1a 64 hash of (program version, scene path, scene text, flags) and its outputs exist.
//
// Exit code: flag errors exit 2 with one line before anything runs. Otherwise 0 when every
// scene is ok or skipped; else 2 if any scene had bad input; else 3 if any had a numerical
// failure; else 1. A failed scene never stops the others.
#pragma once

#include "commands/reference/reference_command.hpp"

#include "cli/cli11_fwd.hpp"

#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace eulervop::app {

struct batch_options {
  std::vector<std::string> scenes;
  std::optional<std::string> out_dir;
  std::optional<std::string> jobs;   // "N", N >= 1
  std::optional<std::string> shard;  // "i/n", 1 <= i <= n
  // The flags passed on to every scene's `reference` (--samples, --precision, --degree,
  // --tolerance, --verify, --certify), bound by their definitions in `reference`; `report`
  // gets them too, but --samples and --certify.
  reference_options reference;
  bool report = false;
};

// Registers the command's flags on `sub`, bound to `options`.
void add_batch_flags(CLI::App& sub, batch_options& options);

// Runs the batch; returns the exit code (above). Throws input_error for bad flags, before any
// scene runs.
int run_batch(const batch_options& options, std::ostream& standard_output);

}  // namespace eulervop::app
