// The formulations of the comparison runs (comparison_run.hpp):
//   euler      the normalized Euler equations, Eq. 5, integrated directly;
//   vop        the paper's variation of parameters, elements (c1, c2, u), Eqs. 12-16
//              (vop/vop_system.hpp);
//   vop-theta  the secular-free variant, elements (c1, c2, theta), theta = pi u / (2K) kept in
//              [-pi, pi) with whole turns counted apart (vop/vop_theta_system.hpp,
//              docs/vop-strategies.md).
#pragma once

#include <array>
#include <optional>
#include <string_view>

namespace eulervop {

enum class formulation { euler, vop, vop_theta };

inline constexpr std::array<formulation, 3> all_formulations = {formulation::euler, formulation::vop,
                                                                formulation::vop_theta};

constexpr std::string_view formulation_name(formulation f) {
  switch (f) {
    case formulation::euler: return "euler";
    case formulation::vop: return "vop";
    case formulation::vop_theta: return "vop-theta";
  }
  return "?";
}

constexpr std::optional<formulation> formulation_from_name(std::string_view text) {
  for (formulation f : all_formulations)
    if (formulation_name(f) == text) return f;
  return std::nullopt;
}

}  // namespace eulervop
