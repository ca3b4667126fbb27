// The reference as a test oracle for other tools: build a problem, get a
// dense reference in a chosen precision, evaluate it at any tau, and measure a double
// trajectory against it by Eq. 20.
//
//   #include <eulervop/oracle.hpp>            // CMake: find_package(eulervop REQUIRED)
//                                             //        target_link_libraries(app PRIVATE eulervop::core)
//   using eulervop::quad;
//   const auto p = eulervop::oracle::problem<quad>({1, 1, 1}, {quad("0.5"), 0, 1});  // G, Omega(0)
//   const eulervop::oracle::reference<quad> ref(p, quad(20));  // Omega on [0, 20], ~1e-32 accurate
//   eulervop::vec3<quad> Om = ref(quad("1.5"));                // Omega(1.5)
//   double e = ref.error(1.5, my_omega_at_1_5);                // Eq. 20 error of a double state
//   double worst = ref.max_error(my_taus, my_states);          // over a whole trajectory
//
// Precision is the scalar type: double, eulervop::quad (binary128) or eulervop::mpfr_real.
// MPFR values take the thread's default precision when they are created, so construct and use
// an MPFR reference inside one scope:
//   const eulervop::mpfr_precision_scope scope(256);
//   eulervop::oracle::reference<eulervop::mpfr_real> ref(eulervop::oracle::problem<eulervop::mpfr_real>(G, Om0), 20);
// A precision named at run time ("double", "quad", "mpfr:256") is eulervop::precision::parse(text);
// dispatch on its .type to one of the three instantiations (as `eulervop check` does).
//
// Values: give numbers in T directly from text (quad("0.1"), not quad(0.1)) when the decimal
// matters: a double literal carries its own rounding error of ~1e-17 into the problem.
//
// Scene files (TOML, data/scenes/) are read by the optional library eulervop::scene
// (find_package(eulervop REQUIRED COMPONENTS scene); needs fmt and toml++), not by this
// header-only core:
//   #include <eulervop/scene/scene_problem.hpp>
//   const eulervop::scene::scene s = eulervop::scene::load_scene_file("paper-fig1.toml");
//   const auto p = eulervop::scene::to_problem<quad>(s);  // decimals converted directly in quad
//   const quad tau_end = eulervop::scene::tau_end_of<quad>(s);
//   eulervop::oracle::reference<quad> ref(p, tau_end);
// load_scene_file throws eulervop::scene::input_error (a std::runtime_error) naming the bad field.
// A scene whose torque is a formula of time or state, or has pieces, or a scene in the
// coefficient form (the published test problems, data/scenes/problems/), has a problem of its own
// type: with_problem calls a function with it.
//   const auto s = eulervop::scene::load_scene_file("data/scenes/problems/sciml-rigid-body.toml");
//   const auto ref = eulervop::scene::with_problem<quad>(s, [&](const auto& p) {
//     return eulervop::oracle::reference<quad>(p, eulervop::scene::tau_end_of<quad>(s));
//   });
// From values, any torque type (model/torque.hpp) and the coefficients of y_i' = a_i y_j y_k + g_i:
//   eulervop::oracle::problem<quad>(a, my_torque, y0)
#pragma once

#if defined(__GNUC__) && !defined(__clang__) && defined(__STRICT_ANSI__)
#error "eulervop needs GNU extensions for quad (__float128): compile with -std=gnu++20 (CMake: CXX_EXTENSIONS ON, the default)"
#endif

#include <eulervop/reference/integrate.hpp>
#include <eulervop/model/error_measure.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/integrals.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/core/scalar.hpp>

#include <cstddef>
#include <stdexcept>
#include <vector>

