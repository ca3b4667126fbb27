// Two doubles in one SSE register (GCC/Clang vector extension; element-wise IEEE arithmetic, so
// each lane rounds exactly as the scalar code would). Used where two polynomials share their
// argument (the kernels of special/jacobi_theta.hpp and special/detail/sincos_double.hpp); the
// reference's sweeps and double-double products use four lanes (reference/detail/double4.hpp).
#pragma once

#include <cstring>

namespace eulervop::detail {

using double2 = double __attribute__((vector_size(16)));

// The pair stored at p (two consecutive doubles).
inline double2 load2(const double* p) {
  double2 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

}  // namespace eulervop::detail
