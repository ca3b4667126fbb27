// A torque of time, or of time and state, given by formulas (torque_law.hpp), as a torque type of
// euler_problem (torque.hpp): g(t, y) in the integrator's variables.
//
// The formulas are written in the scene's variables; the torque maps them:
//   - a normalized scene (tau, Omega, G) and the coefficient form (t, y, f) are integrated in
//     their own variables;
//   - a physical scene writes M(t, omega) in N m, s and rad/s in the body's axes. The integrator
//     runs in tau and Omega (Eqs. 2-4, physical_scaling.hpp), or in t and omega in the direct
//     form, so t = tau / (dtau/dt), omega = P^T (sqrt(A) Omega) and G = (P M) / (I sqrt(A)
//     dtau/dt), P the axis permutation (principal_axes.hpp).
//
// Pieces make the torque piecewise: each bound is a breakpoint, and the integrators end a segment
// or a step exactly there (docs/design.md, "Breakpoints"). Between two breakpoints one set of
// formulas applies. A caller that knows on which side of a breakpoint it works (a segment ending
// there evaluates the torque at its end) pins the interval; otherwise the torque is
// right-continuous: at a breakpoint the interval that starts there applies.
//
// A formula that is not finite where it is evaluated (log of a negative, a division by zero)
// throws numerical_failure naming the component, the formula and the time: no NaN is integrated.
#pragma once

#include <eulervop/core/error_free.hpp>
#include <eulervop/core/numerical_failure.hpp>
#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/model/expression.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/model/principal_axes.hpp>
#include <eulervop/model/torque_law.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace eulervop {

// The change of variables from the integrator's (t, y, g) to the scene's (time, state, torque):
// time = t / rate, state = P^T (state_scale y), g = (P torque) / torque_divisor, P = axes; for a
// physical body the same operations as physical_scaling's, so a constant formula gives exactly
// the G of a constant torque.
template <class T>
struct torque_variables {
  bool identity = true;  // normalized and coefficient-form scenes: no change at all
  axis_permutation axes;
  vec3<T> state_scale{T(1), T(1), T(1)};
  vec3<T> torque_divisor{T(1), T(1), T(1)};
  T rate = T(1);

  // The map of a physical body (Eqs. 2-4, or the direct form's G = M / I).
  static torque_variables of(const physical_scaling<T>& s) {
    torque_variables v;
    v.identity = false;
    v.axes = s.axes();
    v.rate = s.tau_rate();
    const T I[3] = {s.moments().I1, s.moments().I2, s.moments().I3};
    for (int i = 0; i < 3; ++i) {
      v.state_scale[i] = s.sqrt_A()[i];
      v.torque_divisor[i] = I[i] * s.sqrt_A()[i] * s.tau_rate();
    }
    return v;
  }

  template <class U>
  torque_variables<U> to() const {
    torque_variables<U> v;
    v.identity = identity;
    v.axes = axes;
    v.rate = static_cast<U>(rate);
    for (int i = 0; i < 3; ++i) {
      v.state_scale[i] = static_cast<U>(state_scale[i]);
      v.torque_divisor[i] = static_cast<U>(torque_divisor[i]);
    }
    return v;
  }
};

template <class T, bool OfState>
class expression_torque {
 public:
  static constexpr bool depends_on_time = true;
  static constexpr bool depends_on_state = OfState;

  expression_torque() = default;
  // Compiles the law in T (constants and piece bounds converted at the current precision).
  expression_torque(std::shared_ptr<const torque_law> law, const torque_variables<T>& vars)
      : law_(std::move(law)), vars_(vars) {
    sets_.push_back(compile(law_->base));
    for (const torque_piece& p : law_->pieces) sets_.push_back(compile(p.terms));
    build_intervals();
  }

  const std::shared_ptr<const torque_law>& law() const { return law_; }
  const torque_variables<T>& variables() const { return vars_; }

