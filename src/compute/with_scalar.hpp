// The one place that maps a precision named at run time ("double", "quad", "mpfr:BITS") to the
// scalar type the templated core computes in.
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/model/wide_formula_cells.hpp>
#include <eulervop/scene/wide_scene_problems.hpp>

#include <stdexcept>
#include <utility>

namespace eulervop::app {

// Calls f(T{}) with T = double, quad or mpfr_real for p, inside an mpfr_precision_scope of
// p.bits for MPFR (the calling thread's default precision; a worker thread that makes MPFR
// values must open its own scope, with mpfr_scope_on_this_thread).
template <class F>
decltype(auto) with_scalar(const eulervop::precision& p, F&& f) {
  switch (p.type) {
    case eulervop::precision::kind::binary64: return std::forward<F>(f)(double{});
    case eulervop::precision::kind::binary128: return std::forward<F>(f)(quad{});
    case eulervop::precision::kind::mpfr: break;
  }
  const mpfr_precision_scope scope(p.bits);
  return std::forward<F>(f)(mpfr_real{});
}

// Runs f() with the MPFR default precision of p on this thread when p is an MPFR precision.
template <class F>
decltype(auto) mpfr_scope_on_this_thread(const eulervop::precision& p, F&& f) {
  if (p.type == eulervop::precision::kind::mpfr) {
    const mpfr_precision_scope scope(p.bits);
    return std::forward<F>(f)();
  }
  return std::forward<F>(f)();
}

}  // namespace eulervop::app
