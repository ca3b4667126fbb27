// A scene's problem for the general path of --certify (certify/certification_problem.hpp): its
// equations in the integrator's variables, the variables' map and its initial state, every
// number a ball that holds the exact value of the scene's decimals and constant formulas.
//
// The integrator's variables are those of the reference (scene_problem.hpp): Eq. 5 in tau and
// Omega for a normalized scene and a physical body with distinct moments (Eqs. 2-4, the
// principal axes the plain run uses), Eq. 1 in t and omega in the direct form, the coefficient
// form in its own t and y; and q, normalized exactly, for a body with an attitude. A constant
// torque enters as a law of constants, so one path takes every torque.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/certification_problem.hpp>
#include <eulervop/certify/detail/field_algebra.hpp>
#include <eulervop/scene/scene.hpp>
#include <eulervop/scene/scene_balls.hpp>
#include <eulervop/scene/scene_problem.hpp>

#include <arb.h>

#include <algorithm>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace eulervop::scene {

namespace detail {

// -1, 0 or 1 when the ball is exactly that number, else 2.
inline int unit_value(const ball& x) {
  for (int v : {-1, 0, 1})
    if (arb_equal_si(x.get(), v)) return v;
  return 2;
}

// The torque as formulas (a constant torque as a law of constants), or null for none.
inline std::shared_ptr<const torque_law> law_of(const scene& s) {
  if (s.torque_law) return s.torque_law;
  if (!s.torque) return nullptr;
  auto law = std::make_shared<torque_law>();
  law->name = std::string(s.torque_key());
  law->time_name = std::string(s.time_name());
  for (int i = 0; i < 3; ++i) law->base[static_cast<std::size_t>(i)] = constant_expression((*s.torque)[static_cast<std::size_t>(i)].text);
  return law;
}

// The reference's breakpoints in T (expression_torque.hpp, the same object the integrator uses).
template <scalar T>
std::vector<T> reference_breakpoints(const scene& s, const std::shared_ptr<const torque_law>& law) {
  if (!law || law->pieces.empty()) return {};
  const torque_variables<T> vars = s.is_physical() ? torque_variables<T>::of(scaling_of<T>(s)) : torque_variables<T>{};
  return expression_torque<T, true>(law, vars).breakpoints();
}

// The equations' coefficients a and the change of variables into p; the scene's exact scaling
// where it is a physical body in Eq. 5.
inline std::optional<physical_scaling<ball_value>> put_equations(certification_problem& p, const scene& s, bool direct) {
  const slong prec = p.prec;
  if (s.is_coefficient_form()) {
    for (int i = 0; i < 3; ++i) p.a[i] = ball_of_decimal((*s.coefficients)[i], prec, "[equations] a");
  } else if (direct) {
    std::array<ball, 3> I;
    for (int i = 0; i < 3; ++i) I[i] = ball_of_decimal((*s.inertia)[i], prec, "[body] inertia");
    for (int i = 0; i < 3; ++i) {
      arb_sub(p.a[i].get(), I[(i + 1) % 3].get(), I[(i + 2) % 3].get(), prec);
      arb_div(p.a[i].get(), p.a[i].get(), I[i].get(), prec);
      p.variables.identity = false;
      arb_inv(p.variables.divisor_inverse[i].get(), I[i].get(), prec);
    }
  } else {
    p.a = {ball(-1), ball(1), ball(-1)};
  }
  for (int i = 0; i < 3; ++i) p.unit_a[i] = unit_value(p.a[i]);
  std::optional<physical_scaling<ball_value>> scaling;
  if (s.is_physical() && !direct) {
    scaling.emplace(ball_scaling_of(s, prec));
    exact_variables& v = p.variables;
    v.identity = false;
    v.axes = scaling->axes();
    const ball& rate = scaling->tau_rate().get();
    arb_inv(v.rate_inverse.get(), rate.get(), prec);
    const ball_value I[3] = {scaling->moments().I1, scaling->moments().I2, scaling->moments().I3};
    for (int i = 0; i < 3; ++i) {
      v.state_scale[i] = scaling->sqrt_A()[i].get();
      // divisor = I_i sqrt(A_i) dtau/dt (physical_scaling.hpp, G_of_M).
      ball d = I[i].get();
      arb_mul(d.get(), d.get(), v.state_scale[i].get(), prec);
      arb_mul(d.get(), d.get(), rate.get(), prec);
      arb_inv(v.divisor_inverse[i].get(), d.get(), prec);
      // The body rates per unit of tau: sqrt(A_i) / (dtau/dt) (body_rates.hpp).
      p.rates.identity = false;
      p.rates.axes = v.axes;
      arb_mul(p.rates.scale[i].get(), v.state_scale[i].get(), v.rate_inverse.get(), prec);
    }
  }
  return scaling;
}

// The initial state into p (q normalized exactly), in the integrator's variables.
inline void put_initial(certification_problem& p, const scene& s,
                        const std::optional<physical_scaling<ball_value>>& scaling) {
  const slong prec = p.prec;
  p.initial.resize(p.dimension);
  const auto put3 = [&](const decimal3& d, const std::string& field) {
    for (int i = 0; i < 3; ++i) p.initial[i] = ball_of_decimal(d[i], prec, field);
  };
  if (scaling) {
    const vec3<ball_value> omega0 = ball_values_of(std::get<initial_rates>(s.initial).rates, prec, "[initial] omega");
    const vec3<ball_value> Omega0 = scaling->Omega_of_omega(omega0);
    for (int i = 0; i < 3; ++i) p.initial[i] = Omega0[i].get();
  } else if (const auto* r = std::get_if<initial_rates>(&s.initial)) {
    put3(r->rates, s.is_coefficient_form() ? "[initial] y" : s.is_physical() ? "[initial] omega" : "[initial] Omega");
  } else {
    const std::array<ball, 3> Omega0 = ball_Omega_of_elements(std::get<initial_elements>(s.initial), prec);
    for (int i = 0; i < 3; ++i) p.initial[i] = Omega0[i];
  }
  if (!s.has_attitude()) return;
  ball norm2;
  for (int r = 0; r < 4; ++r) {
    p.initial[3 + r] = ball_of_decimal((*s.attitude)[r], prec, "[initial] q");
    arb_addmul(norm2.get(), p.initial[3 + r].get(), p.initial[3 + r].get(), prec);
  }
  arb_rsqrt(norm2.get(), norm2.get(), prec);
  for (int r = 0; r < 4; ++r) arb_mul(p.initial[3 + r].get(), p.initial[3 + r].get(), norm2.get(), prec);
}

// The torque's formula sets (the base, then each piece's) and the pieces' windows into p; returns
// the pieces' exact bounds in the integrator's time, in order.
inline std::vector<ball> put_formula_sets(certification_problem& p) {
  const slong prec = p.prec;
  const auto compile = [&](const std::array<expression, 3>& terms) {
    std::array<eulervop::detail::ball_formula, 3> set;
    for (int i = 0; i < 3; ++i) set[i] = eulervop::detail::ball_formula(terms[i], prec);
    return set;
  };
  p.sets.push_back(compile(p.law->base));
  ball rate(1);
  if (!p.variables.identity) arb_inv(rate.get(), p.variables.rate_inverse.get(), prec);
  std::vector<ball> exact;
  for (const torque_piece& piece : p.law->pieces) {
    p.sets.push_back(compile(piece.terms));
    std::array<ball, 2> w;
    w[0] = eulervop::detail::ball_formula(piece.from, prec).constant_value(prec);
    w[1] = eulervop::detail::ball_formula(piece.to, prec).constant_value(prec);
    for (ball& x : w) {
      arb_mul(x.get(), x.get(), rate.get(), prec);
      exact.push_back(x);
    }
    p.windows.push_back(std::move(w));
  }
  return exact;
}

// Each breakpoint of the reference (`reference`, in T) stands for the exact bounds nearest to it.
template <scalar T>
void put_breakpoints(certification_problem& p, const std::vector<T>& reference, const std::vector<ball>& exact) {
  const slong prec = p.prec;
  for (const T& b : reference) {
    breakpoint_window w;
    set_exact(w.reference, b);
    w.hull = w.reference;
    p.breakpoints.push_back(std::move(w));
  }
  for (const ball& x : exact) {
    if (p.breakpoints.empty()) break;
    std::size_t nearest = 0;
    double best = -1;
    for (std::size_t k = 0; k < p.breakpoints.size(); ++k) {
      ball d;
      arb_sub(d.get(), x.get(), p.breakpoints[k].reference.get(), prec);
      const double m = magnitude_up(d);
      if (best < 0 || m < best) {
        best = m;
        nearest = k;
      }
    }
    breakpoint_window& w = p.breakpoints[nearest];
    arb_union(w.hull.get(), w.hull.get(), x.get(), prec);
    // Bounds that are the same number (a piece that ends where the next starts) count once.
    if (w.exact_count == 0 || !arb_equal(w.exact.get(), x.get())) ++w.exact_count;
    w.exact = x;
  }
}

}  // namespace detail

