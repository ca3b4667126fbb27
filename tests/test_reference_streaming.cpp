// `reference` streams its rows: they are written as the integration evaluates each sample, to
// an unnamed scratch file, and copied after the metadata block once the run is over (the block
// states the finished run). The file must be exactly what the in-memory route gives: the whole
// dense trajectory, sampled afterwards, and the whole CSV built in a string. A run that fails
// half-way must leave neither the output nor a scratch file.
#include "cli_test_support.hpp"
#include "commands/reference/reference_command.hpp"
#include "compute/reference_compute.hpp"
#include "compute/verify.hpp"
#include "io/reference_csv.hpp"
#include "compute/scene_library.hpp"
#include "cli/scene_overrides.hpp"
#include "compute/with_scalar.hpp"

#include <eulervop/reference/integrate.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/core/scalar.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

using namespace eulervop;
using namespace eulervop::app;
using cli_test::read_file;
using cli_test::temp_dir;
using cli_test::write_file;

// The route the program took before the rows were streamed: the samples kept in memory
// (integrate_and_sample, the same sampler), the CSV built in a string.
template <scalar T>
std::string in_memory_csv(const reference_options& o) {
  app::scene s = o.scene_path ? load_scene_file(*o.scene_path) : load_default_scene();
  const applied_overrides applied = apply_scene_overrides(s, o.overrides);
  const T tau_end = tau_end_of<T>(s);
  const sample_times<T> times = sample_times_of<T>(s);
  const sampled_reference<T> run = integrate_and_sample<T>(to_problem<T>(s), tau_end, times.tau, applied.settings, "");
  const picard_stats& stats = run.stats;
  const std::vector<vec3<T>>& Omega = run.Omega;

  reference_metadata m;
  m.scene_name = s.name;
  m.scene_source = s.origin;
  m.command = o.command;
  m.overrides = applied.text();
  m.precision = applied.precision;
  m.method = method_text(applied.settings, stats);
  if (o.verify) {
    const verify_result check = verify<T>(s, tau_end, times.tau, Omega, applied.precision);
    m.estimated_max_error = check.max_error;
    m.estimated_max_error_omega = check.max_error_omega;
    m.verify_precision = check.precision;
    m.verify_method = check.method;
  }
  m.scene_text = s.source_text;
  reference_csv_writer csv(m, s.is_physical() ? reference_layout::physical : reference_layout::normalized);
  for (std::size_t i = 0; i < Omega.size(); ++i) {
    if (s.is_physical())
      csv.row(times.tau[i], Omega[i], times.t[i], scaling_of<T>(s).omega_of_Omega(Omega[i]));
    else
      csv.row(times.tau[i], Omega[i]);
  }
  return csv.text();
}

std::string expected_csv(const reference_options& o) {
  app::scene s = o.scene_path ? load_scene_file(*o.scene_path) : load_default_scene();
  const applied_overrides applied = apply_scene_overrides(s, o.overrides);
  return with_scalar(applied.precision, [&](auto zero) { return in_memory_csv<decltype(zero)>(o); });
}

// Runs the command in this process to `out` (a file, or a string for standard output).
std::string streamed_csv(reference_options o, const std::optional<fs::path>& out) {
  std::ostringstream standard_output;
  if (out) o.out = out->string();
  run_reference(o, standard_output);
  return out ? read_file(*out) : standard_output.str();
}

reference_options options(std::optional<std::string> scene_path, const std::string& tau_end_flag,
                          const std::string& tau_end, const std::string& samples, const std::string& precision) {
  reference_options o;
  o.scene_path = std::move(scene_path);
  (tau_end_flag == "--t-end" ? o.overrides.t_end : o.overrides.tau_end) = tau_end;
  o.overrides.samples = samples;
  o.overrides.precision = precision;
  o.omit_timing = true;  // the only lines that differ between two runs
  o.command = "eulervop reference (test)";
  return o;
}

