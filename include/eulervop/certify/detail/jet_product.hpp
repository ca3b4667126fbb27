// The pieces of series_algebra's products (field_algebra.hpp) that spare a factor's repeated
// preparation. A product of two jets multiplies their models and, for each state component, a
// partial of one by the model of the other; a model is moved to its grid (grid_factor,
// chebyshev_model.hpp) or rounded to the partials' precision once, where multiply() would do it
// again for every product it enters. The balls are those multiply() makes: the same grids, the
// same integers, the same remainders computed in the same order.
#pragma once

#include <eulervop/certify/detail/chebyshev_model.hpp>

#include <arb.h>

namespace eulervop::detail {

// A jet's model on the grid of the value products, and its coefficients rounded as
// multiply_constant() rounds them for the partials (where the other factor's partial is a signed
// power of two, as a variable's is): each filled by the first product that needs it, shared by
// the jet's copies (a state component is a factor of several products).
struct grid_cache {
  bool ready = false, rounded_ready = false;
  grid_factor g;
  chebyshev_model rounded;  // the coefficients only
};

// f on the grid `bits` below its largest coefficient, from the cache where it is there.
inline const grid_factor& on_grid(grid_cache& c, const chebyshev_model& f, slong bits) {
  if (!c.ready || c.g.bits != bits) c.g.set(f, bits);
  c.ready = true;
  return c.g;
}

// f's coefficients rounded to bits + 64 (multiply_constant()'s rounding), from the cache where
// they are there (the cache serves one `bits`: the partials').
inline const chebyshev_model& rounded_on(grid_cache& c, const chebyshev_model& f, slong bits) {
  if (!c.rounded_ready) {
    c.rounded.reserve_length(f.length());
    for (slong k = 0; k < f.length(); ++k) arb_set_round(c.rounded.coeff(k), f.coeff(k), bits + 64);
  }
  c.rounded_ready = true;
  return c.rounded;
}

// A model on the partials' grid, moved by the first partial product of a jet product that takes it.
struct partial_factor {
  bool ready = false;
  grid_factor g;
};

// out = d m (m_first: m d) as multiply(out, ., ., bits) makes it: m kept on its grid in f for the
// other partials of the product, and, where d is a signed power of two, m's rounding taken from
// its jet's cache c (if any). True where out is a scaling's result (its coefficients rounded to
// bits + 64) or zero.
inline bool partial_product(chebyshev_model& out, const chebyshev_model& d, const chebyshev_model& m, grid_cache* c,
                            partial_factor& f, bool m_first, slong bits) {
  if (c && takes_grid(m) && d.length() == 1 && mag_is_zero(d.remainder())) {
    const arf_struct* x = arb_midref(d.coeff(0));
    if (arb_is_exact(d.coeff(0)) && !arf_is_zero(x) && arf_is_finite(x) && arf_bits(x) == 1) {
      // multiply_constant()'s rounding (once per jet) and scaling.
      const slong e = arf_abs_bound_lt_2exp_si(x) - 1;
      const chebyshev_model& r = rounded_on(*c, m, bits);
      out.reserve_length(r.length());
      for (slong k = 0; k < r.length(); ++k) {
        if (e == 0)  // the same ball, without the exponent's arithmetic
          arb_set(out.coeff(k), r.coeff(k));
        else
          arb_mul_2exp_si(out.coeff(k), r.coeff(k), e);
        if (arf_sgn(x) < 0) arb_neg(out.coeff(k), out.coeff(k));
      }
      mag_mul_2exp_si(out.remainder(), m.remainder(), e);
      return true;
    }
  }
  if (!takes_grid(d) || !takes_grid(m)) {  // a scaling (multiply_constant()) or zero
    if (m_first) multiply(out, m, d, bits); else multiply(out, d, m, bits);
    return true;
  }
  if (!f.ready) f.g.set(m, bits);
  f.ready = true;
  thread_local grid_factor gd;
  gd.set(d, bits);
  if (m_first) multiply_grids(out, f.g, gd); else multiply_grids(out, gd, f.g);
  return false;
}

}  // namespace eulervop::detail
