// The three components of a rate, torque or body-frame vector, in any number type.
#pragma once

#include <array>

namespace eulervop {

template <class T>
using vec3 = std::array<T, 3>;

}  // namespace eulervop
