// The Python module `eulervop` (docs/python.md): the library bound with NumPy arrays in and out.
// One file per part: scenes.cpp (Scene, problems, templates), reference.cpp (reference,
// Reference), check.cpp (check, CheckResult), messages.cpp (the library's messages in Python's
// terms), keywords.cpp (one line for a wrong keyword), module.cpp (errors, Ctrl-C, progress).
#pragma once

#include "compute/scene_library.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <optional>
#include <string>
#include <vector>

namespace eulervop::python {

namespace py = pybind11;

using float64_array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// A parsed, validated scene, and the file it came from.
struct py_scene {
  app::scene parsed;
  std::optional<std::string> path;

  std::string form() const;
};

// A scene argument: a Scene, a path to a scene file, or a shipped scene's name.
py_scene scene_of(const py::object& o);
// The path a caller gave (a str or an os.PathLike), if `o` is one.
std::optional<std::string> path_of(const py::object& o);

void bind_scenes(py::module_& m);
void bind_reference(py::module_& m);
void bind_check(py::module_& m);

// What a function's parameter takes, for a one-line message when a call does not fit.
enum class takes { anything, number, integer, boolean, text, texts };
struct parameter {
  const char* name;
  takes kind = takes::anything;
  const char* shown = "";   // what it takes, in words: "a float or None"
  bool required = false;
};

// Exposes the function bound as "_<name>" (with pybind11's keywords and defaults) as `name`: the
// same call, but one that does not fit its parameters raises a one-line TypeError naming the
// keyword and what it takes (did you mean tol=?), not pybind11's listing of every overload and
// argument. `doc` is the docstring, its first line the signature. Checks at import that
// `parameters` are the bound function's own.
void def_checked(py::module_& m, const char* name, std::vector<parameter> parameters, const char* doc);

}  // namespace eulervop::python