// The scene's problem at `prec` bits, for a reference computed in T.
// A number undefined on its enclosure is bad input naming its field.
template <scalar T>
certification_problem certification_problem_of(const scene& s, slong prec) {
  certification_problem p;
  p.prec = prec;
  p.dimension = s.has_attitude() ? 7 : 3;
  const std::optional<physical_scaling<ball_value>> scaling = detail::put_equations(p, s, uses_direct_form(s));
  detail::put_initial(p, s, scaling);
  if (s.gravity_gradient) {
    gravity_term g;
    g.mean_motion = ball_of_decimal(*s.gravity_gradient, prec, "[torque.gravity_gradient] mean_motion");
    for (int i = 0; i < 3; ++i) g.moments[i] = ball_of_decimal((*s.inertia)[i], prec, "[body] inertia");
    p.gravity = g;
  }
  // The torque, its pieces and its breakpoints.
  p.law = detail::law_of(s);
  if (!p.law) return p;
  const std::vector<ball> exact = detail::put_formula_sets(p);
  detail::put_breakpoints(p, detail::reference_breakpoints<T>(s, p.law), exact);
  return p;
}

// The conversion for a reference in T, declared extern (EXTERN = extern) where another unit
// instantiates it (EXTERN empty): the program's certificate module does so in its entry unit, off
// the general path's own, the program's slowest.
#define EULERVOP_CERTIFICATION_PROBLEM_CELL(EXTERN, T) \
  EXTERN template certification_problem certification_problem_of<T>(const scene&, slong);

}  // namespace eulervop::scene
