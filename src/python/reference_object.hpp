// The Python Reference: a run held in memory and its columns as NumPy arrays (reference.cpp).
#pragma once

#include "commands/reference/held_reference.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace eulervop::python {

namespace py = pybind11;

struct py_reference {
  std::shared_ptr<const app::held_reference> held;
  py::array_t<double> t, y;
  std::vector<std::string> columns, all_columns, normalized_columns;
  std::optional<py::array_t<double>> normalized, radius, radius_omega, radius_q;
  py::dict meta;
  mutable std::optional<py::object> decimal_cache, csv_cache;  // made on first use
};

py_reference reference_of(std::shared_ptr<const app::held_reference> held);

}  // namespace eulervop::python