  // The breakpoints in the integrator's time, increasing: every piece's bounds.
  const std::vector<T>& breakpoints() const { return breaks_; }
  // The interval of t: 0 before the first breakpoint, i in [breakpoint i-1, breakpoint i).
  std::size_t interval_at(const T& t) const {
    return static_cast<std::size_t>(std::upper_bound(breaks_.begin(), breaks_.end(), t) - breaks_.begin());
  }
  // Evaluate in `interval` whatever the time (a segment or step that ends on its right bound);
  // unpin() returns to the interval of each time. The integrator's copy of the problem holds it.
  void pin(std::size_t interval) const { pinned_ = interval; }
  void unpin() const { pinned_.reset(); }

  using attitude_values = typename compiled_expression<T>::attitude_values;
  using partials = typename compiled_expression<T>::partials;

  vec3<T> value(const T& t, const vec3<T>& y) const {
    return integrator_torque(scene_torque(t, scene_time(t), scene_state(y), nullptr));
  }

  // The torque at a segment's node times t_j = (alpha + alpha_lo) + beta s_j (t: those times),
  // for a law of time alone, into out[j]: compiled_expression::values_at_nodes per component,
  // with `affine_sine` as there; the same checks and change of variables as value(). False (out
  // untouched) where the nodes do not all lie in one interval of the pieces.
  template <class AffineSine>
  bool values_at_nodes(const T& alpha, const T& alpha_lo, const T& beta, const std::vector<T>& t,
                       AffineSine&& affine_sine, std::vector<vec3<T>>& out) const
    requires(!OfState)
  {
    const compiled_set& set = set_at(t.front());
    if (&set != &set_at(t.back())) return false;
    const std::size_t n = t.size();
    node_times_.resize(n);
    for (std::size_t j = 0; j < n; ++j) node_times_[j] = scene_time(t[j]);
    // The scene's time, t / rate, with the quotient's rounding kept in a_lo (as values_at_nodes
    // keeps its own; quad only, where the sines take a_lo).
    const T a = vars_.identity ? alpha : T(alpha / vars_.rate), b = vars_.identity ? beta : T(beta / vars_.rate);
    T a_lo = alpha_lo;
    if (!vars_.identity) {
      T rest = 0;  // alpha - a rate, exactly
      if constexpr (std::is_same_v<T, quad>) {
        T hi, lo;
        two_product(a, vars_.rate, hi, lo);
        rest = (alpha - hi) - lo;
      }
      a_lo = (alpha_lo + rest) / vars_.rate;
    }
    std::array<std::vector<T>, 3> m;
    for (int i = 0; i < 3; ++i) {
      const term& c = set[i];
      if (c.constant) m[i].assign(n, c.value);
      else c.program->values_at_nodes(a, a_lo, b, node_times_, affine_sine, m[i]);
    }
    out.resize(n);
    for (std::size_t j = 0; j < n; ++j) {
      vec3<T> mj;
      for (int i = 0; i < 3; ++i) mj[i] = checked(set[i], m[i][j], i, node_times_[j], t[j]);
      out[j] = integrator_torque(mj);
    }
    return true;
  }

  // J[i][k] += d g_i / d y_k (the chain rule through the change of variables).
  void add_jacobian(const T& t, const vec3<T>& y, std::array<vec3<T>, 3>& J) const
    requires OfState
  {
    std::array<partials, 3> Js;
    scene_jacobian(t, scene_time(t), scene_state(y), nullptr, Js);
    add_mapped_jacobian(Js, J, 3);
  }

  // The torque in the scene's variables (N m in the listed axes for a body) at the integrator's
  // time t, whose scene time is ts, at the scene's state ys and, for a law that names it, the
  // attitude q (model/attitude_torque.hpp adds the gravity gradient to it).
  vec3<T> scene_torque(const T& t, const T& ts, const vec3<T>& ys, const attitude_values* q) const {
    const compiled_set& set = set_at(t);
    vec3<T> m;
    for (int i = 0; i < 3; ++i) {
      const term& c = set[i];
      m[i] = checked(c, c.constant ? c.value : q ? (*c.program)(ts, ys, *q) : (*c.program)(ts, ys), i, ts, t);
    }
    return m;
  }

