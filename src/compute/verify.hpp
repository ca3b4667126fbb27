// --verify: the samples of a reference recomputed one precision up, and the largest Eq. 20
// difference (docs/reference.md), for a body also in rad/s. Compiled once, in verify.cpp, for
// double, quad and MPFR.
#pragma once

#include "compute/scene_library.hpp"

#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/core/vec3.hpp>

#include <optional>

#include <string>
#include <vector>

namespace eulervop::app {

// The verification (--verify): the same samples, recomputed one precision up with the
// integrator's default (stricter) settings, from the scene's decimals converted directly into
// the wider type. Evaluated at the narrow run's tau values (widened exactly), so the difference
// measures the narrow run's error at the rows it prints, input rounding included.
struct verify_result {
  decimal max_error;  // three significant digits, as the metadata prints it
  // A body's largest |omega - omega*|_2 in rad/s: of the omega its rows print (Eq. 2 of the
  // narrow Omega, in the narrow type) for a physical scene in the normalized form; max_error
  // itself in the direct form, whose state is omega. None for the other scenes.
  std::optional<decimal> max_error_omega;
  std::optional<decimal> max_attitude_error;  // radians, when the attitude was verified too
  eulervop::precision precision;
  std::string method;
  double wall_seconds = 0;
};

// One precision up: double -> quad -> mpfr:(113+64) ; mpfr:B -> mpfr:(B+64). `narrow` is the
// precision of Lo (its bits matter for MPFR).
// `attitude`, if given, holds the narrow run's attitude at the same samples: it is verified too,
// as the largest rotation angle between the two (core/quaternion.hpp).
template <scalar Lo>
verify_result verify(const scene& s, const Lo& tau_end, const std::vector<Lo>& taus,
                     const std::vector<vec3<Lo>>& Omega, const eulervop::precision& narrow,
                     const std::vector<quaternion<Lo>>* attitude = nullptr);

}  // namespace eulervop::app
