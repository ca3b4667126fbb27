#include "commands/batch/batch_manifest.hpp"

#include "compute/scene_library.hpp"
#include "io/output_dir.hpp"
#include "io/reference_csv.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>

namespace eulervop::app {

namespace {

// The error figures of a physical scene's reference.csv (its --verify estimates and --certify
// radii), each with its unit, since they come in several: {"estimated_max_error": {"value":
// 1.43e-32, "unit": "normalized Omega (Eq. 20, no unit)"}, ...}. Empty for the other scenes, whose
// figures are all in the integrator's own variables, or when the file has none or cannot be read
// (the manifest never fails for it).
nlohmann::ordered_json figures_of(const batch_settings& s, const scene_task& t) {
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  try {
    const reference_metadata m =
        read_reference_metadata("reference", (s.out_dir / t.name / "reference.csv").string());
    const reference_layout layout = reference_layout_of(load_scene_file(t.path));
    if (layout != reference_layout::physical && layout != reference_layout::direct) return out;
    const auto add = [&](const char* name, const std::optional<decimal>& x) {
      if (x) out[name] = {{"value", x->value}, {"unit", error_unit(layout, name)}};
    };
    add("estimated_max_error", m.estimated_max_error);
    add("estimated_max_error_omega", m.estimated_max_error_omega);
    add("estimated_max_attitude_error", m.estimated_max_attitude_error);
    add("certified_max_error", m.certified_max_error);
    add("certified_max_error_omega", m.certified_max_error_omega);
    add("certified_max_error_q", m.certified_max_error_q);
  } catch (const std::exception&) {
    return nlohmann::ordered_json::object();
  }
  return out;
}

}  // namespace

int write_manifest(const batch_settings& s, const std::optional<shard_spec>& shard,
                   const std::vector<scene_task>& tasks, const std::vector<scene_outcome>& results,
                   std::ostream& standard_output) {
  const std::string suffix = shard ? fmt::format("-{}-of-{}", shard->index, shard->count) : "";
  nlohmann::ordered_json manifest;
  manifest["eulervop"] = EULERVOP_VERSION;
  manifest["shard"] = shard ? nlohmann::ordered_json(fmt::format("{}/{}", shard->index, shard->count)) : nullptr;
  manifest["flags"] = s.flags_text.empty() ? "" : s.flags_text.substr(1);
  manifest["report"] = s.report;
  manifest["scenes"] = nlohmann::ordered_json::array();
  bool any_bad_input = false, any_numerical = false, any_internal = false;
  std::size_t n_ok = 0, n_skipped = 0, n_failed = 0;
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    const scene_outcome& r = results[i];
    manifest["scenes"].push_back({{"path", tasks[i].path},
                                  {"name", tasks[i].name},
                                  {"status", r.status},
                                  {"exit_code", r.exit_code},
                                  {"message", r.message},
                                  {"outputs", r.outputs},
                                  {"hash", r.hash}});
    if (r.status != "failed") {
      nlohmann::ordered_json figures = figures_of(s, tasks[i]);
      if (!figures.empty()) manifest["scenes"].back()["figures"] = std::move(figures);
    }
    if (r.status == "ok") ++n_ok;
    else if (r.status == "skipped-up-to-date") ++n_skipped;
    else ++n_failed;
    any_bad_input |= r.exit_code == exit_bad_input;
    any_numerical |= r.exit_code == exit_numerical_failure;
    any_internal |= r.exit_code == exit_internal_error;
  }
  const std::filesystem::path manifest_path = s.out_dir / ("manifest" + suffix + ".json");
  write_atomically(manifest_path, manifest.dump(2) + "\n");
  standard_output << fmt::format("batch: {} scene{}: {} ok, {} skipped (up to date), {} failed; manifest {}\n",
                                 tasks.size(), tasks.size() == 1 ? "" : "s", n_ok, n_skipped, n_failed,
                                 manifest_path.string())
                  << std::flush;
  if (any_bad_input) return exit_bad_input;
  if (any_numerical) return exit_numerical_failure;
  if (any_internal) return exit_internal_error;
  return exit_success;
}

}  // namespace eulervop::app
