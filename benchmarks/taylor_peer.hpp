// A Taylor-series integrator: the peer our reference is measured against in bench_problems
// (docs/benchmarks.md), written from the published method, not from any code.
//
// The method is that of heyoka's taylor_adaptive and of TIDES (A. Jorba and M. Zou, "A software
// package for the numerical integration of ODEs by means of high-order Taylor methods",
// Experimental Mathematics 14, 2005; F. Biscani and D. Izzo, heyoka's documentation):
//   - order p = ceil(-ln(tol) / 2 + 1) (Jorba and Zou, section 3.2);
//   - the Taylor coefficients of the solution by automatic differentiation: for Euler's equations
//     in the form of Eq. 1, y_i' = a_i y_j y_k + f_i(t), coefficient k+1 of y_i is
//     (a_i sum_{m<=k} y_j[m] y_k[k-m] + f_i[k]) / (k+1) (a Cauchy product per component);
//   - the step h = min_{k in {p-1, p}} (max(1, |y|_inf) / |y[k]|_inf)^(1/k) e^-2 e^(-0.7/(p-1))
//     (Jorba and Zou's rule, as heyoka applies it);
//   - samples inside a step from its Taylor polynomial (dense output, as heyoka's propagate_grid):
//     no step is shortened to land on a sample.
// It is built as a compiler of such an integrator builds it (heyoka compiles each problem's jets
// into straight-line code): the Euler part is written out once with its three products, in
// buffers sized once before the first step; the forcing f_i(t), a constant or a formula of the
// time alone (the scene's expression program, model/expression.hpp), is compiled once into a
// flat tape (time_tape) whose nodes have fixed storage and fixed degrees, constants folded, so a
// step allocates nothing and runs no interpreter's stack. The tape's recurrences on truncated
// series: products (Cauchy, bounded by the operands' degrees, squares by symmetry), quotients,
// integer powers, and sin, cos, exp, log, sqrt by their differential equations (e.g. s' = a' c,
// c' = -a' s for s = sin a, c = cos a).
//
// It takes the problems whose torque reads no state and has no pieces (taylor_applies); the
// others are outside its scope here. T is any scalar: quad or MPFR.
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/model/expression.hpp>

#include <boost/math/constants/constants.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace eulervop::bench {

// The Taylor coefficients 0..n-1 of a formula of the time, at any t0, from its program compiled
// once: one node per step of the program, each with its own n coefficients (and a partner's n
// for the cosine of a sine, or a power's scratch) and an upper bound on its degree, the
// coefficients above it zero from the start and never written.
template <class T>
class time_tape {
 public:
  // Throws std::invalid_argument for a formula of the state or a function without a series here.
  time_tape(const expression& e, std::size_t n) : n_(n), text_(e.text) {
    if (e.uses_state() || e.uses_attitude()) throw std::invalid_argument("taylor peer: a formula of the state");
    std::vector<std::size_t> stack;
    for (const expression_step& step : e.code) {
      node nd{step.op, step.arg, 0, 0, 0, true};
      const std::size_t top = stack.empty() ? 0 : stack.back();
      if (is_binary(step.op)) {
        nd.b = top;
        stack.pop_back();
        nd.a = stack.back();
        stack.pop_back();
      } else if (!is_leaf(step.op)) {
        nd.a = top;
        stack.pop_back();
      }
      nd.degree = degree_of(nd);
      nd.fixed = step.op != expression_op::variable &&
                 (is_leaf(step.op) || (nodes_[nd.a].fixed && (!is_binary(step.op) || nodes_[nd.b].fixed)));
      nodes_.push_back(nd);
      stack.push_back(nodes_.size() - 1);
    }
    store_.assign(3 * n_ * nodes_.size(), T(0));
    for (std::size_t k = 0; k < n_; ++k) ks_.push_back(T(static_cast<int>(k)));
    for (std::size_t k = 0; k < nodes_.size(); ++k) {
      if (nodes_[k].op == expression_op::constant) {
        const std::optional<T> c = from_text<T>(e.constants[static_cast<std::size_t>(nodes_[k].arg)]);
        if (!c) throw std::invalid_argument("taylor peer: a constant that is no number");
        out(k)[0] = *c;
      } else if (nodes_[k].op == expression_op::pi) {
        out(k)[0] = boost::math::constants::pi<T>();
      } else if (nodes_[k].op == expression_op::variable && n_ > 1) {
        out(k)[1] = T(1);
      } else if (nodes_[k].fixed) {
        eval(k);  // constants folded: evaluated once here, never in a step
      }
    }
  }

