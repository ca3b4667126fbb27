// The box algebra of the general path of --certify (field_algebra.hpp): a ball with its first
// and second partial derivatives by the state, in which the field is evaluated over a box of
// states, for the quadratic remainder c(R) and the bound of |F| over the tube (ball_certifier.hpp).
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/chebyshev_composition.hpp>

#include <arb.h>

#include <cstddef>
#include <stdexcept>
#include <utility>
#include <vector>

namespace eulervop::detail {

// A ball with its gradient and Hessian by n variables (H row-major, n x n, symmetric).
struct box_jet {
  ball f;
  std::vector<ball> g, H;
};

class box_algebra {
 public:
  using value = box_jet;
  box_algebra(slong prec, std::size_t variables) : prec_(prec), n_(variables) {}

  slong prec() const { return prec_; }
  value constant(const ball& c) const {
    value v;
    v.f = c;
    v.g.resize(n_);
    v.H.resize(n_ * n_);
    return v;
  }
  value variable(const ball& x, std::size_t k) const {
    value v = constant(x);
    arb_one(v.g[k].get());
    return v;
  }
  value independent(const ball& x) const { return constant(x); }
  // The gradients and Hessians of a state's field are mostly zero (a product of two variables has
  // two Hessian entries): every term with an exactly zero factor is skipped, which leaves Arb's
  // results as they were (x + 0 and 0 y are exact, and x is already at prec_).
  void add(value& a, const value& b) const { combine(a, b, arb_add); }
  void sub(value& a, const value& b) const { combine(a, b, arb_sub); }
  void neg(value& a) const {
    arb_neg(a.f.get(), a.f.get());
    for (ball& x : a.g) arb_neg(x.get(), x.get());
    for (ball& x : a.H) arb_neg(x.get(), x.get());
  }
  void scale(value& a, const ball& x) const {
    arb_mul(a.f.get(), a.f.get(), x.get(), prec_);
    for (ball& y : a.g)
      if (!arb_is_zero(y.get())) arb_mul(y.get(), y.get(), x.get(), prec_);
    for (ball& y : a.H)
      if (!arb_is_zero(y.get())) arb_mul(y.get(), y.get(), x.get(), prec_);
  }
  // a = f(a): grad f(a) = f'(a) grad a, H f(a) = f'(a) H a + f''(a) grad a grad a^T, with f, f'
  // and f'' over a's ball. std::domain_error where the ball leaves f's domain.
  void function(elementary f, value& a) const {
    ball v, d1, d2;
    if (!elementary_on_ball(f, a.f, &v, &d1, &d2, prec_)) throw std::domain_error(outside_domain(f));
    ball gg;
    for (std::size_t i = 0; i < n_; ++i)
      for (std::size_t j = 0; j < n_; ++j) {
        arb_ptr h = a.H[i * n_ + j].get();
        if (!arb_is_zero(h)) arb_mul(h, h, d1.get(), prec_);
        if (arb_is_zero(a.g[i].get()) || arb_is_zero(a.g[j].get())) continue;
        arb_mul(gg.get(), a.g[i].get(), a.g[j].get(), prec_);
        arb_addmul(h, gg.get(), d2.get(), prec_);
      }
    for (ball& x : a.g)
      if (!arb_is_zero(x.get())) arb_mul(x.get(), x.get(), d1.get(), prec_);
    a.f = v;
  }
  void invert(value& a) const { function(elementary::inverse, a); }
  // a = a b: H(ab) = a H(b) + b H(a) + grad a grad b^T + grad b grad a^T.
  void mul(value& a, const value& b) const {
    const auto zero = [](const ball& x) { return arb_is_zero(x.get()) != 0; };
    const bool af = !zero(a.f);
    for (std::size_t i = 0; i < n_; ++i)
      for (std::size_t j = 0; j < n_; ++j) {
        arb_ptr h = a.H[i * n_ + j].get();
        const ball& bh = b.H[i * n_ + j];
        if (!arb_is_zero(h)) arb_mul(h, h, b.f.get(), prec_);
        if (af && !zero(bh)) arb_addmul(h, a.f.get(), bh.get(), prec_);
        if (!zero(a.g[i]) && !zero(b.g[j])) arb_addmul(h, a.g[i].get(), b.g[j].get(), prec_);
        if (!zero(b.g[i]) && !zero(a.g[j])) arb_addmul(h, b.g[i].get(), a.g[j].get(), prec_);
      }
    ball t;
    for (std::size_t k = 0; k < n_; ++k) {
      if (zero(a.g[k]) && zero(b.g[k])) continue;
      arb_mul(t.get(), a.g[k].get(), b.f.get(), prec_);
      arb_addmul(t.get(), a.f.get(), b.g[k].get(), prec_);
      std::swap(a.g[k], t);
    }
    arb_mul(a.f.get(), a.f.get(), b.f.get(), prec_);
  }
  // a = a a (mul() updates a in place, so it takes a copy).
  void square(value& a) const {
    const value b = a;
    mul(a, b);
  }
  // out = a b.
  void product(value& out, const value& a, const value& b) const {
    out = a;
    mul(out, b);
  }

 private:
  slong prec_;
  std::size_t n_;

  // a = op(a, b) entry by entry (op: arb_add or arb_sub), b's zero partials skipped.
  void combine(value& a, const value& b, void (*op)(arb_t, const arb_t, const arb_t, slong)) const {
    op(a.f.get(), a.f.get(), b.f.get(), prec_);
    for (std::size_t k = 0; k < n_; ++k)
      if (!arb_is_zero(b.g[k].get())) op(a.g[k].get(), a.g[k].get(), b.g[k].get(), prec_);
    for (std::size_t k = 0; k < n_ * n_; ++k)
      if (!arb_is_zero(b.H[k].get())) op(a.H[k].get(), a.H[k].get(), b.H[k].get(), prec_);
  }
};

}  // namespace eulervop::detail
