// Four doubles as one GCC/Clang vector: one AVX register in code compiled for AVX, two SSE
// registers otherwise, with element-wise IEEE arithmetic either way (each lane rounds exactly as
// the scalar code would). For the correction's row products (picard_correction.hpp) and the
// double-double product's rows side by side (double_double_matvec.hpp). Loaded with memcpy
// where used: a function returning one would take another ABI with AVX than without.
#pragma once

namespace eulervop::detail {

using double4 = double __attribute__((vector_size(32)));

}  // namespace eulervop::detail