  // The coefficients 0..n-1 at t0; they stay valid until the next call.
  const T* at(const T& t0) {
    for (std::size_t k = 0; k < nodes_.size(); ++k) {
      if (nodes_[k].op == expression_op::variable)
        out(k)[0] = t0;
      else if (!nodes_[k].fixed)
        eval(k);
    }
    return out(nodes_.size() - 1);
  }

 private:
  struct node {
    expression_op op;
    std::int32_t arg;
    std::size_t a, b;    // operands (node indices)
    std::size_t degree;  // the last coefficient that can be nonzero
    bool fixed;          // of no time: evaluated at construction
  };

  static bool is_leaf(expression_op op) {
    return op == expression_op::constant || op == expression_op::pi || op == expression_op::variable;
  }
  static bool is_binary(expression_op op) {
    return op == expression_op::add || op == expression_op::sub || op == expression_op::mul || op == expression_op::div;
  }

  std::size_t degree_of(const node& nd) const {
    const std::size_t top = n_ - 1;
    if (nd.op == expression_op::constant || nd.op == expression_op::pi) return 0;
    if (nd.op == expression_op::variable) return std::min<std::size_t>(1, top);
    const std::size_t da = nodes_[nd.a].degree, db = is_binary(nd.op) ? nodes_[nd.b].degree : 0;
    switch (nd.op) {
      case expression_op::add:
      case expression_op::sub: return std::max(da, db);
      case expression_op::neg: return da;
      case expression_op::mul: return std::min(da + db, top);
      case expression_op::div: return db == 0 ? da : top;
      case expression_op::pow:
        return nd.arg >= 0 ? std::min(static_cast<std::size_t>(nd.arg) * da, top) : (da == 0 ? 0 : top);
      default: return da == 0 ? 0 : top;
    }
  }

  T* out(std::size_t k) { return &store_[3 * n_ * k]; }
  T* partner(std::size_t k) { return &store_[3 * n_ * k + n_]; }
  T* scratch(std::size_t k) { return &store_[3 * n_ * k + 2 * n_]; }

  // c[0..dc] = (a * b)[0..dc], from a's coefficients 0..da and b's 0..db.
  static void product(const T* a, std::size_t da, const T* b, std::size_t db, T* c, std::size_t dc) {
    for (std::size_t k = 0; k <= dc; ++k) {
      T s(0);
      for (std::size_t m = k > db ? k - db : 0; m <= std::min(k, da); ++m) s += a[m] * b[k - m];
      c[k] = s;
    }
  }

  // c[0..dc] = (a^2)[0..dc]: each pair of distinct factors once, doubled.
  static void square(const T* a, std::size_t da, T* c, std::size_t dc) {
    for (std::size_t k = 0; k <= dc; ++k) {
      T s(0);
      const std::size_t lo = k > da ? k - da : 0;
      for (std::size_t m = lo; 2 * m < k; ++m) s += a[m] * a[k - m];
      s += s;
      if (k % 2 == 0 && k / 2 <= da) s += a[k / 2] * a[k / 2];
      c[k] = s;
    }
  }

  // c = a / b, every coefficient.
  void quotient(const T* a, std::size_t da, const T* b, std::size_t db, T* c, std::size_t dc) const {
    for (std::size_t k = 0; k <= dc; ++k) {
      T s = k <= da ? a[k] : T(0);
      for (std::size_t m = 1; m <= std::min(k, db); ++m) s -= b[m] * c[k - m];
      c[k] = s / b[0];
    }
  }

  // out(k) = a^p, p > 0, by squares and products in the node's scratch (no allocation).
  void power(std::size_t k, const T* a, std::size_t da, std::int32_t p, T* c, std::size_t dc) {
    if (p == 2) return square(a, da, c, dc);
    T* s = scratch(k);
    std::copy(a, a + da + 1, c);
    std::size_t d = da;
    for (std::int32_t i = 1; i < p; ++i) {
      const std::size_t dn = std::min(d + da, n_ - 1);
      product(c, d, a, da, s, dn);
      std::copy(s, s + dn + 1, c);
      d = dn;
    }
  }

