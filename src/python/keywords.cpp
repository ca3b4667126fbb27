// def_checked: a call that does not fit a function's parameters as one line (module.hpp).
#include "module.hpp"

#include "messages.hpp"

#include <pybind11/stl.h>

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace eulervop::python {

namespace {

bool fits(const py::handle& v, takes kind) {
  if (v.is_none()) return kind != takes::boolean;
  const auto is_number = [](const py::handle& x) {
    return !py::isinstance<py::str>(x) && !py::isinstance<py::bool_>(x) &&
           (py::isinstance<py::float_>(x) || py::isinstance<py::int_>(x) || py::hasattr(x, "__float__"));
  };
  switch (kind) {
    case takes::anything: return true;
    case takes::number: return is_number(v);
    case takes::integer: return !py::isinstance<py::bool_>(v) && py::hasattr(v, "__index__");
    case takes::boolean: return py::isinstance<py::bool_>(v) || py::hasattr(v, "__bool__") && !is_number(v);
    case takes::text: return py::isinstance<py::str>(v);
    case takes::texts:
      if (!py::isinstance<py::list>(v) && !py::isinstance<py::tuple>(v)) return false;
      for (const py::handle x : v)
        if (!py::isinstance<py::str>(x)) return false;
      return true;
  }
  return true;
}

std::string names_of(const std::vector<parameter>& ps) {
  std::string out;
  for (const parameter& p : ps) out += (out.empty() ? "" : ", ") + std::string(p.name);
  return out;
}

// Why a call of `name` with `args` and `kwargs` does not fit `ps`, in one line.
std::string misfit(const std::string& name, const std::vector<parameter>& ps, const py::args& args,
                   const py::kwargs& kwargs) {
  const std::string f = name + "()";
  if (args.size() > ps.size())
    return fmt::format("{} takes at most {} positional arguments ({} given)", f, ps.size(), args.size());
  std::vector<std::string> names;
  for (const parameter& p : ps) names.emplace_back(p.name);
  for (const auto& [key, value] : kwargs) {
    const std::string k = py::str(key);
    const auto at = std::find(names.begin(), names.end(), k);
    if (at == names.end()) {
      const py::list close = py::module_::import("difflib").attr("get_close_matches")(k, py::cast(names), 1, 0.5);
      return fmt::format("{}: no keyword {}={} (its keywords: {})", f, k,
                         close.empty() ? "" : fmt::format("; did you mean {}=?", close[0].cast<std::string>()),
                         names_of(ps));
    }
    if (static_cast<std::size_t>(at - names.begin()) < args.size())
      return fmt::format("{}: {} given twice, by position and as {}=", f, k, k);
  }
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const bool positional = i < args.size();
    const bool keyword = kwargs.contains(ps[i].name);
    if (!positional && !keyword) {
      if (ps[i].required) return fmt::format("{}: {} is missing ({})", f, ps[i].name, ps[i].shown);
      continue;
    }
    const py::object v = positional ? py::object(args[i]) : py::object(kwargs[ps[i].name]);
    if (!fits(v, ps[i].kind))
      return fmt::format("{}: {}={}: expected {}", f, ps[i].name, short_repr(v), ps[i].shown);
  }
  return fmt::format("{}: the arguments do not fit ({})", f, names_of(ps));
}

// The parameter names of pybind11's own signature line: "_check(against: object, t: ..." .
std::vector<std::string> bound_names(const py::object& f) {
  const std::string doc = py::str(f.attr("__doc__"));
  const std::size_t open = doc.find('('), close = doc.find(") ->");
  std::vector<std::string> names;
  if (open == std::string::npos || close == std::string::npos) return names;
  std::size_t at = open + 1;
  while (at < close) {
    const std::size_t colon = doc.find(':', at);
    if (colon == std::string::npos || colon > close) break;
    names.push_back(doc.substr(at, colon - at));
    // skip to the next top-level ", " (defaults and types hold no comma here but for brackets)
    int depth = 0;
    std::size_t k = colon;
    for (; k < close; ++k) {
      const char c = doc[k];
      if (c == '[' || c == '(') ++depth;
      if (c == ']' || c == ')') --depth;
      if (c == ',' && depth == 0) break;
    }
    at = k + 2;
  }
  return names;
}

}  // namespace

void def_checked(py::module_& m, const char* name, std::vector<parameter> parameters, const char* doc) {
  const py::object impl = m.attr(("_" + std::string(name)).c_str());
  std::vector<std::string> expected;
  for (const parameter& p : parameters) expected.emplace_back(p.name);
  if (bound_names(impl) != expected)
    throw std::logic_error(fmt::format("eulervop module: the parameters of {} are not {}", name, names_of(parameters)));
  py::options options;
  options.disable_function_signatures();
  const std::string function = name;
  m.def(
      name,
      [impl, parameters, function](const py::args& args, const py::kwargs& kwargs) -> py::object {
        try {
          return impl(*args, **kwargs);
        } catch (py::error_already_set& e) {
          if (!e.matches(PyExc_TypeError) ||
              std::string(py::str(e.value())).find("incompatible function arguments") == std::string::npos)
            throw;
          throw py::type_error(misfit(function, parameters, args, kwargs));
        }
      },
      doc);
}

}  // namespace eulervop::python