  // Js[a] = the partials of M_a by the scene's state, then (q given) by q0..q3, in the scene's
  // variables.
  void scene_jacobian(const T& t, const T& ts, const vec3<T>& ys, const attitude_values* q,
                      std::array<partials, 3>& Js) const {
    const compiled_set& set = set_at(t);
    for (int a = 0; a < 3; ++a) {
      Js[a].fill(T(0));
      const expression* e = set[a].source;
      if (set[a].constant || !(e->uses_state() || e->uses_attitude())) continue;
      if (q) {
        checked(set[a], set[a].program->value_and_gradient(ts, ys, *q, Js[a]), a, ts, t);
      } else {
        vec3<T> d;
        checked(set[a], set[a].program->value_and_gradient(ts, ys, d), a, ts, t);
        for (int k = 0; k < 3; ++k) Js[a][k] = d[k];
      }
    }
  }

  // J[i][k] += the partials Js mapped to the integrator's variables, for the first `columns`
  // columns: the state's three (scaled and permuted as the state is), then q's, which every
  // variable set shares (the attitude is in the listed axes).
  template <class Row>
  void add_mapped_jacobian(const std::array<partials, 3>& Js, std::array<Row, 3>& J, std::size_t columns) const {
    for (int i = 0; i < 3; ++i) {
      const int a = vars_.identity ? i : vars_.axes.axis(i);
      for (std::size_t k = 0; k < columns; ++k) {
        const bool state = k < 3;
        const int b = !state || vars_.identity ? static_cast<int>(k) : vars_.axes.axis(static_cast<int>(k));
        T d = Js[a][b];
        if (!vars_.identity) {
          if (state) d *= vars_.state_scale[k];
          d /= vars_.torque_divisor[i];
          if (vars_.axes.sign(i) * (state ? vars_.axes.sign(static_cast<int>(k)) : 1) < 0) d = -d;
        }
        J[i][k] += d;
      }
    }
  }

  T scene_time(const T& t) const { return vars_.identity ? t : T(t / vars_.rate); }
  vec3<T> scene_state(const vec3<T>& y) const {
    if (vars_.identity) return y;
    const vec3<T> s = {y[0] * vars_.state_scale[0], y[1] * vars_.state_scale[1], y[2] * vars_.state_scale[2]};
    return vars_.axes.to_user(s);
  }
  vec3<T> integrator_torque(const vec3<T>& m) const {
    if (vars_.identity) return m;
    vec3<T> g = vars_.axes.to_principal(m);
    for (int i = 0; i < 3; ++i) g[i] /= vars_.torque_divisor[i];
    return g;
  }

 private:
  struct term {
    bool constant = false;
    T value{};                                    // a constant formula, evaluated once
    std::optional<compiled_expression<T>> program;  // otherwise
    const expression* source = nullptr;
  };
  using compiled_set = std::array<term, 3>;

  static compiled_set compile(const std::array<expression, 3>& formulas) {
    compiled_set set;
    for (int i = 0; i < 3; ++i) {
      set[i].source = &formulas[i];
      const compiled_expression<T> program(formulas[i]);
      if (formulas[i].is_constant()) {
        set[i].constant = true;
        set[i].value = program(T(0), vec3<T>{T(0), T(0), T(0)});
      } else {
        set[i].program.emplace(program);
      }
    }
    return set;
  }

