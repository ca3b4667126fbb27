// An arithmetic expression of the time and the state, such as a torque component "0.25*sin(t)^2"
// or "-0.1*omega1", compiled for one number type T from its program, which is independent of the
// number type (model/expression_program.hpp).
//
// The core parses no text (docs/design.md section 5.3): the scene library turns a string into an
// `expression` (scene/expression_parser.hpp); this header only evaluates it. The program is
// postfix (reverse Polish) code over a stack, so evaluating is one loop over the steps with no
// recursion and no allocation per step. Numbers are kept as their exact decimal texts and
// converted once, in T, when the expression is compiled: "0.1" is 0.1 correctly rounded to every
// digit of a quad or MPFR run, not the double nearest 0.1 (the same rule as the scene's numbers,
// scene/decimal.hpp).
#pragma once

#include <eulervop/core/error_free.hpp>
#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/model/expression_program.hpp>

#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace eulervop {

namespace detail {

// x = -x, in place (the negation of a Boost number without a temporary).
template <scalar T>
void negate_in_place(T& x) {
  if constexpr (std::is_same_v<T, double>)
    x = -x;
  else
    x.backend().negate();
}

}  // namespace detail

// An expression compiled for the number type T (double, quad or mpfr_real).
//
// Constants and pi are converted once, at construction, at T's precision then current (for
// mpfr_real: the thread's default precision; construct and evaluate under the same
// mpfr_precision_scope). Evaluation uses a stack allocated at construction (mutable members), so
// it allocates nothing per step beyond what the elementary functions do internally and the value
// returned; it also means one object must not be evaluated by two threads at once (copy it per
// thread). Evaluation never throws: a non-finite result (log of a negative number, division by
// zero) is returned as it is, and the caller checks it.
template <scalar T>
class compiled_expression {
 public:
  explicit compiled_expression(expression e) : source_(std::move(e)) {
    const std::size_t depth = detail::checked_stack_depth(source_);
    constants_.reserve(source_.constants.size());
    for (const std::string& c : source_.constants) {
      auto v = eulervop::from_text<T>(c);
      if (!v) throw std::invalid_argument("expression constant does not convert: " + c);
      constants_.push_back(std::move(*v));
    }
    pi_ = pi_in<T>();
    // Every slot is created now, at the current precision, and only assigned to afterwards.
    values_.assign(depth, T(0));
    partials_.assign(depth, partials{T(0), T(0), T(0), T(0), T(0), T(0), T(0)});
    s1_ = T(0);
    s2_ = T(0);
    s3_ = T(0);
  }

  const expression& source() const { return source_; }

  // The attitude's four components, for the slots q0..q3.
  using attitude_values = std::array<T, 4>;
  // The partials of a value: by y1..y3, then by q0..q3 (only the first three without q).
  using partials = std::array<T, 7>;

  // The value at time t and state y. An expression that names q needs the three-argument form.
  T operator()(const T& t, const vec3<T>& y) const { return evaluate(t, y, nullptr); }
  // The value at time t, state y and attitude q.
  T operator()(const T& t, const vec3<T>& y, const attitude_values& q) const { return evaluate(t, y, &q); }

