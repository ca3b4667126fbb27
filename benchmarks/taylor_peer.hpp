// A Taylor-series integrator: the peer our reference is measured against in bench_problems
// (docs/benchmarks.md), written from the published method, not from any code.
//
// The method is that of heyoka's taylor_adaptive and of TIDES (A. Jorba and M. Zou, "A software
// package for the numerical integration of ODEs by means of high-order Taylor methods",
// Experimental Mathematics 14, 2005; F. Biscani and D. Izzo, heyoka's documentation):
//   - order p = ceil(-ln(tol) / 2 + 1);
//   - the Taylor coefficients of the solution by automatic differentiation: for Euler's equations
//     in the form of Eq. 1, y_i' = a_i y_j y_k + f_i(t), coefficient k+1 of y_i is
//     (a_i sum_{m<=k} y_j[m] y_k[k-m] + f_i[k]) / (k+1) (a Cauchy product per component);
//   - the step h = min_{k in {p-1, p}} (max(1, |y|_inf) / |y[k]|_inf)^(1/k) e^-2 e^(-0.7/(p-1));
//   - samples inside a step from its Taylor polynomial (dense output), as heyoka's propagate_grid.
// The forcing f_i(t) is a constant or a formula of the time alone (the scene's expression program,
// model/expression.hpp), whose Taylor coefficients at each step come from the same recurrences on
// truncated series: products, quotients, integer powers, and sin, cos, exp, log, sqrt by their
// differential equations (e.g. s' = a' c, c' = -a' s for s = sin a, c = cos a).
//
// It takes the problems whose torque reads no state and has no pieces (taylor_applies); the
// others are outside its scope here. T is any scalar: quad or MPFR.
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/model/expression.hpp>
#include <eulervop/model/torque_law.hpp>
#include <eulervop/core/vec3.hpp>

#include <boost/math/constants/constants.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace eulervop::bench {

// A truncated Taylor series in the step's time s = t - t0: coefficients 0..n-1.
template <class T>
using jet = std::vector<T>;

