// The number types a problem's field is evaluated in by the general path of --certify
// (certification_problem.hpp), each with the derivatives it needs, and the evaluation of a formula
// (model/expression.hpp) in them.
//
//   - series_algebra: Chebyshev models of a segment (chebyshev_model.hpp) with their first
//     partial derivatives by the state (forward mode): the field along P and its Jacobian J.
//   - box_algebra (box_algebra.hpp): balls with first and second partial derivatives: the field
//     and its Hessian over a box of states, for the quadratic remainder c(R) and the bound of |F|
//     over the tube.
//
// A formula's constant subexpressions are folded into one ball each, evaluated by Arb's
// functions. On a variable, the ring operations are the algebras' own; sin, cos, exp, log, sqrt,
// tanh, atan, sinh, cosh, divisions and negative powers are elementary functions of it
// (chebyshev_composition.hpp: a model of f(u) with a proven remainder; on balls, Arb's functions
// with their derivatives). A
// function undefined where its argument may be (the log of a ball that reaches 0) throws
// undefined_formula: it is never a bound.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/box_algebra.hpp>
#include <eulervop/certify/detail/chebyshev_composition.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/certify/detail/jet_product.hpp>
#include <eulervop/model/expression.hpp>

#include <arb.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace eulervop {

// A function undefined on the ball of its argument (log or sqrt of a ball reaching 0 or below,
// a division by a ball that holds 0).
struct undefined_formula : std::domain_error {
  using std::domain_error::domain_error;
};

namespace detail {

// A segment's Chebyshev model and its partial derivatives by the state (an empty model where a
// partial is zero). `grid`, where set, holds f on the grid of the algebra's value products; the
// copies of a jet share it, so that a model that is a factor of several products (a state
// component, a body rate) is moved to its grid once. Every change of f drops it.
struct series_jet {
  chebyshev_model f;
  std::vector<chebyshev_model> d;
  mutable std::shared_ptr<grid_cache> grid;
};

class series_algebra {
 public:
  using value = series_jet;
  series_algebra(slong prec, std::size_t variables) : prec_(prec), n_(variables) {}