  // The values at a segment's node times t_j = (alpha + alpha_lo) + beta s_j (t: those times as
  // the integrator rounded them; alpha_lo: what alpha's rounding left, so that the sum is the
  // segment's exact midpoint), of an expression of time alone, into out[j]: node by node the
  // operations of operator(), except that a sine or cosine of an argument affine in s (t and
  // constants joined by +, -, negation, and products or quotients by constants) is handed whole to
  // `affine_sine(a, a_lo, b, cosine, values)`, which either fills values[j] with
  // sin(a + a_lo + b s_j) (or the cosine) and returns true, or returns false to have it evaluated
  // node by node. A reference integrator's torque of time thus costs one sine per segment, not one
  // per node. a_lo follows the sums (TwoSum) and, in quad, the products and quotients by constants
  // (Dekker's product) exactly to first order: the roundings of the midpoint and of the argument's
  // operations are common to all of a segment's nodes, and left out they would bias the segment's
  // torque coherently by up to half an ulp of the argument.
  template <class AffineSine>
  void values_at_nodes(const T& alpha, const T& alpha_lo, const T& beta, const std::vector<T>& t,
                       AffineSine&& affine_sine, std::vector<T>& out) const {
    const std::size_t n = t.size();
    if (node_stack_.size() < values_.size()) node_stack_.resize(values_.size());
    if (affine_.size() < values_.size()) affine_.resize(values_.size());
    std::size_t sp = 0;
    for (const expression_step& s : source_.code) {
      switch (s.op) {
        case expression_op::constant:
        case expression_op::pi: {
          const T& c = s.op == expression_op::pi ? pi_ : constants_[static_cast<std::size_t>(s.arg)];
          node_stack_[sp].assign(n, c);
          affine_[sp++] = {true, c, T(0), T(0)};
          break;
        }
        case expression_op::variable:
          if (s.arg != expression::time_slot) throw std::logic_error("values_at_nodes: the expression reads the state");
          node_stack_[sp] = t;
          affine_[sp++] = {true, alpha, alpha_lo, beta};
          break;
        case expression_op::add:
        case expression_op::sub:
        case expression_op::mul:
        case expression_op::div:
          --sp;
          binary_at_nodes(s.op, sp, n);
          break;
        default: function_at_nodes(s, sp - 1, affine_sine); break;
      }
    }
    out = node_stack_[0];
  }

  // The value, and in dy its partial derivatives d/dy_k (k = 0, 1, 2) at (t, y).
  T value_and_gradient(const T& t, const vec3<T>& y, vec3<T>& dy) const {
    count_ = 3;
    const T v = evaluate_with_partials(t, y, nullptr);
    for (std::size_t k = 0; k < 3; ++k) dy[k] = partials_[0][k];
    return v;
  }
  // The value, and in d its partials by y1..y3 and q0..q3 at (t, y, q).
  T value_and_gradient(const T& t, const vec3<T>& y, const attitude_values& q, partials& d) const {
    count_ = 7;
    const T v = evaluate_with_partials(t, y, &q);
    d = partials_[0];
    return v;
  }

 private:
  // values_at_nodes: whether a stack entry is a + b s (known).
  struct affine_tag {
    bool known = false;
    T a, lo, b;  // a + lo + b s
  };

  // values_at_nodes: f on every node value of slot i; a constant's tag stays one, no other.
  template <class F>
  void elementwise_at_nodes(std::size_t i, F&& f) const {
    for (T& x : node_stack_[i]) f(x);
    affine_[i].known = affine_[i].known && affine_[i].b == 0 && affine_[i].lo == 0;  // a constant stays one
    if (affine_[i].known) affine_[i].a = node_stack_[i][0];
  }

  // values_at_nodes: slot sp - 1 op slot sp (the popped top) into slot sp - 1, values and tags.
  void binary_at_nodes(expression_op op, std::size_t sp, std::size_t n) const {
    std::vector<T>& x = node_stack_[sp - 1];
    const std::vector<T>& y = node_stack_[sp];
    for (std::size_t j = 0; j < n; ++j) {
      if (op == expression_op::add) x[j] += y[j];
      else if (op == expression_op::sub) x[j] -= y[j];
      else if (op == expression_op::mul) x[j] *= y[j];
      else x[j] /= y[j];
    }
    combine_affine(op, affine_[sp - 1], affine_[sp]);
  }

  // The tag of p op q into p: a sum or difference of affine values, or a product or quotient by a
  // constant, stays affine (a_lo by TwoSum and, in quad, Dekker's product); nothing else does.
  static void combine_affine(expression_op op, affine_tag& p, const affine_tag& q) {
    if (op == expression_op::add || op == expression_op::sub) {
      p.known = p.known && q.known;
      if (p.known) {
        const bool add = op == expression_op::add;
        T sum, error, scratch;
        two_sum(p.a, add ? q.a : T(-q.a), sum, error, scratch);
        p.lo = add ? T(p.lo + q.lo) : T(p.lo - q.lo);
        p.lo += error;
        p.a = sum;
        p.b = add ? T(p.b + q.b) : T(p.b - q.b);
      }
    } else if (op == expression_op::mul && p.known && q.known && (p.b == 0 || q.b == 0)) {
      T a, rounding;  // a + rounding = p.a q.a exactly
      if constexpr (std::is_same_v<T, quad>) {
        two_product(p.a, q.a, a, rounding);
      } else {
        a = p.a * q.a;
        rounding = 0;
      }
      const T lo = p.lo * q.a + p.a * q.lo + rounding, b = p.b == 0 ? T(p.a * q.b) : T(p.b * q.a);
      p = {true, a, lo, b};
    } else if (op == expression_op::div && p.known && q.known && q.b == 0) {
      const T a = p.a / q.a;
      T rest = 0;  // p.a - a q.a, exactly (Sterbenz: a q.a is within an ulp of p.a)
      if constexpr (std::is_same_v<T, quad>) {
        T hi, lo;
        two_product(a, q.a, hi, lo);
        rest = (p.a - hi) - lo;
      }
      p = {true, a, T((p.lo + rest - a * q.lo) / q.a), T(p.b / q.a)};
    } else {
      p.known = false;
    }
  }

