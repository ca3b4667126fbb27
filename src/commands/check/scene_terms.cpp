#include "commands/check/scene_terms.hpp"

#include "io/reference_csv.hpp"

#include <fmt/format.h>

#include <variant>

namespace eulervop::app {

namespace {

// No torque, or a constant one of zeros: no formula, piece or gravity gradient.
bool is_torque_free(const scene& s) {
  if (s.torque_law || s.gravity_gradient) return false;
  if (!s.torque) return true;
  for (const decimal& m : *s.torque)
    if (m.value != 0) return false;
  return true;
}

// Eq. 7 holds for the normalized Eq. 5 only; why a form has none.
void set_invariants_of_form(integrated_form form, scene_terms& terms) {
  if (form == integrated_form::normalized) return;
  terms.invariants = false;
  terms.invariants_note = form == integrated_form::direct
                              ? "Eq. 7 holds only for the normalized Eq. 5, not for the direct form of Eq. 1"
                              : "Eq. 7 holds only for the normalized Eq. 5, not for the coefficient form";
}

// The unit of an estimated error of a reference integrated in `form` (the variables --verify
// compares), in the words of the reference's own `# error_units:` line (error_unit); `physical`:
// a body integrated in the normalized variables.
void set_estimated_error_unit(integrated_form form, bool physical, scene_terms& terms) {
  switch (form) {
    case integrated_form::direct:
      terms.estimated_error_unit = error_unit(reference_layout::direct, "estimated_max_error");
      terms.estimated_error_label = "rad/s";
      return;
    case integrated_form::coefficient:
      terms.estimated_error_unit = error_unit(reference_layout::coefficient, "estimated_max_error");
      terms.estimated_error_label = "(in y, coefficient form)";
      return;
    case integrated_form::normalized:
      terms.estimated_error_unit =
          error_unit(physical ? reference_layout::physical : reference_layout::normalized, "estimated_max_error");
      terms.estimated_error_label = "(normalized, Eq. 20)";
      return;
  }
}

}  // namespace

integrated_form integrated_form_of(const scene& s) {
  if (s.is_coefficient_form()) return integrated_form::coefficient;
  if (uses_direct_form(s)) return integrated_form::direct;
  return integrated_form::normalized;
}

scene_terms scene_terms_of(const scene& s, const trajectory_columns& cols) {
  scene_terms terms;
  const integrated_form form = integrated_form_of(s);
  terms.torque_free = is_torque_free(s);
  set_invariants_of_form(form, terms);
  if (terms.invariants && !*terms.torque_free) {
    terms.invariants = false;
    terms.invariants_in_table = false;
    terms.invariants_note =
        fmt::format("c1^2 and c2^2 of Eq. 7 are constant only for a torque-free body, and scene {} has a torque", s.name);
  }
  std::string key =
      std::holds_alternative<eulervop::scene::initial_elements>(s.initial) ? "c1, c2, u" : std::string(s.state_name());
  if (cols.state != s.state_name()) key += fmt::format(", as {} of Eq. 4", cols.state);
  terms.initial_rates = fmt::format("the initial state of scene {} ([initial] {})", s.name, key);
  terms.initial_q = fmt::format("the initial state of scene {} ([initial] q)", s.name);
  set_estimated_error_unit(form, s.is_physical(), terms);
  return terms;
}

scene_terms unknown_scene_terms(integrated_form form) {
  scene_terms terms;
  set_invariants_of_form(form, terms);
  if (terms.invariants)
    terms.invariants_note =
        "the reference file has no `# scene_text:`, so whether its body is torque-free is not known; c1^2 and c2^2 "
        "are constant only if it is";
  set_estimated_error_unit(form, false, terms);
  return terms;
}

std::optional<motion_function> motion_of(const scene& s) {
  if (s.couples_attitude()) return std::nullopt;
  return with_problem<double>(s, [](const auto& problem) {
    return motion_function([problem](double tau, const vec3<double>& y, vec3<double>& dy) { problem.rhs(tau, y, dy); });
  });
}

}  // namespace eulervop::app