  slong prec() const { return prec_; }
  value constant(const ball& c) const {
    value v;
    v.f.set_constant(c);
    v.d.resize(n_);
    return v;
  }
  // Variable k (a state component) with the model `f`: its partial by itself is 1.
  value variable(chebyshev_model f, std::size_t k) const {
    value v;
    v.f = std::move(f);
    v.d.resize(n_);
    v.d[k].set_constant(ball(1));
    v.grid = std::make_shared<grid_cache>();
    return v;
  }
  // The same into v, whose models keep their storage (a segment's check reuses its jets).
  void set_variable(value& v, const chebyshev_model& f, std::size_t k) const {
    v.f = f;
    v.d.resize(n_);
    for (chebyshev_model& d : v.d) d.set_zero();
    v.d[k].set_constant(ball(1));
    if (v.grid && v.grid.use_count() == 1)  // no copy of the last segment's jet holds it
      v.grid->ready = v.grid->rounded_ready = false;
    else
      v.grid = std::make_shared<grid_cache>();
  }
  // A model with no partials (the time).
  value independent(chebyshev_model f) const {
    value v;
    v.f = std::move(f);
    v.d.resize(n_);
    return v;
  }
  void add(value& a, const value& b) const {
    a.grid.reset();
    add_to(a.f, b.f, prec_);
    for (std::size_t k = 0; k < n_; ++k)
      if (!b.d[k].is_zero()) add_to(a.d[k], b.d[k], jacobian_prec);
  }
  void sub(value& a, const value& b) const {
    a.grid.reset();
    subtract_from(a.f, b.f, prec_);
    for (std::size_t k = 0; k < n_; ++k)
      if (!b.d[k].is_zero()) subtract_from(a.d[k], b.d[k], jacobian_prec);
  }
  void neg(value& a) const {
    a.grid.reset();
    negate(a.f);
    for (chebyshev_model& d : a.d) negate(d);
  }
  void scale(value& a, const ball& x) const {
    a.grid.reset();
    eulervop::detail::scale(a.f, x, prec_);
    for (chebyshev_model& d : a.d) eulervop::detail::scale(d, x, jacobian_prec);
  }
  // The products' grids lie 32 bits below the working precision (which is the reference's plus
  // 64): a factor's move to its grid, about 2^-(bits + 32) of it, then stays three orders below
  // the residual it enters, and the products cost a fifth less (measured: the radii of the shipped
  // scenes did not move in three digits; 48 bits below, they grew up to sixtyfold).
  static constexpr slong product_guard = 32;
  // The partials (the Jacobian) need far fewer digits: the linear flow cuts them at 2^-36 of their
  // size (ball_linear_flow.hpp) and the bounds take their ranges. They are computed at 128 bits,
  // where Arb's numbers need no allocation, their products on grids 64 bits below their largest
  // coefficient.
  static constexpr slong jacobian_prec = 128, jacobian_grid_bits = 64;
  // f'(u) as a model, at the Jacobian's precision.
  static void derivative(chebyshev_model& out, elementary f, const chebyshev_model& u) {
    constexpr slong bits = jacobian_grid_bits;
    chebyshev_model t;
    switch (f) {
      case elementary::sin: compose(out, elementary::cos, u, jacobian_prec, bits); break;
      case elementary::cos:
        compose(out, elementary::sin, u, jacobian_prec, bits);
        negate(out);
        break;
      case elementary::exp: compose(out, elementary::exp, u, jacobian_prec, bits); break;
      case elementary::log: compose(out, elementary::inverse, u, jacobian_prec, bits); break;
      case elementary::sqrt: {  // 1 / (2 sqrt u)
        compose(t, elementary::sqrt, u, jacobian_prec, bits);
        compose(out, elementary::inverse, t, jacobian_prec, bits);
        ball half(1);
        arb_mul_2exp_si(half.get(), half.get(), -1);
        eulervop::detail::scale(out, half, jacobian_prec);
        break;
      }
      case elementary::inverse:  // -1 / u^2
        compose(t, elementary::inverse, u, jacobian_prec, bits);
        multiply(out, t, t, bits);
        negate(out);
        break;
      case elementary::tanh: {  // 1 - tanh(u)^2: one composition; the partials need their error
                                // small against 1, not against sech^2
        compose(t, elementary::tanh, u, jacobian_prec, bits);
        multiply(out, t, t, bits);
        negate(out);
        chebyshev_model one;
        one.set_constant(ball(1));
        add_to(out, one, jacobian_prec);
        break;
      }
      case elementary::atan: {  // 1 / (1 + u^2) = cos(atan u)^2: cos takes any model, while the
                                // range bound of a model of 1 + u^2 (c_0 - sum |c_k|) may reach 0
        chebyshev_model c;
        compose(t, elementary::atan, u, jacobian_prec, bits);
        compose(c, elementary::cos, t, jacobian_prec, bits);
        multiply(out, c, c, bits);
        break;
      }
      case elementary::sinh: compose(out, elementary::cosh, u, jacobian_prec, bits); break;
      case elementary::cosh: compose(out, elementary::sinh, u, jacobian_prec, bits); break;
    }
  }
  // a = f(a): f(a)' = f'(a) a', f' at the Jacobian's precision. std::domain_error where a may
  // leave f's domain.
  void function(elementary f, value& a) const {
    chebyshev_model g;
    compose(g, f, a.f, prec_, prec_ - product_guard);
    bool partials = false;
    for (const chebyshev_model& d : a.d) partials = partials || !d.is_zero();
    if (partials) {
      chebyshev_model df, t;
      derivative(df, f, a.f);
      partial_factor on_grid_df;  // f'(a) moved to its grid once for all the partials
      for (chebyshev_model& d : a.d) {
        if (d.is_zero()) continue;
        partial_product(t, d, df, nullptr, on_grid_df, true, jacobian_grid_bits);  // multiply(t, df, d)
        d.swap(t);
      }
    }
    a.f.swap(g);
    a.grid.reset();
  }
  // a = sin(a)^2 (cos(a)^2 where `cosine`) as (1 -+ cos(2 a)) / 2: one function of a model, in
  // closed form where a is linear (trig_of_linear.hpp), instead of a function and then a product
  // of two long models. (SciML's forcing 0.25 sin(t)^2: the square had taken two fifths of the
  // forcing's time.)
  static constexpr bool squares_trig_by_double_angle = true;
  void squared_trig(bool cosine, value& a) const {
    const ball two(2);
    ball half(cosine ? 1 : -1);
    arb_mul_2exp_si(half.get(), half.get(), -1);
    scale(a, two);
    function(elementary::cos, a);
    scale(a, half);
    arb_abs(half.get(), half.get());
    add(a, constant(half));
  }
  // a = 1 / a.
  void invert(value& a) const { function(elementary::inverse, a); }
  // a = a b: (a b)' = a' b + a b', each product as multiply() makes it (jet_product.hpp: a
  // factor moved to its grid or rounded once, not once per product).
  void mul(value& a, const value& b) const {
    // Scratch kept per thread: the product lands in t and is swapped into a, so a's old models
    // (and their limbs) serve the next product instead of going back to malloc.
    thread_local value t;
    product(t, a, b);
    a.f.swap(t.f);
    a.d.swap(t.d);
    a.grid.reset();
  }
  // a = a a, with no copy of a: product() only reads its factors (a's grid is made once, for both).
  void square(value& a) const { mul(a, a); }
  // out = a b (out distinct from a and b; its models keep their storage), as mul() would make it
  // of a copy of a: a product needs no copy of its first factor.
  void product(value& out, const value& a, const value& b) const {
    thread_local chebyshev_model u;
    thread_local partial_factor fa, fb;
    fa.ready = fb.ready = false;
    if (!b.grid) b.grid = std::make_shared<grid_cache>();
    out.d.resize(n_);
    for (std::size_t k = 0; k < n_; ++k) {
      const bool da = !a.d[k].is_zero(), db = !b.d[k].is_zero();
      chebyshev_model& t = out.d[k];
      if (!da && !db) {
        t.set_zero();
        continue;
      }
      if (da) partial_product(t, a.d[k], b.f, b.grid.get(), fb, false, jacobian_grid_bits);
      if (db) {
        const bool scaled = partial_product(da ? u : t, b.d[k], a.f, a.grid.get(), fa, true, jacobian_grid_bits);
        if (da)
          add_to(t, u, jacobian_prec);
        else if (!scaled || jacobian_grid_bits + 64 > jacobian_prec)
          round_coefficients(t, jacobian_prec);  // the balls of 0 + u at jacobian_prec
      }
    }
    const slong bits = prec_ - product_guard;
    if (takes_grid(a.f) && takes_grid(b.f)) {
      thread_local grid_factor scratch;
      const grid_factor* ga = &scratch;
      if (a.grid) ga = &on_grid(*a.grid, a.f, bits); else scratch.set(a.f, bits);
      multiply_grids(out.f, *ga, on_grid(*b.grid, b.f, bits));
    } else {
      multiply(out.f, a.f, b.f, bits);
    }
    out.grid.reset();
  }

