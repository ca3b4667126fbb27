// A scene turned into numbers of the scalar type T: its problem (Eq. 5, Eq. 1 in the direct form,
// or the coefficient form; with a constant torque or one given by formulas), its span and its
// sample times.
//
// Every value is converted from the scene's exact decimal text directly into T (so a quad run
// sees 0.1 to 36 digits), and physical scenes are mapped by Eqs. 2-4 in T as well. For MPFR,
// call these inside the eulervop::mpfr_precision_scope of the run: values take the precision
// current at their creation.
#pragma once

#include <eulervop/scene/scene.hpp>

#include <eulervop/model/coupled_problem.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/expression_torque.hpp>
#include <eulervop/model/integrals.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/model/staged_attitude_torque.hpp>
#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/model/body_rates.hpp>

#include <boost/math/special_functions/jacobi_elliptic.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <stdexcept>
#include <utility>
#include <variant>
#include <vector>

namespace eulervop::scene {

template <scalar T>
vec3<T> to_vec3(const decimal3& d) {
  return {d[0].template to_scalar<T>(), d[1].template to_scalar<T>(), d[2].template to_scalar<T>()};
}

// Whether the scene is integrated in the direct form of Eq. 1 (in t, with coefficients a), not in
// the paper's tau and Omega: a scene in the coefficient form, or a physical scene whose moments
// need it (needs_direct_form; decided from the decimals as doubles, once, so that every
// precision and --verify integrate the same equations).
inline bool uses_direct_form(const scene& s) {
  if (s.is_coefficient_form()) return true;
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

// The scene's problem with its constant torque: G, Omega(tau0), tau0 = 0, normalized (Eq. 5);
// for a physical scene in the direct form, Eq. 1 in rad/s; in the coefficient form,
// y' = a_i y_j y_k + f with the scene's a. A scene whose torque is a formula or has pieces
// (s.has_torque_law()) needs with_problem: std::logic_error here.
template <scalar T>
euler_problem<T> to_problem(const scene& s) {
  if (s.has_torque_law()) throw std::logic_error("to_problem: the scene's torque is not constant; use with_problem");
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
  if (s.is_coefficient_form()) {
    p.form = equation_form::direct;
    p.a = to_vec3<T>(*s.coefficients);
  }
  if (const auto* rates = std::get_if<initial_rates>(&s.initial))
    p.Omega0 = to_vec3<T>(rates->rates);
  else
    p.Omega0 = Omega_of_elements<T>(std::get<initial_elements>(s.initial));
  return p;
}

// The initial state in the integrator's variables (Omega(0), or omega or y in the direct form).
template <scalar T>
vec3<T> initial_state_of(const scene& s) {
  scene constant = s;
  constant.torque_law.reset();
  return to_problem<T>(constant).Omega0;
}

// What the torque depends on: the paths of the integrators differ (model/torque.hpp).
enum class torque_kind { constant, of_time, of_state };

inline torque_kind torque_kind_of(const scene& s) {
  if (!s.has_torque_law()) return torque_kind::constant;
  return s.torque_law->uses_state() ? torque_kind::of_state : torque_kind::of_time;
}

// The problem of a scene whose torque is a formula or has pieces (precondition:
// s.has_torque_law(); OfState as torque_kind_of says): the formulas compiled in T, written in
// the scene's variables and mapped to the integrator's (model/expression_torque.hpp).
template <scalar T, bool OfState>
euler_problem<T, expression_torque<T, OfState>> to_problem_with_law(const scene& s) {
  scene constant = s;  // the same problem with a zero torque, for its form and initial state
  constant.torque_law.reset();
  const euler_problem<T> base = to_problem<T>(constant);
  euler_problem<T, expression_torque<T, OfState>> p;
  p.Omega0 = base.Omega0;
  p.tau0 = base.tau0;
  p.form = base.form;
  p.a = base.a;
  const torque_variables<T> vars =
      s.is_physical() ? torque_variables<T>::of(scaling_of<T>(s)) : torque_variables<T>{};
  p.torque = expression_torque<T, OfState>(s.torque_law, vars);
  return p;
}

// Calls f with the scene's problem in T, of the type its torque needs: euler_problem<T> for a
// constant torque (every fast path of the reference), or one with an expression_torque of time,
// or of time and state. Returns what f returns. The rates of a scene whose torque reads the
// attitude are no problem of their own (to_coupled_problem): std::logic_error here.
template <scalar T, class F>
decltype(auto) with_problem(const scene& s, F&& f) {
  if (s.couples_attitude())
    throw std::logic_error("with_problem: the torque of scene " + s.name + " reads the attitude; use to_coupled_problem");
  switch (torque_kind_of(s)) {
    case torque_kind::of_time: return f(to_problem_with_law<T, false>(s));
    case torque_kind::of_state: return f(to_problem_with_law<T, true>(s));
    case torque_kind::constant: break;
  }
  return f(to_problem<T>(s));
}

// Calls f with the problem the double-precision comparison runs integrate: with_problem's, or
// for a torque of the attitude the rates' equations under a staged torque, which each stage of a
// run shows its q (model/staged_attitude_torque.hpp): such runs must carry q.
template <class F>
decltype(auto) with_run_problem(const scene& s, F&& f);

// The scene's initial attitude in T (precondition: s.has_attitude()), normalized in T: the
// decimals are 1 in norm only to 1e-9.
template <scalar T>
quaternion<T> attitude_of(const scene& s) {
  const auto& q = *s.attitude;
  return normalized(quaternion<T>{q[0].template to_scalar<T>(), q[1].template to_scalar<T>(),
                                  q[2].template to_scalar<T>(), q[3].template to_scalar<T>()});
}

// The body rates per unit of the integrator's time, in the scene's axes, from the integrator's
// state (precondition: s.is_physical()).
template <scalar T>
body_rates<T> body_rates_of(const scene& s) {
  return body_rates<T>::of(scaling_of<T>(s));
}

// The problem of the rates and the attitude of a scene whose torque reads q
// (s.couples_attitude(); model/coupled_problem.hpp): the same equations of the rates as
// with_problem's, in the same variables, with the formulas (or the constant M) and the gravity
// gradient in one torque of (t, y, q).
template <scalar T>
coupled_problem<T> to_coupled_problem(const scene& s) {
  if (!s.couples_attitude() || !s.has_attitude())
    throw std::logic_error("to_coupled_problem: the torque of scene " + s.name + " does not read the attitude");
  scene constant = s;
  constant.torque_law.reset();
  constant.torque.reset();
  const euler_problem<T> base = to_problem<T>(constant);
  coupled_problem<T> p;
  p.tau0 = base.tau0;
  p.form = base.form;
  p.a = base.a;
  p.rates = body_rates_of<T>(s);
  const quaternion<T> q = attitude_of<T>(s);
  p.initial = {base.Omega0[0], base.Omega0[1], base.Omega0[2], q.w, q.x, q.y, q.z};
  std::shared_ptr<const torque_law> law = s.torque_law;
  if (!law) {  // numbers, or no [torque] M: a law of constants
    auto constants = std::make_shared<torque_law>();
    constants->name = "M";
    constants->time_name = "t";
    for (int i = 0; i < 3; ++i) constants->base[i] = constant_expression(s.torque ? (*s.torque)[i].text : "0");
    law = std::move(constants);
  }
  std::optional<gravity_gradient<T>> gravity;
  if (s.gravity_gradient) gravity = gravity_gradient<T>{s.gravity_gradient->template to_scalar<T>(), to_vec3<T>(*s.inertia)};
  p.torque = attitude_torque<T>(std::move(law), torque_variables<T>::of(scaling_of<T>(s)), std::move(gravity));
  return p;
}

template <class F>
decltype(auto) with_run_problem(const scene& s, F&& f) {
  if (!s.couples_attitude()) return with_problem<double>(s, std::forward<F>(f));
  const coupled_problem<double> c = to_coupled_problem<double>(s);
  euler_problem<double, staged_attitude_torque<double>> p;
  p.Omega0 = coupled_problem<double>::rates_part(c.initial);
  p.tau0 = c.tau0;
  p.form = c.form;
  p.a = c.a;
  const std::array<double, 4> q = coupled_problem<double>::attitude_part(c.initial);
  p.torque = staged_attitude_torque<double>(c.torque, quaternion<double>{q[0], q[1], q[2], q[3]});
  return f(p);
}

// The end of the span in the integrator's time (physical scenes: tau_end = t_end dtau/dt, Eq. 4;
// t_end in the direct form and in the coefficient form).
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
  if (!s.samples && s.times.empty())
    throw input_error("[span] of scene " + s.name + ": give samples (a count) or times (a list)");
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

// The conversions of a scene into the problems of one scalar T, compiled once in the kernels
// (src/kernels/CMakeLists.txt, the cell scene_problems) for double, quad and MPFR, as the formula
// types are (model/expression_torque.hpp): EXTERN is `extern` to declare them, empty to define
// them. Most of the program's units convert a scene, each in up to three scalars, and would
// otherwise each compile every conversion they call. Declared extern for double here; for quad
// and MPFR in scene/wide_scene_problems.hpp.
#define EULERVOP_SCENE_PROBLEM_CELL(EXTERN, T)                                                                     \
  EXTERN template T eulervop::scene::decimal::to_scalar<T>() const;                                               \
  EXTERN template eulervop::physical_scaling<T> eulervop::scene::scaling_of<T>(const eulervop::scene::scene&);    \
  EXTERN template eulervop::vec3<T> eulervop::scene::Omega_of_elements<T>(const eulervop::scene::initial_elements&); \
  EXTERN template eulervop::euler_problem<T> eulervop::scene::to_problem<T>(const eulervop::scene::scene&);       \
  EXTERN template eulervop::vec3<T> eulervop::scene::initial_state_of<T>(const eulervop::scene::scene&);          \
  EXTERN template eulervop::euler_problem<T, eulervop::expression_torque<T, false>>                               \
  eulervop::scene::to_problem_with_law<T, false>(const eulervop::scene::scene&);                                   \
  EXTERN template eulervop::euler_problem<T, eulervop::expression_torque<T, true>>                                \
  eulervop::scene::to_problem_with_law<T, true>(const eulervop::scene::scene&);                                    \
  EXTERN template eulervop::quaternion<T> eulervop::scene::attitude_of<T>(const eulervop::scene::scene&);         \
  EXTERN template eulervop::body_rates<T> eulervop::scene::body_rates_of<T>(const eulervop::scene::scene&);       \
  EXTERN template eulervop::coupled_problem<T> eulervop::scene::to_coupled_problem<T>(const eulervop::scene::scene&); \
  EXTERN template T eulervop::scene::tau_end_of<T>(const eulervop::scene::scene&);                                \
  EXTERN template eulervop::scene::sample_times<T> eulervop::scene::sample_times_of<T>(const eulervop::scene::scene&);
#ifdef EULERVOP_COMPILED_KERNELS
EULERVOP_SCENE_PROBLEM_CELL(extern, double)
#endif
