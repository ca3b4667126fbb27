// The Runge-Kutta methods as a run-time value: the choice a command line or a scene makes, once
// per run. The methods themselves are tag types (tableaux.hpp, embedded_pairs.hpp), and
// dispatch_method / dispatch_pair hand the concrete one to a generic lambda.
//
// Methods (stages = right-hand-side evaluations per step; FSAL is not used in fixed stepping):
//   rk4     classical Runge-Kutta, order 4, 4 stages.
//   rkf45   Fehlberg 4(5), advancing with its 5th-order weights (our reading of the paper's
//           "Runge-Kutta 4/5"), order 5, 6 stages. HNW I, Table II.5.1.
//   dp45    Dormand-Prince 5(4), advancing with the 5th-order solution, order 5, 6 stages. The
//           pair's 7th stage (FSAL, a7j = bj, b7 = 0) serves only the embedded 4th-order error
//           estimate, which a fixed-step run never uses, so it is not evaluated. HNW I, Table II.5.2.
//   rk8     the 8th-order 12-stage method of DOP853 (Hairer & Wanner). See
//           detail/butcher_dop853.hpp for which coefficients are exact and which carry the ~30
//           digits printed in dop853.f.
//   dop853  rk8 with DOP853's embedded 5th- and 3rd-order error estimators: an adaptive method
//           (embedded_pairs.hpp). At a fixed step it is rk8.
// HNW I = E. Hairer, S. P. Norsett, G. Wanner, Solving Ordinary Differential Equations I, 2nd ed.
#pragma once

#include <array>
#include <optional>
#include <string_view>

namespace eulervop::rk {

enum class method { rk4, rkf45, dp45, rk8, dop853 };

// The methods of a fixed-step run, and those with an embedded error estimate (adaptive runs).
inline constexpr std::array<method, 4> fixed_step_methods = {method::rk4, method::rkf45, method::dp45,
                                                             method::rk8};
inline constexpr std::array<method, 3> adaptive_methods = {method::rkf45, method::dp45, method::dop853};
inline constexpr std::array<method, 5> all_methods = {method::rk4, method::rkf45, method::dp45, method::rk8,
                                                      method::dop853};

// The name of a method on the command line and in the outputs (the tags' `name` too).
constexpr std::string_view method_name(method m) {
  switch (m) {
    case method::rk4: return "rk4";
    case method::rkf45: return "rkf45";
    case method::dp45: return "dp45";
    case method::rk8: return "rk8";
    case method::dop853: return "dop853";
  }
  return "?";
}

// True for the methods with an embedded error estimate.
constexpr bool is_adaptive(method m) { return m == method::rkf45 || m == method::dp45 || m == method::dop853; }
// True for the methods of a fixed-step run (dop853 is run adaptively; at a fixed step it is rk8).
constexpr bool is_fixed_step(method m) { return m != method::dop853; }

// "rk4", "rkf45", "dp45", "rk8", "dop853" (exact, lower case); nullopt otherwise.
constexpr std::optional<method> method_from_name(std::string_view text) {
  for (method m : all_methods)
    if (method_name(m) == text) return m;
  return std::nullopt;
}

}  // namespace eulervop::rk