  // values_at_nodes: the unary step s (negation, power or function) on slot i; a sine or cosine
  // of an affine argument goes whole to affine_sine when it takes it.
  template <class AffineSine>
  void function_at_nodes(const expression_step& s, std::size_t i, AffineSine& affine_sine) const {
    using std::cos;
    using std::sin;
    affine_tag& p = affine_[i];
    switch (s.op) {
      case expression_op::neg:
        for (T& x : node_stack_[i]) detail::negate_in_place(x);
        if (p.known)
          for (T* v : {&p.a, &p.lo, &p.b}) detail::negate_in_place(*v);
        break;
      case expression_op::pow: elementwise_at_nodes(i, [&](T& x) { integer_power(x, s.arg); }); break;
      case expression_op::sin:
      case expression_op::cos: {
        const bool cosine = s.op == expression_op::cos;
        if (p.known && p.b != 0 && affine_sine(p.a, p.lo, p.b, cosine, node_stack_[i])) {
          p.known = false;
          break;
        }
        elementwise_at_nodes(i, [&](T& x) {
          s1_ = cosine ? T(cos(x)) : T(sin(x));  // T(...): MPFR's two expression types
          std::swap(x, s1_);
        });
        break;
      }
      default:
        elementwise_at_nodes(i, [&](T& x) {
          function_value(s.op, x);
          std::swap(x, s1_);
        });
        break;
    }
  }

  // Slot `slot` of a variable step: the time, a state component or (q given) an attitude one.
  static const T& slot_value(int slot, const T& t, const vec3<T>& y, const attitude_values* q) {
    if (slot == expression::time_slot) return t;
    if (slot <= expression::state_slots) return y[static_cast<std::size_t>(slot - 1)];
    if (!q) throw std::logic_error("expression: the attitude q is named but not given");
    return (*q)[static_cast<std::size_t>(slot - expression::attitude_slot)];
  }

  // s1_ = f(x) for a function step f. f(x) goes to a scratch value, which the caller then trades
  // with x: no temporary for MPFR.
  void function_value(expression_op op, const T& x) const {
    using std::atan;
    using std::cos;
    using std::cosh;
    using std::exp;
    using std::log;
    using std::sin;
    using std::sinh;
    using std::sqrt;
    using std::tanh;
    switch (op) {
      case expression_op::sin: s1_ = sin(x); break;
      case expression_op::cos: s1_ = cos(x); break;
      case expression_op::exp: s1_ = exp(x); break;
      case expression_op::log: s1_ = log(x); break;
      case expression_op::sqrt: s1_ = sqrt(x); break;
      case expression_op::tanh: s1_ = tanh(x); break;
      case expression_op::atan: s1_ = atan(x); break;
      case expression_op::sinh: s1_ = sinh(x); break;
      case expression_op::cosh: s1_ = cosh(x); break;
      default: throw std::logic_error("expression: not a function step");
    }
  }

  T evaluate(const T& t, const vec3<T>& y, const attitude_values* q) const {
    using std::swap;
    std::size_t sp = 0;  // values_[0, sp) is the stack
    for (const expression_step& s : source_.code) {
      switch (s.op) {
        case expression_op::constant: values_[sp++] = constants_[static_cast<std::size_t>(s.arg)]; break;
        case expression_op::pi: values_[sp++] = pi_; break;
        case expression_op::variable: values_[sp++] = slot_value(s.arg, t, y, q); break;
        case expression_op::add: --sp; values_[sp - 1] += values_[sp]; break;
        case expression_op::sub: --sp; values_[sp - 1] -= values_[sp]; break;
        case expression_op::mul: --sp; values_[sp - 1] *= values_[sp]; break;
        case expression_op::div: --sp; values_[sp - 1] /= values_[sp]; break;
        case expression_op::neg: detail::negate_in_place(values_[sp - 1]); break;
        case expression_op::pow: integer_power(values_[sp - 1], s.arg); break;
        default:
          function_value(s.op, values_[sp - 1]);
          swap(values_[sp - 1], s1_);
          break;
      }
    }
    return values_[0];
  }

