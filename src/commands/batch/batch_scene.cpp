#include "commands/batch/batch_scene.hpp"

#include "commands/report/report_command.hpp"
#include "compute/scene_library.hpp"
#include "io/output_dir.hpp"
#include "io/shell_word.hpp"

#include <eulervop/core/numerical_failure.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>
#include <system_error>

namespace eulervop::app {

namespace {

namespace fs = std::filesystem;

constexpr const char* stamp_name = ".batch-hash";

std::uint64_t fnv1a(std::uint64_t h, std::string_view data) {
  for (unsigned char c : data) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return h;
}

std::optional<std::string> read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) return std::nullopt;
  return s.str();
}

// FNV-1a 64 of what shapes the scene's outputs: the program version, the scene's path and text,
// the flags passed on and whether a report is made.
std::string input_hash(const batch_settings& s, const scene_task& t, const std::string& text) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const std::string_view part : {std::string_view(EULERVOP_VERSION), std::string_view(t.path),
                                      std::string_view(text), std::string_view(s.flags_text),
                                      std::string_view(s.report ? "report" : "")}) {
    h = fnv1a(h, part);
    h = fnv1a(h, std::string_view("\0", 1));
  }
  return fmt::format("{:016x}", h);
}

std::vector<std::string> expected_outputs(const batch_settings& s, const scene_task& t) {
  std::vector<std::string> out = {t.name + "/reference.csv"};
  if (s.report) {
    out.push_back(t.name + "/report/errors.csv");
    out.push_back(t.name + "/report/summary.json");
  }
  return out;
}

// The stamp (written last) holds the hash and every output is there.
bool up_to_date(const batch_settings& s, const fs::path& stamp, const std::string& hash,
                const std::vector<std::string>& outputs) {
  const auto old = read_all(stamp);
  return old && *old == hash + "\n" && std::all_of(outputs.begin(), outputs.end(), [&](const std::string& o) {
           return fs::is_regular_file(s.out_dir / o);
         });
}

// The scene's `reference` into dir/reference.csv (no wall-clock lines), and its `report` into
// dir/report/ with the same reference settings.
void run_commands(const batch_settings& s, const scene_task& t, const fs::path& dir) {
  reference_options ref = s.reference;
  ref.scene_path = t.path;
  ref.out = (dir / "reference.csv").string();
  ref.omit_timing = true;
  ref.command = "eulervop reference " + shell_word(t.path) + s.flags_text;
  std::ostringstream sink;
  run_reference(ref, sink);
  if (!s.report) return;
  report_options rep;
  rep.scene_path = t.path;
  rep.overrides = s.reference.overrides;
  rep.overrides.samples.reset();  // the reference's rows; the report keeps its own error samples
  rep.out_dir = (dir / "report").string();
  rep.format = "json";
  rep.no_plot = true;
  rep.verify = s.reference.verify;
  run_report(rep, sink);
}

// Runs the scene unless it is up to date; throws what the commands throw.
void run_or_skip(const batch_settings& s, const scene_task& t, scene_outcome& r) {
  const fs::path dir = s.out_dir / t.name;
  const fs::path stamp = dir / stamp_name;
  const std::optional<std::string> text = read_all(t.path);
  if (!text) throw input_error(fmt::format("scene {}: cannot read the file", t.path));
  r.hash = input_hash(s, t, *text);
  const std::vector<std::string> outputs = expected_outputs(s, t);
  if (up_to_date(s, stamp, r.hash, outputs)) {
    r.status = "skipped-up-to-date";
  } else {
    std::error_code ec;
    fs::remove(stamp, ec);
    fs::create_directories(dir, ec);
    if (ec) throw input_error(fmt::format("cannot create {}: {}", dir.string(), ec.message()));
    run_commands(s, t, dir);
    write_atomically(stamp, r.hash + "\n");
    r.status = "ok";
  }
  r.exit_code = exit_success;
  r.outputs = outputs;
}

}  // namespace

scene_outcome run_scene(const batch_settings& s, const scene_task& t) {
  const auto start = std::chrono::steady_clock::now();
  scene_outcome r;
  try {
    run_or_skip(s, t, r);
  } catch (const input_error& e) {
    r.exit_code = exit_bad_input;
    r.message = e.what();
  } catch (const numerical_failure& e) {
    r.exit_code = exit_numerical_failure;
    r.message = e.what();
  } catch (const std::exception& e) {
    r.exit_code = exit_internal_error;
    r.message = fmt::format("internal error: {}", e.what());
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace eulervop::app
