// The compiled kernels: which instantiations of the heavy templates the library eulervop::kernels
// holds, one translation unit per cell (src/kernels/CMakeLists.txt reads the X(...) lines of the
// two lists below and writes the units; docs/design.md, "The compiled kernels").
//
// The cells are the products of the lists:
//   - the reference (reference/integrate.hpp): every scalar x every torque, rates only; and again
//     with the attitude beside the rates; and every scalar for the rates and attitude coupled by
//     a torque of the attitude (model/coupled_problem.hpp);
//   - the double-precision runs (runs/comparison_run.hpp): the two torque types of the runs x
//     {euler, vop, vop-theta} x {fixed, adaptive} x {rates only, with attitude}, in double, one
//     unit each. Every torque of time or state runs as the one varying_torque, whose kind is data
//     (runs/varying_torque.hpp), so a new torque kind adds no run cells.
// Adding a scalar or a torque is one line here. With EULERVOP_COMPILED_KERNELS defined (linking
// eulervop::kernels defines it), the headers above declare their cells `extern`, so that a unit
// that includes them never instantiates what the library already has.
#pragma once

// X(scalar): double, quad (core/scalar.hpp), mpfr_real.
#define EULERVOP_KERNEL_SCALARS(X, ...) \
  X(double, __VA_ARGS__)                \
  X(quad, __VA_ARGS__)                  \
  X(mpfr_real, __VA_ARGS__)

// X(torque template): model/torque.hpp, model/expression_torque.hpp.
#define EULERVOP_KERNEL_TORQUES(X, ...) \
  X(constant_torque, __VA_ARGS__)       \
  X(time_torque, __VA_ARGS__)           \
  X(state_torque, __VA_ARGS__)

// X(torque template) of the double-precision runs: the paper's constant G, and every torque of
// time or state (runs/varying_torque.hpp).
#define EULERVOP_KERNEL_RUN_TORQUES(X, ...) \
  X(constant_torque, __VA_ARGS__)           \
  X(varying_torque, __VA_ARGS__)

// Every (scalar, torque) pair: CELL(T, G) for each.
#define EULERVOP_KERNEL_PAIR_(G, CELL) EULERVOP_KERNEL_SCALARS(EULERVOP_KERNEL_PAIR_T_, CELL, G)
#define EULERVOP_KERNEL_PAIR_T_(T, CELL, G) CELL(T, G)
#define EULERVOP_FOR_EACH_SCALAR_AND_TORQUE(CELL) EULERVOP_KERNEL_TORQUES(EULERVOP_KERNEL_PAIR_, CELL)
