// The phase of the secular-free elements, theta = pi u / (2K) (docs/vop-strategies.md): its rate
// per unit u, and its reduction to one turn.
#pragma once

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/special/elliptic.hpp>

#include <boost/math/constants/constants.hpp>

#include <cmath>

namespace eulervop {

// pi / (2 K(k)) = a_N, the AGM mean (K = pi / (2 a_N), A&S 17.6.3): the rate of
// theta = pi u / (2K) per unit u, without rounding K or pi.
template <scalar T>
const T& pi_over_2K(const elliptic_modulus<T>& m) {
  return m.a(m.levels());
}

// Keeps a phase theta in [-pi, pi): subtracts whole turns 2 pi j and adds j to `turns`.
// For |j| = 1 (the only case in a run) theta - 2 pi is exact (Sterbenz), so the reduced phase
// carries no rounding beyond its own ulp; the theta right-hand side has period 2 pi exactly in
// the value of pi used here, so nothing drifts.
template <scalar T>
void reduce_phase(T& theta, long long& turns) {
  using std::floor;
  const T pi = boost::math::constants::pi<T>();
  if (theta >= -pi && theta < pi) return;
  const T j = floor((theta + pi) / (2 * pi));
  theta -= j * (2 * pi);
  if (theta >= pi) {  // rounding at the edge
    theta -= 2 * pi;
    turns += 1;
  } else if (theta < -pi) {
    theta += 2 * pi;
    turns -= 1;
  }
  turns += static_cast<long long>(static_cast<double>(j));
}

}  // namespace eulervop
