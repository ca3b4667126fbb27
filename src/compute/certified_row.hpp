// A certified row of a reference: its cells as printed and their radii, as texts (the radii are
// proven for those very cells). Apart from the certificate (certified_reference.hpp), so that what
// only keeps or writes rows does not compile the certificate's headers.
#pragma once

#include <array>
#include <optional>
#include <string>

namespace eulervop::app {

// A row's cells as printed: the integrator's state (Omega, omega in the direct form, or y), and
// for a physical body in the normalized form omega in rad/s (listed axes), and q with an attitude.
struct certified_cells {
  std::array<std::string, 3> state;
  std::optional<std::array<std::string, 3>> omega;
  std::optional<std::array<std::string, 4>> q;
};

// The radii of a row: of the state (the `radius` column, or `radius_omega` in the direct form), of
// omega in rad/s (`radius_omega`, a physical body in the normalized form) and of q (`radius_q`).
struct certified_radii {
  std::string state;
  std::optional<std::string> omega, q;
};

// The largest radius of each column so far.
struct certified_maxima {
  std::string state, omega, q;
};

}  // namespace eulervop::app