  // Forward mode: each stack entry carries its value and its partials (count_ of them: 3, or 7
  // with q), and each step applies the derivative rule of its operation exactly (sum, product
  // and quotient rules, the chain rule for the functions). The value is computed by the same
  // operations in the same order as operator(), so the two agree to the last bit.
  T evaluate_with_partials(const T& t, const vec3<T>& y, const attitude_values* q) const {
    std::size_t sp = 0;
    for (const expression_step& s : source_.code) {
      switch (s.op) {
        case expression_op::constant:
        case expression_op::pi:
        case expression_op::variable: push_with_partials(s, t, y, q, sp); break;
        case expression_op::add:
        case expression_op::sub:
        case expression_op::mul:
        case expression_op::div:
          --sp;
          binary_with_partials(s.op, sp);
          break;
        case expression_op::neg:
          detail::negate_in_place(values_[sp - 1]);
          for (std::size_t k = 0; k < count_; ++k) detail::negate_in_place(partials_[sp - 1][k]);
          break;
        case expression_op::pow: power_with_partials(values_[sp - 1], partials_[sp - 1], s.arg); break;
        default: function_with_partials(s.op, sp - 1); break;
      }
    }
    return values_[0];
  }

  // A constant, pi or a variable onto the stack, with its partials (1 for d y_k / d y_k).
  void push_with_partials(const expression_step& s, const T& t, const vec3<T>& y, const attitude_values* q,
                          std::size_t& sp) const {
    zero(partials_[sp]);
    if (s.op == expression_op::constant) {
      values_[sp] = constants_[static_cast<std::size_t>(s.arg)];
    } else if (s.op == expression_op::pi) {
      values_[sp] = pi_;
    } else {
      values_[sp] = slot_value(s.arg, t, y, q);
      if (s.arg != expression::time_slot) partials_[sp][static_cast<std::size_t>(s.arg - 1)] = 1;
    }
    ++sp;
  }

  // a op b with a = entry sp - 1 and b = entry sp: the sum, difference, product and quotient
  // rules.
  void binary_with_partials(expression_op op, std::size_t sp) const {
    using std::swap;
    T& a = values_[sp - 1];
    const T& b = values_[sp];
    switch (op) {
      case expression_op::add:
        a += b;
        for (std::size_t k = 0; k < count_; ++k) partials_[sp - 1][k] += partials_[sp][k];
        break;
      case expression_op::sub:
        a -= b;
        for (std::size_t k = 0; k < count_; ++k) partials_[sp - 1][k] -= partials_[sp][k];
        break;
      case expression_op::mul:  // (a b)' = a' b + a b'
        for (std::size_t k = 0; k < count_; ++k) {
          partials_[sp - 1][k] *= b;
          s2_ = a;
          s2_ *= partials_[sp][k];
          partials_[sp - 1][k] += s2_;
        }
        a *= b;
        break;
      default:  // div: (a / b)' = (a' - q b') / b with q = a / b
        s1_ = a;
        s1_ /= b;
        for (std::size_t k = 0; k < count_; ++k) {
          s2_ = s1_;
          s2_ *= partials_[sp][k];
          partials_[sp - 1][k] -= s2_;
          partials_[sp - 1][k] /= b;
        }
        swap(a, s1_);
        break;
    }
  }

