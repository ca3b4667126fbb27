// The conversions of a scene into problems (scene/scene_problem.hpp) in quad and MPFR, declared
// extern for the units that link the compiled kernels, which compile them once. A separate header,
// as the types of quad and MPFR (core/scalar.hpp) must not reach the double-only units that
// convert a scene.
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/scene/scene_problem.hpp>

#ifdef EULERVOP_COMPILED_KERNELS
EULERVOP_SCENE_PROBLEM_CELL(extern, eulervop::quad)
EULERVOP_SCENE_PROBLEM_CELL(extern, eulervop::mpfr_real)
#endif
