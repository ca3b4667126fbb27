#include "io/reference_csv.hpp"

#include "compute/scene_library.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <fstream>
#include <initializer_list>
#include <sstream>

namespace eulervop::app {

namespace {

// Rows are handed over in chunks of this size: large enough that writing costs far less than
// formatting, small enough not to matter for memory.
constexpr std::size_t row_chunk = 1 << 16;

// The precision named at the start of a "# precision:" value ("mpfr:256 (effective_bits=257)").
eulervop::precision parse_precision(const std::string& value, const std::string& where, std::size_t line) {
  const std::string name = value.substr(0, value.find(' '));
  const auto p = eulervop::precision::parse(name);
  if (!p) throw input_error(fmt::format("{}: line {}: unknown precision `{}`", where, line, name));
  return *p;
}

double seconds_of(const std::string& value) { return std::strtod(value.c_str(), nullptr); }

// The metadata's texts and figures (bounds and estimates: non-negative decimals, kept as their
// text for display and their value), by key.
constexpr std::pair<std::string_view, std::string reference_metadata::*> metadata_texts[] = {
    {"scene", &reference_metadata::scene_name},       {"scene_source", &reference_metadata::scene_source},
    {"command", &reference_metadata::command},        {"overrides", &reference_metadata::overrides},
    {"times", &reference_metadata::times},            {"method", &reference_metadata::method},
    {"verify_method", &reference_metadata::verify_method}, {"certify_method", &reference_metadata::certify_method},
    {"attitude", &reference_metadata::attitude},      {"coupled", &reference_metadata::coupled}};
constexpr std::pair<std::string_view, std::optional<decimal> reference_metadata::*> metadata_figures[] = {
    {"estimated_max_error", &reference_metadata::estimated_max_error},
    {"estimated_max_error_omega", &reference_metadata::estimated_max_error_omega},
    {"estimated_max_attitude_error", &reference_metadata::estimated_max_attitude_error},
    {"certified_max_error", &reference_metadata::certified_max_error},
    {"certified_max_error_omega", &reference_metadata::certified_max_error_omega},
    {"certified_max_error_q", &reference_metadata::certified_max_error_q},
    {"q_norm_drift", &reference_metadata::q_norm_drift}};

// One "# key: value" line into `m`; `where` and `line` name it in messages. Unknown keys are
// ignored, so a file written by a later version still reads.
void read_metadata_line(reference_metadata& m, const std::string& l, const std::string& where, std::size_t line) {
  for (const auto& [key, member] : metadata_texts)
    if (auto v = metadata_value(l, key)) return void(m.*member = *v);
  for (const auto& [key, member] : metadata_figures)
    if (auto v = metadata_value(l, key)) {
      const auto parsed = parse_decimal(*v);
      if (!parsed.number || parsed.number->value < 0)
        throw input_error(fmt::format("{}: line {}: {} `{}` is not a non-negative number", where, line, key, *v));
      return void(m.*member = decimal{*v, parsed.number->value});
    }
  if (auto v = metadata_value(l, "precision")) m.precision = parse_precision(*v, where, line);
  else if (auto vp = metadata_value(l, "verify_precision")) m.verify_precision = parse_precision(*vp, where, line);
  else if (auto w = metadata_value(l, "wall_seconds")) m.wall_seconds = seconds_of(*w);
  else if (auto wv = metadata_value(l, "wall_seconds_verify")) m.wall_seconds_verify = seconds_of(*wv);
  else if (auto note = metadata_value(l, "note")) m.notes.push_back(*note);
}

// Reads the '#' lines of a reference file into its metadata.
reference_metadata metadata_of(const csv_rows& rows) {
  reference_metadata m;
  std::size_t line = 0;
  for (const std::string& l : rows.comments()) {
    ++line;  // the comments come first in the file (blank lines aside)
    if (l.starts_with("# scene_text:")) {
      std::string_view text = std::string_view(l).substr(13);
      if (text.starts_with(" ")) text.remove_prefix(1);
      m.scene_text += std::string(text) + "\n";
    } else {
      read_metadata_line(m, l, rows.where(), line);
    }
  }
  return m;
}

// The value of the "# error_units:" line: every figure's unit, named. A body's come in several
// (the normalized state, rad/s, rad), and the normalized and coefficient forms' have none, which
// the line says too.
std::string error_units_of(const reference_metadata& m, reference_layout layout) {
  std::vector<std::string> figures;
  const auto add = [&](bool present, std::string_view name) {
    if (present) figures.push_back(fmt::format("{} = {}", name, error_unit(layout, name)));
  };
  add(m.estimated_max_error.has_value(), "estimated_max_error");
  add(m.estimated_max_error_omega.has_value(), "estimated_max_error_omega");
  add(m.estimated_max_attitude_error.has_value(), "estimated_max_attitude_error");
  add(m.certified_max_error.has_value() && layout != reference_layout::direct, "certified_max_error");
  add(m.certified_max_error_omega.has_value(), "certified_max_error_omega");
  add(m.certified_max_error_q.has_value(), "certified_max_error_q");
  return fmt::format("{}{}", fmt::join(figures, "; "),
                     m.certified_max_error ? "; each row's radius columns likewise" : "");
}

}  // namespace

eulervop::precision reference_metadata::reading_precision() const {
  return precision.type == eulervop::precision::kind::mpfr ? precision : eulervop::precision::binary128();
}

std::string precision_text(const eulervop::precision& p) {
  if (p.type == eulervop::precision::kind::mpfr)
    return fmt::format("{} (effective_bits={})", p.name(), eulervop::mpfr_effective_bits(p.bits));
  return p.name();
}

std::string attitude_convention(const eulervop::precision& p) {
  return fmt::format("q0..q3 a Hamilton quaternion, scalar first, body to inertial (v_inertial = q v_body q*, "
                     "q' = 1/2 q (x) (0, omega), omega in the body's axes as listed); [initial] q normalized in {}",
                     p.name());
}

reference_layout reference_layout_of(const scene& s) {
  if (s.is_coefficient_form()) return reference_layout::coefficient;
  if (uses_direct_form(s)) return reference_layout::direct;
  return s.is_physical() ? reference_layout::physical : reference_layout::normalized;
}

std::string error_unit(reference_layout layout, std::string_view figure) {
  if (figure == "estimated_max_attitude_error") return "rad (rotation angle)";
  if (figure.ends_with("_q")) return "|q - q*|_2 of the printed quaternion (no unit)";
  if (figure.ends_with("_omega")) return "rad/s";
  switch (layout) {
    case reference_layout::direct: return "rad/s";  // the state is omega itself
    case reference_layout::physical: return "normalized Omega (Eq. 20, no unit)";
    case reference_layout::coefficient: return "|y - y*|_2 (no unit)";
    case reference_layout::normalized: break;
  }
  return "Eq. 20 (no unit)";
}

std::vector<std::string> reference_columns(const reference_metadata& m, reference_layout layout) {
  std::vector<std::string> c;
  const auto add = [&c](std::initializer_list<const char*> names) { c.insert(c.end(), names.begin(), names.end()); };
  const bool attitude = !m.attitude.empty();
  // A certified file ends each row with its radii: of the state (`radius`; in the direct form the
  // state is omega: `radius_omega`), of omega in rad/s for a physical body, and of q.
  const bool certified = m.certified_max_error.has_value();
  switch (layout) {
    case reference_layout::normalized: add({"tau", "Omega1", "Omega2", "Omega3"}); break;
    case reference_layout::physical:
      add({"t", "omega1", "omega2", "omega3"});
      if (attitude) add({"q0", "q1", "q2", "q3"});
      add({"tau", "Omega1", "Omega2", "Omega3"});
      if (certified) add({"radius", "radius_omega"});
      break;
    case reference_layout::direct:
      add({"t", "omega1", "omega2", "omega3"});
      if (attitude) add({"q0", "q1", "q2", "q3"});
      if (certified) add({"radius_omega"});
      break;
    case reference_layout::coefficient: add({"t", "y1", "y2", "y3"}); break;
  }
  if (certified && (layout == reference_layout::normalized || layout == reference_layout::coefficient)) add({"radius"});
  if (certified && attitude && layout != reference_layout::normalized && layout != reference_layout::coefficient)
    add({"radius_q"});
  return c;
}

std::string reference_csv_header(const reference_metadata& m, reference_layout layout) {
  fmt::memory_buffer out;
  auto line = [&]<class... Args>(fmt::format_string<Args...> format, Args&&... args) {
    format_into(out, format, std::forward<Args>(args)...);
    out.push_back('\n');
  };
  line("# eulervop {}", EULERVOP_VERSION);
  line("# scene: {}", m.scene_name);
  line("# scene_source: {}", m.scene_source);
  if (!m.command.empty()) line("# command: {}", m.command);
  if (!m.overrides.empty()) line("# overrides: {}", m.overrides);
  if (!m.times.empty()) line("# times: {}", m.times);
  line("# precision: {}", precision_text(m.precision));
  line("# method: {}", m.method);
  if (m.wall_seconds) line("# wall_seconds: {:.3f}", *m.wall_seconds);
  if (m.estimated_max_error) {
    line("# estimated_max_error: {}", m.estimated_max_error->text);
    if (m.estimated_max_error_omega) line("# estimated_max_error_omega: {}", m.estimated_max_error_omega->text);
    if (m.estimated_max_attitude_error)
      line("# estimated_max_attitude_error: {}", m.estimated_max_attitude_error->text);
    if (m.verify_precision) line("# verify_precision: {}", precision_text(*m.verify_precision));
    line("# verify_method: {}", m.verify_method);
    if (m.wall_seconds_verify) line("# wall_seconds_verify: {:.3f}", *m.wall_seconds_verify);
  }
  if (m.certified_max_error) {
    line("# certified_max_error: {}", m.certified_max_error->text);
    if (m.certified_max_error_omega) line("# certified_max_error_omega: {}", m.certified_max_error_omega->text);
    if (m.certified_max_error_q) line("# certified_max_error_q: {}", m.certified_max_error_q->text);
    line("# certify_method: {}", m.certify_method);
  }
  if (m.estimated_max_error || m.certified_max_error) line("# error_units: {}", error_units_of(m, layout));
  for (const std::string& note : m.notes) line("# note: {}", note);
  if (!m.attitude.empty()) line("# attitude: {}", m.attitude);
  if (!m.coupled.empty()) line("# coupled: {}", m.coupled);
  if (m.q_norm_drift) line("# q_norm_drift: {}", m.q_norm_drift->text);
  std::istringstream scene_lines(m.scene_text);
  for (std::string l; std::getline(scene_lines, l);) {
    if (!l.empty() && l.back() == '\r') l.pop_back();
    line("# scene_text: {}", l);
  }
  line("{}", fmt::join(reference_columns(m, layout), ","));
  return fmt::to_string(out);
}

void reference_csv_row_writer::end_row() {
  buffer_.push_back('\n');
  if (buffer_.size() >= row_chunk) flush();
}

void reference_csv_row_writer::flush() {
  if (buffer_.size() == 0) return;
  sink_(std::string_view(buffer_.data(), buffer_.size()));
  buffer_.clear();
}

reference_csv_reader::reference_csv_reader(std::istream& in, std::string where)
    : rows_(in, std::move(where)), meta_(metadata_of(rows_)) {
  const char* state = rows_.column("Omega1") ? "Omega" : rows_.column("omega1") ? "omega" : rows_.column("y1") ? "y" : "Omega";
  for (int k = 0; k < 3; ++k) Omega_[k] = column(fmt::format("{}{}", state, k + 1));
}

reference_metadata read_reference_metadata(std::string_view what, const std::string& path) {
  std::ifstream in = open_input_file(what, path);
  return reference_csv_reader(in, fmt::format("{} {}", what, path)).metadata();
}

std::size_t reference_csv_reader::column(const std::string& name, std::string_view why) const {
  const auto c = rows_.column(name);
  if (!c)
    throw input_error(
        fmt::format("{}: line {}: the header has no column `{}`{}", rows_.where(), rows_.line(), name, why));
  return *c;
}

}  // namespace eulervop::app
