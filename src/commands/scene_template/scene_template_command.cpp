#include "commands/scene_template/scene_template_command.hpp"

#include "cli/command_flags.hpp"
#include "cli/exit_codes.hpp"
#include "compute/scene_library.hpp"
#include "io/atomic_file.hpp"
#include "scene_templates.hpp"

#include <fmt/format.h>

#include <memory>
#include <string_view>

namespace eulervop::app {

void add_scene_template_flags(CLI::App& sub, scene_template_options& o) {
  add_text_flag(sub, {"form", "FORM", "normalized, physical or coefficient (default: physical)"}, o.form);
  add_text_flag(sub, {"--out", "FILE", "Write the scene to FILE (default: standard output)"}, o.out);
}

std::string_view scene_template_text(const std::string& form) {
  if (form == "normalized") return normalized_scene_template;
  if (form == "physical") return physical_scene_template;
  if (form == "coefficient") return coefficient_scene_template;
  throw input_error(fmt::format("form `{}`: unknown (expected normalized, physical or coefficient)", form));
}

int run_scene_template(const scene_template_options& o, std::ostream& standard_output) {
  const std::string_view text = scene_template_text(o.form.value_or("physical"));
  if (!o.out) {
    standard_output << text << std::flush;
    return exit_success;
  }
  if (o.out->empty()) throw input_error("--out: empty path");
  atomic_file file(*o.out);
  file.write(text);
  file.commit();
  return exit_success;
}

}  // namespace eulervop::app
