// A scene turned into numbers of the scalar type T: the normalized problem of Eq. 5, its span
// and its sample times.
//
// Every value is converted from the scene's exact decimal text directly into T (so a quad run
// sees 0.1 to 36 digits), and physical scenes are mapped by Eqs. 2-4 in T as well. For MPFR,
// call these inside the eulervop::mpfr_precision_scope of the run: values take the precision
// current at their creation.
#pragma once

#include <eulervop/scene/scene.hpp>

#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/integrals.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/core/scalar.hpp>

#include <boost/math/special_functions/jacobi_elliptic.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <variant>
#include <vector>

namespace eulervop::scene {

template <scalar T>
vec3<T> to_vec3(const decimal3& d) {
  return {d[0].template to_scalar<T>(), d[1].template to_scalar<T>(), d[2].template to_scalar<T>()};
}

// Whether a physical scene uses the direct form (needs_direct_form); decided from the decimals
// as doubles, once, so that every precision (and --verify) integrates the same equations.
inline bool uses_direct_form(const scene& s) {
  return s.is_physical() &&
         needs_direct_form<double>({(*s.inertia)[0].value, (*s.inertia)[1].value, (*s.inertia)[2].value});
}

// The change of variables for a physical scene (precondition: s.is_physical()), in the body's
// axes as the scene gives them: Eqs. 2-4, or none in the direct form.
template <scalar T>
physical_scaling<T> scaling_of(const scene& s) {
  const vec3<T> I = to_vec3<T>(*s.inertia);
  if (uses_direct_form(s)) return physical_scaling<T>::direct(I);
  return physical_scaling<T>(principal_axes<T>(I));
}

// Omega from the torque-free solution (Eq. 12) at u: (c1 cn u, c1 sn u, c2 dn u), k = c1/c2 < 1.
template <scalar T>
vec3<T> Omega_of_elements(const initial_elements& e) {
  const T c1 = e.c1.template to_scalar<T>(), c2 = e.c2.template to_scalar<T>();
  if (e.u.value == 0) return {c1, T(0), c2};  // exact: cn 0 = dn 0 = 1, sn 0 = 0
  using std::sqrt;
  const T u = e.u.template to_scalar<T>();
  const T k = c1 / c2;
  T cn, dn_ratio;
  const T sn = boost::math::jacobi_elliptic(k, u, &cn, &dn_ratio);
  // Boost's dn is a ratio that is 0/0 at odd multiples of K (docs/design.md section 2);
  // dn^2 = kc^2 + k^2 cn^2 has no cancellation, and kc^2 = (c2-c1)(c2+c1)/c2^2 keeps digits near k = 1.
  const T kc2 = (c2 - c1) * (c2 + c1) / (c2 * c2);
  const T dn = sqrt(kc2 + k * k * cn * cn);
  return {c1 * cn, c1 * sn, c2 * dn};
}

// The scene's problem: G, Omega(tau0), tau0 = 0, normalized (Eq. 5) or, for a physical scene in
// the direct form, Eq. 1 in rad/s.
template <scalar T>
euler_problem<T> to_problem(const scene& s) {
  const vec3<T> zero = {T(0), T(0), T(0)};
  if (s.is_physical()) {
    euler_problem<T> p = scaling_of<T>(s).problem(s.torque ? to_vec3<T>(*s.torque) : zero,
                                                  to_vec3<T>(std::get<initial_rates>(s.initial).rates));
    if (!s.torque) p.torque.G = zero;  // +0 (an axis reversed by the relabelling would negate it)
    return p;
  }
  euler_problem<T> p;
  p.tau0 = T(0);
  p.torque.G = zero;
  if (s.torque) p.torque.G = to_vec3<T>(*s.torque);
  if (const auto* rates = std::get_if<initial_rates>(&s.initial))
    p.Omega0 = to_vec3<T>(rates->rates);
  else
    p.Omega0 = Omega_of_elements<T>(std::get<initial_elements>(s.initial));
  return p;
}

// The end of the span in tau (physical scenes: tau_end = t_end dtau/dt, Eq. 4; t_end in the
// direct form).
template <scalar T>
T tau_end_of(const scene& s) {
  const T end = s.span_end.template to_scalar<T>();
  return s.is_physical() ? scaling_of<T>(s).tau_of_t(end) : end;
}

// The sample times in tau, and for physical scenes also in t (the t column of the output).
template <scalar T>
struct sample_times {
  std::vector<T> tau;
  std::vector<T> t;  // physical scenes only
};

// Equally spaced samples (endpoints included, x_i = end i / (n-1) in T, the last one exactly
// `end`) or the scene's explicit times, in the scene's own time variable, then mapped to tau.
// Since tau = t * rate is monotone under rounding, every tau stays within [0, tau_end_of(s)].
template <scalar T>
sample_times<T> sample_times_of(const scene& s) {
  std::vector<T> x;
  if (s.samples) {
    const T end = s.span_end.template to_scalar<T>();
    const auto n = static_cast<std::size_t>(*s.samples);
    x.reserve(n);
    for (std::size_t i = 0; i + 1 < n; ++i) x.push_back(end * T(i) / T(n - 1));
    x.push_back(end);
  } else {
    x.reserve(s.times.size());
    // Loading compared the times with the span end as doubles; a time whose decimal lies past
    // the end but rounds to the same double (1.00000000000000000001 with tau_end = 1) is caught
    // here, in T, before anything is computed (found by fuzz/fuzz_scene.cpp).
    const T end = s.span_end.template to_scalar<T>();
    for (const auto& t : s.times) {
      x.push_back(t.template to_scalar<T>());
      if (x.back() > end)
        throw input_error("sample time " + t.text + " is beyond " + std::string(s.span_key()) + " = " +
                          s.span_end.text + " (compared exactly, not as doubles)");
    }
  }
  sample_times<T> out;
  if (!s.is_physical()) {
    out.tau = std::move(x);
    return out;
  }
  const physical_scaling<T> scale = scaling_of<T>(s);
  out.tau.reserve(x.size());
  for (const auto& t : x) out.tau.push_back(scale.tau_of_t(t));
  out.t = std::move(x);
  return out;
}

}  // namespace eulervop::scene
