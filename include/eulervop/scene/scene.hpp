// A scene: one problem of Euler's equations as the user describes it in TOML (docs/scenes.md).
//
// A scene is normalized (G, Omega or c1/c2/u, tau: Eq. 5), physical ([body] inertia, M, omega,
// t; converted by Eqs. 2-4), or in the coefficient form ([equations] a, f, y, t:
// y_i' = a_i y_j y_k + f_i). Numbers are kept as exact decimal text (decimal.hpp) and become
// values of the scalar type only in scene_problem.hpp; a torque component may be a formula of
// the time and the state (model/expression.hpp), and pieces apply other components on time
// windows (model/torque_law.hpp). Loading validates everything a later stage would otherwise
// trip over, and reports the first problem as an input_error whose one-line message names the
// field and the value.
#pragma once

#include <eulervop/scene/decimal.hpp>
#include <eulervop/scene/input_error.hpp>

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/model/torque_law.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace eulervop::scene {

using decimal3 = std::array<decimal, 3>;

// Which variables the scene is written in.
enum class scene_units {
  normalized,   // G, Omega, tau (Eq. 5)
  physical,     // inertia kg m^2, M N m, omega rad/s, t s (Eqs. 1-4)
  coefficient,  // [equations] a, f, y, t: y_i' = a_i y_j y_k + f_i, (i, j, k) cyclic
};

// [initial] Omega = [...] (normalized), omega = [...] (physical, rad/s) or y = [...]
// (coefficient form).
struct initial_rates {
  decimal3 rates;
};

// [initial] c1, c2, u (normalized only): Omega = (c1 cn u, c1 sn u, c2 dn u), modulus
// k = c1/c2 < 1 (Eqs. 10-12).
struct initial_elements {
  decimal c1, c2, u;
};

// [run] step: "K/N" (K(k at tau = 0) / N, in tau) or a plain positive number (in the scene's
// time variable: tau, or t for physical scenes).
struct step_spec {
  std::optional<std::int64_t> K_divisor;  // set for "K/N"
  std::optional<decimal> value;           // set for a plain number
};

struct scene {
  // Made, copied, moved and destroyed in the scene library (src/scene/scene.cpp), once, rather
  // than in every unit that passes scenes around.
  scene();
  scene(const scene&);
  scene(scene&&) noexcept;
  scene& operator=(const scene&);
  scene& operator=(scene&&) noexcept;
  ~scene();

  std::string name;
  std::string description;
  std::string origin;       // the path it was loaded from, or the embedded default's origin
  std::string source_text;  // the TOML text, verbatim (copied into every output's metadata)

  scene_units units = scene_units::normalized;
  std::optional<decimal3> inertia;       // [body] inertia = [I1, I2, I3], physical only
  std::optional<decimal3> coefficients;  // [equations] a = [a1, a2, a3], coefficient form only

  // [torque]: G (normalized), M (physical) or f (coefficient form). A constant torque (every
  // component a number, no pieces) is `torque`; one with a formula or pieces is `torque_law`
  // instead. Neither: torque-free.
  std::optional<decimal3> torque;
  std::shared_ptr<const eulervop::torque_law> torque_law;
  // [torque.gravity_gradient] mean_motion: n in rad/s of a circular orbit in the inertial x-y
  // plane (model/gravity_gradient.hpp); a body with an attitude only.
  std::optional<decimal> gravity_gradient;

  // What the user should know but is no error (e.g. moments that no rigid body has): each is
  // printed as a "note:" line, and written into the reference's metadata.
  std::vector<std::string> notes;

  std::variant<initial_rates, initial_elements> initial;
  // [initial] q: the attitude (physical scenes only), a Hamilton quaternion, scalar first, body
  // to inertial; its norm is 1 to 1e-9 (normalized in the run's precision).
  std::optional<std::array<decimal, 4>> attitude;

  // [span]: tau_end (normalized) or t_end (physical) > 0; sample count (>= 2, equally spaced,
  // endpoints included) or explicit sample times (strictly increasing, in [0, span_end]); a scene
  // may give neither, for the command line to complete (--samples, --times).
  decimal span_end;
  std::optional<std::int64_t> samples;
  std::vector<decimal> times;

  // [run]: settings for the fixed-step comparison runs of later commands (stored only).
  std::optional<step_spec> step;
  std::vector<std::string> methods;        // subset of {rk4, rkf45, dp45, rk8}
  std::vector<std::string> formulations;   // subset of {euler, vop, vop-theta}

  // [reference]
  eulervop::precision reference_precision = eulervop::precision::binary128();
  std::optional<unsigned> degree;     // Chebyshev degree
  std::optional<decimal> tolerance;   // relative tolerance per segment

  bool is_physical() const { return units == scene_units::physical; }
  bool is_coefficient_form() const { return units == scene_units::coefficient; }
  // The time variable: tau (normalized) or t.
  std::string_view time_name() const { return units == scene_units::normalized ? "tau" : "t"; }
  // "tau_end" or "t_end": the span key, for messages.
  std::string_view span_key() const { return units == scene_units::normalized ? "tau_end" : "t_end"; }
  // The torque's key: G, M or f.
  std::string_view torque_key() const {
    return units == scene_units::normalized ? "G" : units == scene_units::physical ? "M" : "f";
  }
  // The state's names without the index: Omega, omega or y.
  std::string_view state_name() const {
    return units == scene_units::normalized ? "Omega" : units == scene_units::physical ? "omega" : "y";
  }
  // Whether the torque changes with the time or the state (a formula, or pieces).
  bool has_torque_law() const { return torque_law != nullptr; }
  bool has_attitude() const { return attitude.has_value(); }
  // Whether the torque reads the attitude (a formula naming q0..q3, or the gravity gradient): the
  // rates and q are then one problem (model/coupled_problem.hpp), not a cascade.
  bool couples_attitude() const {
    return gravity_gradient.has_value() || (torque_law && torque_law->uses_attitude());
  }
};

// Accepted names in [run] methods and formulations.
inline constexpr std::array<std::string_view, 4> known_methods = {"rk4", "rkf45", "dp45", "rk8"};
inline constexpr std::array<std::string_view, 3> known_formulations = {"euler", "vop", "vop-theta"};

// Limits shared by the scene file and the command-line flags that override it.
struct scene_limits {
  // [span] samples: far above any use, small enough that an MPFR run's samples fit in memory.
  static constexpr std::int64_t min_samples = 2, max_samples = 10'000'000;
  // [reference] degree: below 4 a segment cannot resolve a rotation; above 1024 the O(N^2)
  // Chebyshev matrices dominate at any precision we support.
  static constexpr std::int64_t min_degree = 4, max_degree = 1024;
};

// Parses and validates a scene. `origin` names it in messages ("scene <origin>: ...").
scene parse_scene(std::string_view toml_text, std::string origin);

// Reads and parses a scene file; an unreadable path is an input_error naming it. A bare name
// that is no file but a shipped scene's ("sciml-rigid-body") reads that scene.
scene load_scene_file(const std::filesystem::path& path);

// The shipped scenes, by name (the file's stem, "sciml-rigid-body") to their files: those of the
// source tree this library was built from (data/scenes/), else the installed ones
// (share/eulervop/scenes/). Empty when neither is there.
std::map<std::string, std::filesystem::path> shipped_scenes();

// The paper's scene embedded in the binary (data/scenes/paper-fig1.toml).
scene load_default_scene();

}  // namespace eulervop::scene