  // sin or cos of an argument of degree at most 1, u0 + u1 s: closed forms below.
  bool is_affine_sine(const node& nd) const {
    return (nd.op == expression_op::sin || nd.op == expression_op::cos) && nodes_[nd.a].degree <= 1;
  }

  // sin(u0 + u1 s) = sum_k u1^k / k! sin(u0 + k pi / 2) s^k, and the cosine likewise: from f[0] =
  // sin u0 and g[0] = cos u0, the derivatives cycling through (s, c, -s, -c) and (c, -s, -c, s).
  void affine_sine(T* f, T* g, const T& u1, std::size_t dc) const {
    T w(1);  // u1^k / k!
    for (std::size_t k = 1; k <= dc; ++k) {
      w = w * u1 / ks_[k];
      const T& sv = k % 2 ? g[0] : f[0];
      const T& cv = k % 2 ? f[0] : g[0];
      const bool s_negative = k % 4 == 2 || k % 4 == 3, c_negative = k % 4 == 1 || k % 4 == 2;
      f[k] = s_negative ? T(-(w * sv)) : T(w * sv);
      g[k] = c_negative ? T(-(w * cv)) : T(w * cv);
    }
  }

  // sin^2 u = (1 - cos 2u) / 2 and cos^2 u = (1 + cos 2u) / 2 for u = u0 + u1 s: coefficient k >= 1
  // is -+ (2 u1)^k / k! cos(2 u0 + k pi / 2) / 2, with cos 2u0 = c^2 - s^2 and sin 2u0 = 2 s c of
  // the sine node's values (a hand-written jet's double angle, O(p) instead of the square's O(p^2)).
  void affine_sine_square(const node& sine, T* c, std::size_t dc) const {
    const T* s = &store_[3 * n_ * index_of(sine)];
    const T* co = s + n_;
    const bool is_sin = sine.op == expression_op::sin;
    const T sv = is_sin ? s[0] : co[0], cv = is_sin ? co[0] : s[0];  // the node's sine and cosine
    c[0] = is_sin ? T(sv * sv) : T(cv * cv);
    if (dc == 0) return;
    const T u1 = nodes_[sine.a].degree == 1 ? store_[3 * n_ * sine.a + 1] : T(0);
    const T c2 = cv * cv - sv * sv, s2 = T(2) * sv * cv, two_u1 = u1 + u1;
    T w = is_sin ? T(-0.5) : T(0.5);  // -+ (2 u1)^k / k! / 2
    for (std::size_t k = 1; k <= dc; ++k) {
      w = w * two_u1 / ks_[k];
      const T& v = k % 2 ? s2 : c2;  // cos(2u0 + k pi/2) = c2, -s2, -c2, s2
      c[k] = (k % 4 == 1 || k % 4 == 2) ? T(-(w * v)) : T(w * v);
    }
  }

  std::size_t index_of(const node& nd) const { return static_cast<std::size_t>(&nd - nodes_.data()); }

  void eval(std::size_t k);
  void eval_function(std::size_t k, const T* a, std::size_t da);

  std::size_t n_;
  std::vector<T> ks_;  // k in T, k = 0..n-1
  std::string text_;
  std::vector<node> nodes_;
  std::vector<T> store_;  // per node: its coefficients, its partner's, its scratch (n each)
};

template <class T>
void time_tape<T>::eval(std::size_t k) {
  const node& nd = nodes_[k];
  T* c = out(k);
  const T* a = out(nd.a);
  const std::size_t da = nodes_[nd.a].degree, dc = nd.degree;
  const T* b = is_binary(nd.op) ? out(nd.b) : nullptr;
  const std::size_t db = b ? nodes_[nd.b].degree : 0;
  switch (nd.op) {
    case expression_op::add:
      for (std::size_t m = 0; m <= dc; ++m) c[m] = (m <= da ? a[m] : T(0)) + (m <= db ? b[m] : T(0));
      break;
    case expression_op::sub:
      for (std::size_t m = 0; m <= dc; ++m) c[m] = (m <= da ? a[m] : T(0)) - (m <= db ? b[m] : T(0));
      break;
    case expression_op::neg:
      for (std::size_t m = 0; m <= dc; ++m) c[m] = -a[m];
      break;
    case expression_op::mul: product(a, da, b, db, c, dc); break;
    case expression_op::div: quotient(a, da, b, db, c, dc); break;
    case expression_op::pow: {
      const std::int32_t p = nd.arg < 0 ? -nd.arg : nd.arg;
      if (nd.arg == 2 && is_affine_sine(nodes_[nd.a])) {
        affine_sine_square(nodes_[nd.a], c, dc);
      } else if (p == 0) {
        c[0] = T(1);
      } else if (nd.arg > 0) {
        power(k, a, da, p, c, dc);
      } else {  // 1 / a^p: the power in the partner, then the quotient
        T* q = partner(k);
        const std::size_t dq = std::min(static_cast<std::size_t>(p) * da, n_ - 1);
        power(k, a, da, p, q, dq);
        T one[1] = {T(1)};
        quotient(one, 0, q, dq, c, dc);
      }
      break;
    }
    default: eval_function(k, a, da);
  }
}

