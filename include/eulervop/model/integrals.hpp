// Eq. 7: the integrals c1^2 = Omega1^2 + Omega2^2 and c2^2 = Omega2^2 + Omega3^2 of Eq. 5,
// constant when G = 0.
#pragma once

#include <eulervop/core/vec3.hpp>

namespace eulervop {

template <class T>
T c1_squared(const vec3<T>& Om) { return Om[0] * Om[0] + Om[1] * Om[1]; }
template <class T>
T c2_squared(const vec3<T>& Om) { return Om[1] * Om[1] + Om[2] * Om[2]; }

}  // namespace eulervop