// 3000 quad rows are about 450 KB: several chunks of rows pass through the scratch file.
TEST(ReferenceStreaming, ManyQuadRowsEqualTheInMemoryCsv) {
  temp_dir dir;
  const reference_options o = options(std::nullopt, "--tau-end", "20", "3000", "quad");
  const std::string expected = expected_csv(o);
  ASSERT_GT(expected.size(), 400'000u);
  EXPECT_EQ(streamed_csv(o, dir.path() / "ref.csv"), expected);
  EXPECT_EQ(streamed_csv(o, std::nullopt), expected);  // standard output: the same bytes
}

TEST(ReferenceStreaming, PhysicalRowsEqualTheInMemoryCsv) {
  temp_dir dir;
  const std::string scene_path = EULERVOP_SOURCE_DIR "/data/scenes/spacecraft-physical.toml";
  const reference_options o = options(scene_path, "--t-end", "30", "41", "double");
  EXPECT_EQ(streamed_csv(o, dir.path() / "ref.csv"), expected_csv(o));
}

// --verify keeps the narrow samples for the comparison; the estimate is the in-memory one.
TEST(ReferenceStreaming, VerifiedRunEqualsTheInMemoryCsv) {
  temp_dir dir;
  reference_options o = options(std::nullopt, "--tau-end", "4", "17", "double");
  o.verify = true;
  const std::string expected = expected_csv(o);
  ASSERT_NE(expected.find("# estimated_max_error: "), std::string::npos);
  EXPECT_EQ(streamed_csv(o, dir.path() / "ref.csv"), expected);
}

TEST(ReferenceStreaming, MpfrRowsEqualTheInMemoryCsv) {
  temp_dir dir;
  const reference_options o = options(std::nullopt, "--tau-end", "2", "9", "mpfr:160");
  EXPECT_EQ(streamed_csv(o, dir.path() / "ref.csv"), expected_csv(o));
}

std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// Sets an environment variable for the programs the test starts, and restores it.
class scoped_env {
 public:
  scoped_env(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~scoped_env() {
    if (old_)
      ::setenv(name_, old_->c_str(), 1);
    else
      ::unsetenv(name_);
  }
  scoped_env(const scoped_env&) = delete;
  scoped_env& operator=(const scoped_env&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

// Omega3 = G3 tau overflows double at tau = 1.8e108. The first 3000 sample times (up to 3e85,
// where Omega3 <= 3e285 and the dense output is finite) go to the scratch file, about 200 KB in
// several chunks, before the integration fails; nothing may remain, neither beside the output
// nor in TMPDIR (where the rows bound for standard output wait).
std::string late_overflow_scene() {
  std::string times;
  for (int i = 0; i < 3000; ++i) times += std::to_string(i) + "e82, ";
  return "name = \"late-overflow\"\n[torque]\nG = [0.0, 0.0, 1.0e200]\n[initial]\nOmega = [0.0, 0.0, 0.0]\n"
         "[span]\ntau_end = 1.0e110\ntimes = [" + times + "1.0e110]\n[reference]\nprecision = \"double\"\n";
}

TEST(ReferenceStreaming, FailureMidRunLeavesNoOutputAndNoScratchFile) {
  temp_dir dir, tmp;
  write_file(dir.path() / "overflow.toml", late_overflow_scene());
  const scoped_env env("TMPDIR", tmp.path().string());
  for (const bool to_file : {true, false}) {
    SCOPED_TRACE(to_file ? "--out" : "standard output");
    std::vector<std::string> args = {"reference", "overflow.toml"};
    if (to_file) args.insert(args.end(), {"--out", "ref.csv"});
    const cli_test::run_result r = cli_test::run(dir.path(), args);
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_NE(r.err.find("numerical failure at tau=1.79769313e+108"), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out.substr(0, 200);
    EXPECT_EQ(entries(dir.path()), std::vector<std::string>{"overflow.toml"});
    EXPECT_TRUE(entries(tmp.path()).empty());
  }
}

}  // namespace