// sin, cos, exp, log, sqrt of node a (degree da) into node k, by their differential equations.
template <class T>
void time_tape<T>::eval_function(std::size_t k, const T* a, std::size_t da) {
  using std::cos;
  using std::exp;
  using std::log;
  using std::sin;
  using std::sqrt;
  const expression_op op = nodes_[k].op;
  const std::size_t dc = nodes_[k].degree;
  T* f = out(k);
  T* g = partner(k);
  switch (op) {
    case expression_op::sin:
    case expression_op::cos: {
      if (op == expression_op::cos) std::swap(f, g);  // f the sine, g the cosine
      f[0] = sin(a[0]);
      g[0] = cos(a[0]);
      if (da <= 1) return affine_sine(f, g, da == 1 ? a[1] : T(0), dc);
      for (std::size_t j = 1; j <= dc; ++j) {
        T s(0), c(0);
        for (std::size_t m = 1; m <= std::min(j, da); ++m) {
          const T am = T(static_cast<int>(m)) * a[m];
          s += am * g[j - m];
          c -= am * f[j - m];
        }
        f[j] = s / T(static_cast<int>(j));
        g[j] = c / T(static_cast<int>(j));
      }
      break;
    }
    case expression_op::exp:
      f[0] = exp(a[0]);
      for (std::size_t j = 1; j <= dc; ++j) {
        T s(0);
        for (std::size_t m = 1; m <= std::min(j, da); ++m) s += T(static_cast<int>(m)) * a[m] * f[j - m];
        f[j] = s / T(static_cast<int>(j));
      }
      break;
    case expression_op::log:
      f[0] = log(a[0]);
      for (std::size_t j = 1; j <= dc; ++j) {
        T s(0);
        for (std::size_t m = 1; m < j; ++m)
          if (j - m <= da) s += T(static_cast<int>(m)) * f[m] * a[j - m];
        f[j] = ((j <= da ? a[j] : T(0)) - s / T(static_cast<int>(j))) / a[0];
      }
      break;
    case expression_op::sqrt:
      f[0] = sqrt(a[0]);
      for (std::size_t j = 1; j <= dc; ++j) {
        T s(0);
        for (std::size_t m = 1; m < j; ++m) s += f[m] * f[j - m];
        f[j] = ((j <= da ? a[j] : T(0)) - s) / (T(2) * f[0]);
      }
      break;
    default:  // tanh, atan, sinh, cosh: not in the peer, whose problems do not use them
      throw std::invalid_argument("taylor peer: no series for a function of `" + text_ + "`");
  }
}

// The problem the peer integrates: y_i' = a_i y_j y_k + f_i(t), (i, j, k) cyclic, from t0, y0.
template <class T>
struct taylor_problem {
  vec3<T> a;
  std::array<std::optional<expression>, 3> forcing;  // none: the constant
  vec3<T> constant{T(0), T(0), T(0)};
  T t0{0};
  vec3<T> y0;
};

struct taylor_stats {
  std::size_t steps = 0;
  unsigned order = 0;
};

