// `eulervop scene-template [normalized|physical|coefficient]`: prints an annotated scene of that
// form, every key commented (data/templates/, embedded at build time), to start a scene from.
// Each template runs as printed.
#pragma once

#include "cli/cli11_fwd.hpp"

#include <optional>
#include <ostream>
#include <string>
#include <string_view>

namespace eulervop::app {

struct scene_template_options {
  std::optional<std::string> form;  // normalized | physical | coefficient (default: physical)
  std::optional<std::string> out;   // a file (written atomically) instead of standard output
};

void add_scene_template_flags(CLI::App& sub, scene_template_options& options);

// The annotated scene of a form; input_error for an unknown form.
std::string_view scene_template_text(const std::string& form);

// input_error for an unknown form.
int run_scene_template(const scene_template_options& options, std::ostream& standard_output);

}  // namespace eulervop::app