 private:
  slong prec_;
  std::size_t n_;
};

// The variables a formula reads, in an algebra: the scene's time, its state (three) and, for a
// body with an attitude, q0..q3.
template <class Algebra>
struct formula_variables {
  const typename Algebra::value* time = nullptr;
  std::array<const typename Algebra::value*, 3> state{};
  std::array<const typename Algebra::value*, 4> attitude{};
};

// A formula compiled for the general path: its program, each constant enclosed at `prec`.
class ball_formula {
 public:
  ball_formula() = default;
  ball_formula(const expression& e, slong prec) : source_(&e) {
    constants_.reserve(e.constants.size());
    for (const std::string& c : e.constants) constants_.push_back(decimal_ball(c, prec));
    arb_const_pi(pi_.get(), prec);
  }

  const expression& source() const { return *source_; }
  bool is_constant() const { return source_->is_constant(); }

  // The formula's value in the algebra (throws not_polynomial, undefined_formula).
  template <class Algebra>
  typename Algebra::value operator()(const Algebra& alg, const formula_variables<Algebra>& vars) const;
  // The value of a constant formula.
  ball constant_value(slong prec) const;

 private:
  // A stack entry: a folded constant (c) or a value in the algebra (v).
  template <class Value>
  struct slot {
    bool constant = true;
    ball c;
    Value v{};
  };
  template <class Algebra>
  using stack_of = std::vector<slot<typename Algebra::value>>;

  undefined_formula undefined(const char* why) const { return undefined_formula("`" + source_->text + "`: " + why); }
  void apply_function(expression_op op, ball& x, slong prec) const;
  static void power(ball& x, std::int32_t n, slong prec);
  template <class Apply>
  void defined(Apply&& apply) const;
  template <class Algebra>
  static typename Algebra::value& as_value(const Algebra& alg, slot<typename Algebra::value>& s);
  template <class Algebra>
  const typename Algebra::value& variable(const formula_variables<Algebra>& vars, std::int32_t arg) const;
  void fold(expression_op op, ball& a, const ball& b, slong prec) const;
  template <class Algebra>
  void binary(const Algebra& alg, expression_op op, stack_of<Algebra>& stack) const;
  template <class Algebra>
  void power_step(const Algebra& alg, std::int32_t n, slot<typename Algebra::value>& a) const;
  template <class Algebra>
  void step(const Algebra& alg, const formula_variables<Algebra>& vars, const expression_step& s,
            stack_of<Algebra>& stack) const;

