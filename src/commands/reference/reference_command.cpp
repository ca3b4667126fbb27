#include "commands/reference/reference_command.hpp"

#include "cli/exit_codes.hpp"
#include "cli/scene_overrides.hpp"
#include "commands/reference/reference_job.hpp"
#include "compute/run_certificate.hpp"
#include "compute/scene_library.hpp"
#include "io/atomic_file.hpp"
#include "io/reference_csv.hpp"
#include "io/scratch_file.hpp"

#include <eulervop/core/scalar.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/model/wide_formula_cells.hpp>

#include <memory>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace eulervop::app {

namespace reference_flags {
const flag_def verify{"--verify", "",
                      "Recompute one precision up and report # estimated_max_error (a body's also in rad/s: "
                      "# estimated_max_error_omega)"};
const flag_def certify{"--certify", "",
                       "Prove a bound on every row's distance to the exact solution: a radius column and "
                       "# certified_max_error (docs/certified.md)"};
}  // namespace reference_flags

namespace {

// The rows as CSV, streamed to `out` in chunks: each row as it is evaluated, or with --certify
// each certified row's cells once its radii are known.
class csv_row_sink final : public reference_row_sink {
 public:
  csv_row_sink(const reference_job& job, scratch_file& out)
      : job_(job), rows_([&out](std::string_view chunk) { out.write(chunk); }) {}

  void values(const double& tau, const double* t, const vec3<double>& y, const quaternion<double>* q) override {
    row(tau, t, y, q);
  }
  void values(const quad& tau, const quad* t, const vec3<quad>& y, const quaternion<quad>* q) override {
    row(tau, t, y, q);
  }
  void values(const mpfr_real& tau, const mpfr_real* t, const vec3<mpfr_real>& y,
              const quaternion<mpfr_real>* q) override {
    row(tau, t, y, q);
  }
  void certified(const std::vector<std::string>& cells, const certified_radii&) override { rows_.certified_row(cells); }
  void flush() { rows_.flush(); }

 private:
  template <scalar T>
  void row(const T& tau, const T* t, const vec3<T>& y, const quaternion<T>* q) {
    if (job_.certify) return;  // written by certified()
    if (job_.layout == reference_layout::physical) {
      if (!std::holds_alternative<physical_scaling<T>>(scale_)) scale_ = scaling_of<T>(job_.scn);
      const auto& scale = std::get<physical_scaling<T>>(scale_);
      if (q) rows_.row(tau, y, *t, scale.omega_of_Omega(y), *q);
      else rows_.row(tau, y, *t, scale.omega_of_Omega(y));
    } else if (q) {
      rows_.row(t ? *t : tau, y, *q);
    } else {
      rows_.row(t ? *t : tau, y);
    }
  }

  const reference_job& job_;
  reference_csv_row_writer rows_;
  // A physical scene's scaling, in the run's type.
  std::variant<std::monostate, physical_scaling<double>, physical_scaling<quad>, physical_scaling<mpfr_real>> scale_;
};

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
  if (options.certify) start_loading_certificate_module();
  const reference_job job = reference_job_of(options);
  // Open the output first, so an unwritable path fails before any computation.
  std::unique_ptr<atomic_file> file;
  if (options.out) file = std::make_unique<atomic_file>(*options.out);
  // The header states the finished run (segments, wall time, --verify's estimate) but comes
  // first: the rows are streamed to a scratch file during the run, then copied after it.
  scratch_file rows(scratch_directory_for(file.get()));
  csv_row_sink sink(job, rows);
  const reference_metadata metadata = run_reference_job(job, sink);
  sink.flush();
  const std::string header = reference_csv_header(metadata, job.layout);
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