namespace eulervop::oracle {

// The normalized problem of Eq. 5 from values: constant torque G, Omega(0) = Omega0, tau0 = 0.
template <scalar T>
euler_problem<T> problem(const vec3<T>& G, const vec3<T>& Omega0) {
  euler_problem<T> p;
  p.torque.G = G;
  p.Omega0 = Omega0;
  p.tau0 = T(0);
  return p;
}

// y_i' = a_i y_j y_k + g_i(t, y), (i, j, k) cyclic, from values: the coefficient form (Eq. 1 with
// any a), with a torque of any type (model/torque.hpp, e.g. one of time), y(0) = y0, t0 = 0.
template <scalar T, class Torque>
euler_problem<T, Torque> problem(const vec3<T>& a, const Torque& g, const vec3<T>& y0) {
  euler_problem<T, Torque> p;
  p.form = equation_form::direct;
  p.a = a;
  p.torque = g;
  p.Omega0 = y0;
  p.tau0 = T(0);
  return p;
}

// A physical body (torque M in N m, omega(0) in rad/s, in the body's principal axes). Principal
// moments I1 < I2 < I3 are mapped by Eqs. 2-4; moments in any order, equal or not, by Eqs. 2-4
// after a relabelling of the axes, or as Eq. 1 itself in the direct form when two of them are
// equal or nearly so (needs_direct_form). Either way, use scaling.tau_of_t(t) for times and
// scaling.omega_of_Omega(...) for rates.
template <scalar T>
struct physical_problem {
  physical_scaling<T> scaling;
  euler_problem<T> problem;

  physical_problem(const inertia<T>& I, const vec3<T>& M, const vec3<T>& omega0)
      : scaling(I), problem(scaling.problem(M, omega0)) {}
  physical_problem(const vec3<T>& moments, const vec3<T>& M, const vec3<T>& omega0)
      : scaling(needs_direct_form<double>({static_cast<double>(moments[0]), static_cast<double>(moments[1]),
                                           static_cast<double>(moments[2])})
                    ? physical_scaling<T>::direct(moments)
                    : physical_scaling<T>(principal_axes<T>(moments))),
        problem(scaling.problem(M, omega0)) {}
};

// The dense reference on [0, tau_end]: Chebyshev-Picard at the precision of T (tolerance and
// degree from T unless `settings` says otherwise). Throws eulervop::numerical_failure if the
// integrator gives up (a blow-up, or a segment that cannot converge).
template <scalar T>
class reference {
 public:
  // Any problem of Euler's equations in T: a constant torque, or one of time and state.
  template <class Torque>
  reference(const euler_problem<T, Torque>& p, const T& tau_end, const picard_settings& settings = {})
      : trajectory_(integrate_reference(p, tau_end, settings, {}, &stats_)) {}

  // Omega(tau) for tau in [0, tau_end] (std::out_of_range outside).
  vec3<T> operator()(const T& tau) const { return trajectory_(tau); }

  const T& tau_end() const { return trajectory_.tau_end(); }
  const picard_stats& stats() const { return stats_; }
  const dense_trajectory<T>& trajectory() const { return trajectory_; }

  // Eq. 20: |Omega_ref(tau) - Omega|, computed in T (the double state converts exactly),
  // returned in double. `tau` is converted to T: pass it in T for a time a double cannot hold.
  double error(const T& tau, const vec3<double>& Omega) const {
    return static_cast<double>(eq20_error((*this)(tau), Omega));
  }

  // The largest Eq. 20 error over a trajectory (taus[i], states[i]); the index of the row in
  // *where if given. std::invalid_argument if the sizes differ.
  double max_error(const std::vector<double>& taus, const std::vector<vec3<double>>& states,
                   std::size_t* where = nullptr) const {
    if (taus.size() != states.size()) throw std::invalid_argument("oracle::reference::max_error: sizes differ");
    double worst = 0;
    for (std::size_t i = 0; i < taus.size(); ++i) {
      const double e = error(T(taus[i]), states[i]);
      if (i == 0 || e > worst) {
        worst = e;
        if (where) *where = i;
      }
    }
    return worst;
  }

 private:
  picard_stats stats_;  // declared first: filled while trajectory_ is initialised
  dense_trajectory<T> trajectory_;
};

}  // namespace eulervop::oracle