  const expression* source_ = nullptr;
  std::vector<ball> constants_;
  ball pi_;
};

// The elementary function of a function step.
inline elementary elementary_of(expression_op op) {
  switch (op) {
    case expression_op::sin: return elementary::sin;
    case expression_op::cos: return elementary::cos;
    case expression_op::exp: return elementary::exp;
    case expression_op::log: return elementary::log;
    case expression_op::sqrt: return elementary::sqrt;
    case expression_op::tanh: return elementary::tanh;
    case expression_op::atan: return elementary::atan;
    case expression_op::sinh: return elementary::sinh;
    case expression_op::cosh: return elementary::cosh;
    default: throw std::logic_error("ball_formula: not a function step");
  }
}

inline void ball_formula::power(ball& x, std::int32_t n, slong prec) {
  if (n >= 0) {
    arb_pow_ui(x.get(), x.get(), static_cast<ulong>(n), prec);
  } else {
    arb_pow_ui(x.get(), x.get(), static_cast<ulong>(-static_cast<long>(n)), prec);
    arb_inv(x.get(), x.get(), prec);
  }
}

inline void ball_formula::apply_function(expression_op op, ball& x, slong prec) const {
  switch (op) {
    case expression_op::sin: arb_sin(x.get(), x.get(), prec); break;
    case expression_op::cos: arb_cos(x.get(), x.get(), prec); break;
    case expression_op::exp: arb_exp(x.get(), x.get(), prec); break;
    case expression_op::tanh: arb_tanh(x.get(), x.get(), prec); break;
    case expression_op::atan: arb_atan(x.get(), x.get(), prec); break;
    case expression_op::sinh: arb_sinh(x.get(), x.get(), prec); break;
    case expression_op::cosh: arb_cosh(x.get(), x.get(), prec); break;
    case expression_op::log:
      if (!arb_is_positive(x.get())) throw undefined("the log of a number that is not certainly positive");
      arb_log(x.get(), x.get(), prec);
      break;
    default:
      if (!arb_is_nonnegative(x.get())) throw undefined("the square root of a number that is not certainly >= 0");
      arb_sqrt(x.get(), x.get(), prec);
      break;
  }
  if (!arb_is_finite(x.get())) throw undefined("a value that is not finite");
}

// Runs apply(): a std::domain_error from it (a function of a variable undefined where the variable
// may be) becomes an undefined_formula that names the formula and the cause.
template <class Apply>
void ball_formula::defined(Apply&& apply) const {
  try {
    apply();
  } catch (const undefined_formula&) {
    throw;
  } catch (const std::domain_error& e) {
    throw undefined_formula("`" + source_->text + "`: " + e.what());
  }
}

// The entry as a value in the algebra (a constant becomes one there).
template <class Algebra>
typename Algebra::value& ball_formula::as_value(const Algebra& alg, slot<typename Algebra::value>& s) {
  if (s.constant) {
    s.v = alg.constant(s.c);
    s.constant = false;
  }
  return s.v;
}

// The variable of a variable step: the time, a state component or an attitude component.
template <class Algebra>
const typename Algebra::value& ball_formula::variable(const formula_variables<Algebra>& vars, std::int32_t arg) const {
  const typename Algebra::value* v =
      arg == expression::time_slot    ? vars.time
      : arg <= expression::state_slots ? vars.state[static_cast<std::size_t>(arg - 1)]
                                       : vars.attitude[static_cast<std::size_t>(arg - expression::attitude_slot)];
  if (!v) throw std::logic_error("ball_formula: `" + source_->text + "` names a variable that is not given");
  return *v;
}

// a = a op b of two constants (op one of + - * /).
inline void ball_formula::fold(expression_op op, ball& a, const ball& b, slong prec) const {
  switch (op) {
    case expression_op::add: arb_add(a.get(), a.get(), b.get(), prec); break;
    case expression_op::sub: arb_sub(a.get(), a.get(), b.get(), prec); break;
    case expression_op::mul: arb_mul(a.get(), a.get(), b.get(), prec); break;
    default:
      if (arb_contains_zero(b.get())) throw undefined("a division by a number that may be 0");
      arb_div(a.get(), a.get(), b.get(), prec);
      break;
  }
}

// The two top entries a, b replaced by a op b (op one of + - * /): constants fold; a constant
// factor or divisor scales; a divisor that is a value is inverted in the algebra.
template <class Algebra>
void ball_formula::binary(const Algebra& alg, expression_op op, stack_of<Algebra>& stack) const {
  slot<typename Algebra::value> b = std::move(stack.back());
  stack.pop_back();
  slot<typename Algebra::value>& a = stack.back();
  if (a.constant && b.constant) {
    fold(op, a.c, b.c, alg.prec());
  } else if (op == expression_op::div && !b.constant) {
    defined([&] { alg.invert(b.v); });
    alg.mul(as_value(alg, a), b.v);
  } else if (op == expression_op::div) {
    if (arb_contains_zero(b.c.get())) throw undefined("a division by a number that may be 0");
    arb_inv(b.c.get(), b.c.get(), alg.prec());
    alg.scale(as_value(alg, a), b.c);
  } else if (op == expression_op::mul && b.constant) {
    alg.scale(a.v, b.c);
  } else if (op == expression_op::mul && a.constant) {
    alg.scale(b.v, a.c);
    a.v = std::move(b.v);
    a.constant = false;
  } else if (op == expression_op::mul) {
    alg.mul(a.v, b.v);
  } else if (op == expression_op::add) {
    alg.add(as_value(alg, a), as_value(alg, b));
  } else {
    alg.sub(as_value(alg, a), as_value(alg, b));
  }
}

// a = a^n: of a constant in balls, of a value as n - 1 products (after 1/a for n < 0).
template <class Algebra>
void ball_formula::power_step(const Algebra& alg, std::int32_t n, slot<typename Algebra::value>& a) const {
  if (a.constant) {
    if (n < 0 && arb_contains_zero(a.c.get())) throw undefined("a negative power of a number that may be 0");
    power(a.c, n, alg.prec());
    return;
  }
  if (n == 0) {
    a.constant = true;
    a.c = ball(1);
    return;
  }
  if (n < 0) defined([&] { alg.invert(a.v); });
  if (n == 2 || n == -2) {
    alg.square(a.v);
    return;
  }
  const typename Algebra::value base = a.v;
  for (std::int32_t k = 1; k < (n < 0 ? -n : n); ++k) alg.mul(a.v, base);
}

// One step of the formula's program on the stack.
template <class Algebra>
void ball_formula::step(const Algebra& alg, const formula_variables<Algebra>& vars, const expression_step& s,
                        stack_of<Algebra>& stack) const {
  using value = typename Algebra::value;
  switch (s.op) {
    case expression_op::constant:
      stack.push_back({true, constants_[static_cast<std::size_t>(s.arg)], value{}});
      break;
    case expression_op::pi: stack.push_back({true, pi_, value{}}); break;
    case expression_op::variable: stack.push_back({false, ball(), variable(vars, s.arg)}); break;
    case expression_op::add:
    case expression_op::sub:
    case expression_op::mul:
    case expression_op::div: binary(alg, s.op, stack); break;
    case expression_op::neg:
      if (stack.back().constant)
        arb_neg(stack.back().c.get(), stack.back().c.get());
      else
        alg.neg(stack.back().v);
      break;
    case expression_op::pow: power_step(alg, s.arg, stack.back()); break;
    default:  // a function
      if (stack.back().constant)
        apply_function(s.op, stack.back().c, alg.prec());
      else
        defined([&] { alg.function(elementary_of(s.op), stack.back().v); });
      break;
  }
}

template <class Algebra>
typename Algebra::value ball_formula::operator()(const Algebra& alg, const formula_variables<Algebra>& vars) const {
  stack_of<Algebra> stack;
  stack.reserve(source_->stack_depth);
  const std::vector<expression_step>& code = source_->code;
  for (std::size_t i = 0; i < code.size(); ++i) {
    if constexpr (requires { Algebra::squares_trig_by_double_angle; }) {
      // sin(u)^2 or cos(u)^2 of a value: the algebra's own square of it, in one step.
      const expression_op op = code[i].op;
      if ((op == expression_op::sin || op == expression_op::cos) && i + 1 < code.size() &&
          code[i + 1].op == expression_op::pow && code[i + 1].arg == 2 && !stack.back().constant) {
        defined([&] { alg.squared_trig(op == expression_op::cos, stack.back().v); });
        ++i;
        continue;
      }
    }
    step(alg, vars, code[i], stack);
  }
  return std::move(as_value(alg, stack.back()));
}

inline ball ball_formula::constant_value(slong prec) const {
  box_algebra alg(prec, 0);
  return (*this)(alg, formula_variables<box_algebra>{}).f;
}

}  // namespace detail
}  // namespace eulervop
