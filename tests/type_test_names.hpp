// GoogleTest name generators for the typed suites (the third argument of TYPED_TEST_SUITE), shared
// by every test file with one. Without them a typed test is named by its index and listed with the
// full type, which for quad and MPFR spells out boost::multiprecision's backend templates;
// with them it reads as "Elliptic/quad.CompleteIntegralsAgainstBoostMpfr".
#pragma once

#include <eulervop/core/scalar.hpp>

#include <string>
#include <type_traits>

// A scalar type by the name the command line gives its precision: double, quad, mpfr.
struct scalar_test_names {
  template <class T>
  static std::string GetName(int) {
    if constexpr (std::is_same_v<T, double>) return "double";
    else if constexpr (std::is_same_v<T, eulervop::quad>) return "quad";
    else if constexpr (std::is_same_v<T, eulervop::mpfr_real>) return "mpfr";
    else static_assert(sizeof(T) == 0, "scalar_test_names: give this scalar type a name");
  }
};

// A Runge-Kutta tableau or embedded pair by its method name, the one the command line and the
// reports use: rk4, rkf45, dp45, rk8, dop853.
struct method_test_names {
  template <class Method>
  static std::string GetName(int) {
    return std::string(Method::name);
  }
};
