#include "commands/reference/reference_command.hpp"

#include "cli/exit_codes.hpp"
#include "cli/scene_overrides.hpp"
#include "commands/reference/reference_run.hpp"
#include "compute/certified_reference.hpp"
#include "io/atomic_file.hpp"
#include "io/reference_csv.hpp"
#include "io/scratch_file.hpp"

#include <memory>
#include <string_view>

namespace eulervop::app {

namespace reference_flags {
const flag_def verify{"--verify", "", "Recompute one precision up and report # estimated_max_error"};
const flag_def certify{"--certify", "",
                       "Prove a bound on every row's distance to the exact solution: a radius column and "
                       "# certified_max_error (docs/certified.md)"};
}  // namespace reference_flags

namespace {

// The flags applied to the scene and validated (a scene --certify cannot prove is bad input),
// before any computation.
reference_job make_job(const reference_options& o) {
  reference_job job;
  job.scn = o.scene_path ? load_scene_file(*o.scene_path) : load_default_scene();
  const applied_overrides applied = apply_scene_overrides(job.scn, o.overrides);
  job.precision = applied.precision;
  job.settings = applied.settings;
  job.layout = reference_layout_of(job.scn);
  job.verify = o.verify;
  job.certify = o.certify;
  if (job.certify) require_certifiable(job.scn, job.precision);
  job.omit_timing = o.omit_timing;
  job.command = o.command;
  job.overrides = applied.text();
  return job;
}

}  // namespace

void add_reference_flags(CLI::App& sub, reference_options& o) {
  add_text_flag(sub, {"scene", "SCENE", "Scene file (TOML); default: the embedded paper scene"}, o.scene_path);
  add_scene_override_flags(sub, o.overrides, scene_override_set{},
                           "Number of equally spaced samples, endpoints included");
  add_text_flag(sub, {"--out", "FILE", "Output file (default: standard output)"}, o.out);
  add_switch(sub, reference_flags::verify, o.verify);
  add_switch(sub, reference_flags::certify, o.certify);
}

int run_reference(const reference_options& options, std::ostream& standard_output) {
  const reference_job job = make_job(options);
  // Open the output first, so an unwritable path fails before any computation.
  std::unique_ptr<atomic_file> file;
  if (options.out) file = std::make_unique<atomic_file>(*options.out);
  // The header states the finished run (segments, wall time, --verify's estimate) but comes
  // first: the rows are streamed to a scratch file during the run, then copied after it.
  scratch_file rows(scratch_directory_for(file.get()));
  const std::string header = reference_csv_header(run_reference_job(job, rows), job.layout);
  if (file) {
    file->write(header);
    rows.copy_to([&](std::string_view chunk) { file->write(chunk); });
    file->commit();
  } else {
    standard_output << header;
    rows.copy_to([&](std::string_view chunk) { standard_output.write(chunk.data(), std::ssize(chunk)); });
    standard_output << std::flush;
  }
  return exit_success;
}

}  // namespace eulervop::app
