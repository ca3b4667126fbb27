// The two-norm error of Eq. 20: e = sqrt(dOmega1^2 + dOmega2^2 + dOmega3^2), dOmega = Omega* - Omega,
// evaluated in the reference's scalar type so the reference's digits are not lost on the way.
#pragma once

#include <eulervop/model/euler_problem.hpp>
#include <eulervop/core/scalar_traits.hpp>

#include <cmath>

namespace eulervop {

// Eq. 20 between a reference state (in T) and a state of another precision U (converted
// exactly into T: double and quad values are exact in every wider type).
template <scalar T, scalar U>
T eq20_error(const vec3<T>& reference, const vec3<U>& state) {
  using std::sqrt;
  T sum = 0;
  for (int i = 0; i < 3; ++i) {
    const T d = reference[i] - convert<T>(state[i]);
    sum += d * d;
  }
  return sqrt(sum);
}

}  // namespace eulervop