  // Breakpoints from the pieces' bounds (evaluated in T), and the formulas of each interval.
  void build_intervals() {
    std::vector<std::pair<T, T>> windows;  // in the integrator's time
    for (const torque_piece& p : law_->pieces)
      windows.emplace_back(integrator_time(bound(p.from)), integrator_time(bound(p.to)));
    for (const auto& [a, b] : windows) {
      breaks_.push_back(a);
      breaks_.push_back(b);
    }
    std::sort(breaks_.begin(), breaks_.end());
    breaks_.erase(std::unique(breaks_.begin(), breaks_.end()), breaks_.end());
    set_of_interval_.assign(breaks_.size() + 1, 0);
    for (std::size_t i = 1; i <= breaks_.size(); ++i)
      for (std::size_t p = 0; p < windows.size(); ++p)
        if (!(breaks_[i - 1] < windows[p].first) && breaks_[i - 1] < windows[p].second) set_of_interval_[i] = p + 1;
  }

  static T bound(const expression& e) { return compiled_expression<T>(e)(T(0), vec3<T>{T(0), T(0), T(0)}); }

  const compiled_set& set_at(const T& t) const {
    if (sets_.size() == 1) return sets_[0];
    return sets_[set_of_interval_[pinned_ ? *pinned_ : interval_at(t)]];
  }

  T integrator_time(const T& ts) const { return vars_.identity ? ts : T(ts * vars_.rate); }

  mutable std::vector<T> node_times_;  // values_at_nodes: the scene's times of the nodes

  // The value of component i, or numerical_failure when it is not finite. The message names the
  // formula as the scene wrote it, the scene's time to 15 digits (all a double states reliably:
  // 49.999999999999993 would read as outside a window that starts at 50) and the piece in force.
  T checked(const term& c, T v, int i, const T& ts, const T& t) const {
    using std::isfinite;
    if (isfinite(v)) [[likely]]
      return v;
    char at[96];
    std::snprintf(at, sizeof at, " at %s = %.15g", law_->time_name.c_str(), static_cast<double>(ts));
    const std::string value = v != v ? "nan" : (v > 0 ? "inf" : "-inf");
    throw numerical_failure({.kind = outcome_kind::torque_non_finite, .tau = static_cast<double>(t)},
                            law_->name + std::to_string(i + 1) + " = " + c.source->text + " is " + value + at +
                                in_force(t));
  }

  // ", in the piece [from, to)" or ", outside every piece": which formulas applied at t.
  std::string in_force(const T& t) const {
    if (law_->pieces.empty()) return "";
    const std::size_t set = set_of_interval_[pinned_ ? *pinned_ : interval_at(t)];
    if (set == 0) return ", outside every piece";
    const torque_piece& p = law_->pieces[set - 1];
    return ", in the piece [" + p.from.text + ", " + p.to.text + ")";
  }

  std::shared_ptr<const torque_law> law_;
  torque_variables<T> vars_;
  std::vector<compiled_set> sets_;              // 0: the base formulas; 1 + p: piece p's
  std::vector<T> breaks_;
  std::vector<std::size_t> set_of_interval_;    // the set of each interval
  mutable std::optional<std::size_t> pinned_;
};

// The two kinds, as the program names them: of time alone, and of time and state.
template <class T>
using time_torque = expression_torque<T, false>;
template <class T>
using state_torque = expression_torque<T, true>;

// The same torque in U (the reference's double passes): the formulas compiled again from their
// decimals, the change of variables rounded to U.
template <class U, class T, bool OfState>
expression_torque<U, OfState> convert_torque(const expression_torque<T, OfState>& g) {
  expression_torque<U, OfState> out(g.law(), g.variables().template to<U>());
  return out;
}

// The formula types of one scalar T, compiled once in the kernels (kernels/cells.hpp) for double,
// quad and MPFR: EXTERN is `extern` to declare them, empty to define them. Every unit that builds
// or evaluates a formula torque would otherwise compile its own copy of each member. Declared
// extern for double here; for quad and MPFR in model/wide_formula_cells.hpp.
#define EULERVOP_FORMULA_CELL(EXTERN, T)       \
  EXTERN template class compiled_expression<T>; \
  EXTERN template class expression_torque<T, false>; \
  EXTERN template class expression_torque<T, true>;
#ifdef EULERVOP_COMPILED_KERNELS
EULERVOP_FORMULA_CELL(extern, double)
#endif

}  // namespace eulervop