  // f(x) for x = entry i, by the chain rule: f(x)' = f'(x) x'. The value is function_value's, as
  // in operator(); f'(x) multiplies the partials, or its reciprocal divides them.
  void function_with_partials(expression_op op, std::size_t i) const {
    using std::cos;
    using std::cosh;
    using std::sin;
    using std::sinh;
    using std::swap;
    T& x = values_[i];
    function_value(op, x);  // s1_ = f(x)
    const T* factor = &s2_;  // f'(x), or 1 / f'(x) where `divide`
    bool divide = false;
    switch (op) {
      case expression_op::sin: s2_ = cos(x); break;  // sin' = cos
      case expression_op::cos: s2_ = sin(x); detail::negate_in_place(s2_); break;  // cos' = -sin
      case expression_op::exp: factor = &s1_; break;  // exp' = exp
      case expression_op::log: factor = &x; divide = true; break;  // log' x = 1 / x
      case expression_op::sqrt: factor = &s1_; divide = true; break;  // sqrt' x = 1 / (2 sqrt x)
      case expression_op::tanh:  // tanh' = 1 / cosh^2: no cancellation, unlike 1 - tanh^2
        s2_ = cosh(x);
        s2_ *= s2_;
        divide = true;
        break;
      case expression_op::atan:  // atan' x = 1 / (1 + x^2)
        s2_ = x;
        s2_ *= x;
        s2_ += 1;
        divide = true;
        break;
      case expression_op::sinh: s2_ = cosh(x); break;  // sinh' = cosh
      default: s2_ = sinh(x); break;                   // cosh' = sinh
    }
    for (std::size_t k = 0; k < count_; ++k) {
      if (!divide) {
        partials_[i][k] *= *factor;
        continue;
      }
      partials_[i][k] /= *factor;
      if (op == expression_op::sqrt) partials_[i][k] /= 2;  // exact
    }
    swap(x, s1_);
  }

  void zero(partials& v) const {
    for (std::size_t k = 0; k < count_; ++k) v[k] = 0;
  }

  // x = x^m for m >= 1, in place, by left-to-right binary powering (square, and multiply by the
  // base at each set bit): m = 2 is the single product x x, correctly rounded, and m = 3 is
  // (x x) x, as written by hand. At most 2 log2(m) products. `base` is scratch.
  static void raise(T& x, unsigned m, T& base) {
    if (m <= 1) return;
    base = x;
    for (int b = static_cast<int>(std::bit_width(m)) - 2; b >= 0; --b) {
      x *= x;
      if (((m >> b) & 1u) != 0) x *= base;
    }
  }

  // x = x^n for an integer n: n = 0 gives 1 (also for x = 0, as pow does), n < 0 gives
  // 1 / x^|n| (one rounding more than x^|n|; infinite at x = 0, which the caller sees).
  void integer_power(T& x, std::int32_t n) const {
    using std::swap;
    if (n == 0) {
      x = 1;
      return;
    }
    const unsigned m = n < 0 ? 0u - static_cast<unsigned>(n) : static_cast<unsigned>(n);
    raise(x, m, s2_);
    if (n < 0) {
      s1_ = 1;
      s1_ /= x;
      swap(x, s1_);
    }
  }

  // x = x^n and its partials: (x^n)' = n x^(n-1) x' for n > 0; for n = -m < 0,
  // (1 / x^m)' = -m x^(m-1) x' / x^(2m) = -m x^(m-1) v^2 x' with v = 1 / x^m.
  void power_with_partials(T& x, partials& d, std::int32_t n) const {
    if (n == 0) {
      x = 1;
      zero(d);
      return;
    }
    const unsigned m = n < 0 ? 0u - static_cast<unsigned>(n) : static_cast<unsigned>(n);
    // s3_ = x^(m-1)
    if (m == 1) {
      s3_ = 1;
    } else {
      s3_ = x;
      raise(s3_, m - 1, s2_);
    }
    integer_power(x, n);  // the same operations as operator()
    if (n > 0) {
      s3_ *= m;
    } else {
      s3_ *= x;
      s3_ *= x;
      s3_ *= m;
      detail::negate_in_place(s3_);
    }
    for (std::size_t k = 0; k < count_; ++k) d[k] *= s3_;
  }

  expression source_;
  std::vector<T> constants_;
  T pi_;
  // The evaluation stack and scratch values: allocated at construction, reused by every call.
  mutable std::vector<T> values_;
  mutable std::vector<partials> partials_;
  mutable std::size_t count_ = 3;  // the partials in use: 3, or 7 with q
  mutable T s1_, s2_, s3_;
  // values_at_nodes: the stack of node values, and their tags.
  mutable std::vector<std::vector<T>> node_stack_;
  mutable std::vector<affine_tag> affine_;
};

}  // namespace eulervop
