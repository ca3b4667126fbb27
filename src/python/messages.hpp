// The library's messages in the caller's terms. The program's input errors name flags
// (`--attitude-tol 1e-06`) and the rows of a file ("trajectory FILE: line 7"); a caller of the
// module gave keywords and arrays. So every input_error raised under a call is rewritten: each
// flag as its keyword (`attitude_tol=1e-06`), the arrays' rows as t[i], a Reference as "the
// Reference", a scene given as an object by its name.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace eulervop::python {

namespace py = pybind11;

void replace_all(std::string& s, std::string_view from, std::string_view to);

// A value as Python shows it.
std::string py_repr(const py::handle& o);
std::string py_repr(double x);
// What a caller passed where numbers were due, as Python shows it, cut to one short line.
std::string short_repr(const py::handle& o);
// A shape as NumPy prints it: (), (n,), (n, m).
std::string shape_text(const py::array& a);

// A command's flag and the keyword that set it.
struct keyword {
  std::string flag;                 // "--attitude-tol"
  std::string name;                 // "attitude_tol"
  std::optional<std::string> text;  // the flag's value as the library was given it
  std::string shown;                // that value as Python shows it
  bool is_switch = false;           // a bool keyword: --ignore-attitude is ignore_attitude=True
};

// A keyword with no value to quote: the messages name it as one to give.
keyword plain_keyword(const std::string& flag, const std::string& name);
// A number keyword: the text the library is given (the double's shortest round-trip text, the
// decimal a user types) and its value as Python shows it.
keyword number_keyword(const std::string& flag, const std::string& name, const std::optional<double>& x);
keyword text_keyword(const std::string& flag, const std::string& name, const std::optional<std::string>& x);
keyword switch_keyword(const std::string& flag, const std::string& name);

// The trajectory's rows when they are arrays: how the library names them, and what the caller
// called them.
inline constexpr std::string_view arrays_name = "<t and y>";

struct python_terms {
  std::vector<keyword> keywords;
  bool arrays = false;                    // the trajectory is t and y
  std::string header;                     // its columns: "columns=[...]" or "t and y (read as ...)"
  std::string y_named;                    // y with its shape or its columns
  std::string q_place;                    // where q0..q3 are in y: "y[:, 3:7]"
  std::string names_wanted;               // the names the reference is compared by, for columns=
  const double* times = nullptr;          // t, to show a row's time
  std::size_t rows = 0;
  std::optional<std::string> scene_origin, scene_name;  // a scene given as an object

  std::string operator()(std::string message) const;

 private:
  std::string row_message(std::size_t line, std::string rest) const;
};

// Runs `run`; an input_error it throws is rethrown in the caller's terms.
template <class Run>
auto in_python_terms(const python_terms& terms, Run&& run) -> decltype(run());

// The same with the GIL released, for the library's long work.
template <class Run>
auto run_in_python_terms(const python_terms& terms, Run&& run) -> decltype(run());

}  // namespace eulervop::python

#include <eulervop/scene/input_error.hpp>

namespace eulervop::python {

template <class Run>
auto in_python_terms(const python_terms& terms, Run&& run) -> decltype(run()) {
  try {
    return run();
  } catch (const eulervop::scene::input_error& e) {
    throw eulervop::scene::input_error(terms(e.what()));
  }
}

template <class Run>
auto run_in_python_terms(const python_terms& terms, Run&& run) -> decltype(run()) {
  return in_python_terms(terms, [&] {
    const py::gil_scoped_release nogil;
    return run();
  });
}

}  // namespace eulervop::python