// The Taylor coefficients 0..n-1 of expression `e` of the time at t0 (the program read with jets
// for numbers). Throws std::invalid_argument for a formula of the state.
template <class T>
jet<T> time_jet(const expression& e, const T& t0, std::size_t n) {
  using std::cos;
  using std::exp;
  using std::log;
  using std::sin;
  using std::sqrt;
  if (e.uses_state() || e.uses_attitude()) throw std::invalid_argument("taylor peer: a formula of the state");
  std::vector<jet<T>> stack;
  // The last nonzero coefficient: a constant or a linear jet (the time) multiplies in O(n), as a
  // Taylor integrator's decomposition would treat a product by a number or by t.
  const auto degree = [&](const jet<T>& a) {
    std::size_t d = n;
    while (d > 1 && a[d - 1] == 0) --d;
    return d - 1;
  };
  const auto constant = [&](const T& c) {
    jet<T> j(n, T(0));
    j[0] = c;
    return j;
  };
  const auto mul = [&](const jet<T>& a, const jet<T>& b) {
    jet<T> c(n, T(0));
    const std::size_t da = degree(a), db = degree(b);
    for (std::size_t m = 0; m <= da; ++m)
      for (std::size_t l = 0; l <= db && m + l < n; ++l) c[m + l] += a[m] * b[l];
    return c;
  };
  const auto div = [&](const jet<T>& a, const jet<T>& b) {
    jet<T> c(n, T(0));
    for (std::size_t k = 0; k < n; ++k) {
      T s = a[k];
      for (std::size_t m = 1; m <= k; ++m) s -= b[m] * c[k - m];
      c[k] = s / b[0];
    }
    return c;
  };
  for (const expression_step& step : e.code) {
    switch (step.op) {
      case expression_op::constant: {
        const std::optional<T> c = from_text<T>(e.constants[static_cast<std::size_t>(step.arg)]);
        if (!c) throw std::invalid_argument("taylor peer: a constant that is no number");
        stack.push_back(constant(*c));
        break;
      }
      case expression_op::pi: stack.push_back(constant(boost::math::constants::pi<T>())); break;
      case expression_op::variable: {
        jet<T> t = constant(t0);
        if (n > 1) t[1] = T(1);
        stack.push_back(std::move(t));
        break;
      }
      case expression_op::add:
      case expression_op::sub:
      case expression_op::mul:
      case expression_op::div: {
        jet<T> b = std::move(stack.back());
        stack.pop_back();
        jet<T>& a = stack.back();
        if (step.op == expression_op::add)
          for (std::size_t k = 0; k < n; ++k) a[k] += b[k];
        else if (step.op == expression_op::sub)
          for (std::size_t k = 0; k < n; ++k) a[k] -= b[k];
        else
          a = step.op == expression_op::mul ? mul(a, b) : div(a, b);
        break;
      }
      case expression_op::neg:
        for (T& x : stack.back()) x = -x;
        break;
      case expression_op::pow: {
        const jet<T> base = stack.back();
        jet<T> p = constant(T(1));
        for (std::int32_t i = 0; i < (step.arg < 0 ? -step.arg : step.arg); ++i) p = mul(p, base);
        stack.back() = step.arg < 0 ? div(constant(T(1)), p) : p;
        break;
      }
      default: {
        const jet<T> a = stack.back();
        const std::size_t da = degree(a);
        jet<T> f(n, T(0)), g(n, T(0));  // f: the function; g: its partner (cos for sin) where one is needed
        switch (step.op) {
          case expression_op::sin:
          case expression_op::cos:
            f[0] = sin(a[0]);
            g[0] = cos(a[0]);
            for (std::size_t k = 1; k < n; ++k) {
              T s(0), c(0);
              for (std::size_t m = 1; m <= std::min(k, da); ++m) {
                s += T(m) * a[m] * g[k - m];
                c -= T(m) * a[m] * f[k - m];
              }
              f[k] = s / T(k);
              g[k] = c / T(k);
            }
            if (step.op == expression_op::cos) std::swap(f, g);
            break;
          case expression_op::exp:
            f[0] = exp(a[0]);
            for (std::size_t k = 1; k < n; ++k) {
              T s(0);
              for (std::size_t m = 1; m <= std::min(k, da); ++m) s += T(m) * a[m] * f[k - m];
              f[k] = s / T(k);
            }
            break;
          case expression_op::log:
            f[0] = log(a[0]);
            for (std::size_t k = 1; k < n; ++k) {
              T s(0);
              for (std::size_t m = 1; m < k; ++m) s += T(m) * f[m] * a[k - m];
              f[k] = (a[k] - s / T(k)) / a[0];
            }
            break;
          case expression_op::sqrt:
            f[0] = sqrt(a[0]);
            for (std::size_t k = 1; k < n; ++k) {
              T s(0);
              for (std::size_t m = 1; m < k; ++m) s += f[m] * f[k - m];
              f[k] = (a[k] - s) / (T(2) * f[0]);
            }
            break;
          default:  // tanh, atan, sinh, cosh: not in the peer, whose problems do not use them
            throw std::invalid_argument("taylor peer: no series for a function of `" + e.text + "`");
        }
        stack.back() = std::move(f);
        break;
      }
    }
  }
  return stack.back();
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

// Integrates `p` to the samples `times` (increasing, >= t0), calling take(i, y) at each.
template <class T, class Take>
taylor_stats taylor_integrate(const taylor_problem<T>& p, const T& tol, const std::vector<T>& times, Take&& take) {
  using std::abs;
  using std::ceil;
  using std::exp;
  using std::log;
  using std::max;
  using std::min;
  using std::pow;
  taylor_stats st;
  const unsigned order = static_cast<unsigned>(static_cast<double>(ceil(-log(tol) / T(2) + T(1))));
  st.order = order;
  const std::size_t n = order + 1;  // coefficients 0..p
  static constexpr std::array<std::array<int, 2>, 3> pair = {{{1, 2}, {2, 0}, {0, 1}}};
  const T safety = exp(T(-2)) * exp(T(-0.7) / T(order - 1));
  std::array<jet<T>, 3> y;
  for (auto& c : y) c.assign(n, T(0));
  vec3<T> x = p.y0;
  T t = p.t0;
  std::size_t next = 0;
  while (next < times.size()) {
    std::array<jet<T>, 3> f;
    for (int i = 0; i < 3; ++i)
      f[i] = p.forcing[i] ? time_jet(*p.forcing[i], t, n) : jet<T>();
    for (int i = 0; i < 3; ++i) y[i][0] = x[i];
    for (std::size_t k = 0; k + 1 < n; ++k)
      for (int i = 0; i < 3; ++i) {
        const auto [j, l] = pair[static_cast<std::size_t>(i)];
        T s(0);
        for (std::size_t m = 0; m <= k; ++m) s += y[j][m] * y[l][k - m];
        s *= p.a[i];
        if (p.forcing[i])
          s += f[i][k];
        else if (k == 0)
          s += p.constant[i];
        y[i][k + 1] = s / T(k + 1);
      }
    T norm(1);
    for (int i = 0; i < 3; ++i) norm = max(norm, abs(x[i]));
    T h = -1;
    for (std::size_t k : {order - 1u, order}) {
      T c(0);
      for (int i = 0; i < 3; ++i) c = max(c, abs(y[i][k]));
      if (c == 0) continue;
      const T hk = pow(norm / c, T(1) / T(k));
      h = h < 0 ? hk : min(h, hk);
    }
    h = h < 0 ? times.back() - t : h * safety;
    const T t_end = t + h;
    const auto polynomial = [&](const T& s) {
      vec3<T> out;
      for (int i = 0; i < 3; ++i) {
        T v = y[i][order];
        for (std::size_t k = order; k-- > 0;) v = v * s + y[i][k];
        out[i] = v;
      }
      return out;
    };
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
