// The formula types (model/expression_torque.hpp) in quad and MPFR, declared extern for the units
// that link the compiled kernels (kernels/cells.hpp), which compile them once. A separate header,
// as the types of quad and MPFR (core/scalar.hpp) must not reach the double-only units that
// include the formulas; double's are declared extern in expression_torque.hpp itself.
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/model/expression_torque.hpp>

#ifdef EULERVOP_COMPILED_KERNELS
namespace eulervop {
EULERVOP_FORMULA_CELL(extern, quad)
EULERVOP_FORMULA_CELL(extern, mpfr_real)
}  // namespace eulervop
#endif