namespace detail {

// log |x| in double, from double where x's magnitude fits one and from T where it does not.
template <class T>
double log_abs(const T& x) {
  using std::abs;
  using std::log;
  const T ax = abs(x);
  if (ax > T(1e-300) && ax < T(1e300)) return std::log(static_cast<double>(ax));
  return static_cast<double>(log(ax));
}

// The coefficients 1..p of the solution from y[i][0] (y: three runs of n = p + 1 coefficients),
// the forcing's coefficients f[i] (null: the constant c[i]) and Eq. 1's a.
template <class T>
void euler_jets(T* y, std::size_t n, const vec3<T>& a, const std::array<const T*, 3>& f, const vec3<T>& c,
                const std::vector<T>& divisors) {
  T* y1 = y;
  T* y2 = y + n;
  T* y3 = y + 2 * n;
  const auto cauchy = [](const T* u, const T* v, std::size_t k) {
    T s = u[0] * v[k];
    for (std::size_t m = 1; m <= k; ++m) s += u[m] * v[k - m];
    return s;
  };
  const auto forcing = [&](int i, std::size_t k, T& s) {
    if (f[i]) s += f[i][k];
    else if (k == 0) s += c[i];
  };
  for (std::size_t k = 0; k + 1 < n; ++k) {
    T s1 = a[0] * cauchy(y2, y3, k);
    T s2 = a[1] * cauchy(y3, y1, k);
    T s3 = a[2] * cauchy(y1, y2, k);
    forcing(0, k, s1);
    forcing(1, k, s2);
    forcing(2, k, s3);
    y1[k + 1] = s1 / divisors[k];
    y2[k + 1] = s2 / divisors[k];
    y3[k + 1] = s3 / divisors[k];
  }
}

}  // namespace detail

// Integrates `p` to the samples `times` (increasing, >= t0), calling take(i, y) at each.
template <class T, class Take>
taylor_stats taylor_integrate(const taylor_problem<T>& p, const T& tol, const std::vector<T>& times, Take&& take) {
  using std::ceil;
  using std::log;
  taylor_stats st;
  const unsigned order = static_cast<unsigned>(static_cast<double>(ceil(-log(tol) / T(2) + T(1))));
  st.order = order;
  const std::size_t n = order + 1;  // coefficients 0..p
  // The step's factor e^-2 e^(-0.7/(p-1)): a rule of thumb for the step, so in double.
  const double safety_log = -2 - 0.7 / static_cast<double>(order - 1);
  std::vector<T> divisors(n), y(3 * n, T(0));  // the divisors k+1 in T once; the three jets
  for (std::size_t k = 0; k < n; ++k) divisors[k] = T(static_cast<int>(k + 1));
  std::array<std::optional<time_tape<T>>, 3> tapes;
  for (int i = 0; i < 3; ++i)
    if (p.forcing[i]) tapes[i].emplace(*p.forcing[i], n);
  vec3<T> x = p.y0;
  T t = p.t0;
  std::size_t next = 0;
  const auto polynomial = [&](const T& s) {
    vec3<T> out;
    for (int i = 0; i < 3; ++i) {
      const T* c = &y[static_cast<std::size_t>(i) * n];
      T v = c[order];
      for (std::size_t k = order; k-- > 0;) v = v * s + c[k];
      out[i] = v;
    }
    return out;
  };
  while (next < times.size()) {
    std::array<const T*, 3> f{};
    for (int i = 0; i < 3; ++i)
      if (tapes[i]) f[i] = tapes[i]->at(t);
    for (int i = 0; i < 3; ++i) y[static_cast<std::size_t>(i) * n] = x[i];
    detail::euler_jets(y.data(), n, p.a, f, p.constant, divisors);
    double norm_log = 0;  // log max(1, |x|_inf)
    for (int i = 0; i < 3; ++i)
      if (x[i] != 0) norm_log = std::max(norm_log, detail::log_abs(x[i]));
    std::optional<double> h_log;
    for (std::size_t k : {order - 1u, order}) {
      std::optional<double> c_log;  // log |y[k]|_inf
      for (std::size_t i = 0; i < 3; ++i)
        if (y[i * n + k] != 0) c_log = std::max(c_log.value_or(-1e300), detail::log_abs(y[i * n + k]));
      if (!c_log) continue;
      const double hk = (norm_log - *c_log) / static_cast<double>(k);
      h_log = h_log ? std::min(*h_log, hk) : hk;
    }
    const T h = h_log ? T(std::exp(*h_log + safety_log)) : T(times.back() - t);
    const T t_end = t + h;
    while (next < times.size() && times[next] <= t_end) {
      take(next, polynomial(times[next] - t));
      ++next;
    }
    if (next == times.size()) break;
    x = polynomial(h);
    t = t_end;
    ++st.steps;
  }
  return st;
}

}  // namespace eulervop::bench
