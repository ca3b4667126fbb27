// One scene of a batch: its reference (and report) into DIR/SCENE/, unless the outputs of the
// same input are already there (the stamp DIR/SCENE/.batch-hash, written last).
#pragma once

#include "cli/exit_codes.hpp"
#include "commands/reference/reference_command.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace eulervop::app {

// What every scene of the batch shares.
struct batch_settings {
  std::filesystem::path out_dir;
  bool report = false;
  reference_options reference;  // the flags passed on to every scene
  std::string flags_text;       // those flags as a command line states them, for the hash and the commands
};

struct scene_task {
  std::string path;  // as given
  std::string name;  // the file's stem: the output directory's name
};

struct scene_outcome {
  std::string status = "failed";  // ok | failed | skipped-up-to-date
  int exit_code = exit_internal_error;
  std::string message;
  std::vector<std::string> outputs;  // relative to the output directory
  std::string hash;
  double seconds = 0;
};

// Never throws: a failure is the outcome's status, exit code and message.
scene_outcome run_scene(const batch_settings& s, const scene_task& t);

}  // namespace eulervop::app
