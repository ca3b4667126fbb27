// Scene, problems() and scene_template(): scenes from files, shipped names, TOML text and dicts.
#include "module.hpp"

#include "commands/scene_template/scene_template_command.hpp"
#include "messages.hpp"

#include <pybind11/stl.h>

#include <fmt/format.h>
#include <toml++/toml.h>

#include <cmath>
#include <sstream>
#include <string>

namespace eulervop::python {

std::string py_scene::form() const {
  if (parsed.is_coefficient_form()) return "coefficient";
  return parsed.is_physical() ? "physical" : "normalized";
}

std::optional<std::string> path_of(const py::object& o) {
  if (py::isinstance<py::str>(o)) return o.cast<std::string>();
  if (py::hasattr(o, "__fspath__")) return py::str(py::module_::import("os").attr("fspath")(o)).cast<std::string>();
  return std::nullopt;
}

namespace {

py_scene scene_load(const std::string& path) {
  app::scene s = eulervop::scene::load_scene_file(path);
  std::string file = s.origin;  // a shipped scene's name resolved to its file
  return {std::move(s), std::move(file)};
}

// A scene made from text: named in messages by its name, "(from TOML text)".
py_scene scene_from_text(const std::string& text, const std::string& how) {
  app::scene s = eulervop::scene::parse_scene(text, "<" + how + ">");
  s.origin = fmt::format("{} (from {})", s.name, how);
  return {std::move(s), std::nullopt};
}

// ---- dicts and TOML ------------------------------------------------------------------------------
//
// A dict is written as TOML text (every table inline, which TOML allows at any depth) and read as
// any scene is. A float is written as its shortest round-trip text, the decimal a user means by
// 0.1 (toml++'s own writer gives 17 digits here, 0.10000000000000001); a string goes through
// toml++'s writer, which quotes and escapes it.

void write_value(std::ostream& out, const py::handle& v, const std::string& where);

void write_key(std::ostream& out, const std::string& key) {
  const bool bare = !key.empty() && key.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-") ==
                                        std::string::npos;
  if (bare) out << key;
  else out << toml::value<std::string>(key);
}

void write_float(std::ostream& out, double x, const std::string& where) {
  if (!std::isfinite(x)) throw py::value_error(fmt::format("{} = {}: not finite", where, x));
  std::string text = fmt::format("{}", x);
  if (text.find_first_of(".e") == std::string::npos) text += ".0";
  out << text;
}

void write_value(std::ostream& out, const py::handle& v, const std::string& where) {
  const auto object = py::reinterpret_borrow<py::object>(v);
  if (py::isinstance<py::dict>(v)) {
    out << "{ ";
    bool first = true;
    for (const auto& [key, value] : py::reinterpret_borrow<py::dict>(v)) {
      if (!py::isinstance<py::str>(key))
        throw py::value_error(fmt::format("{}: key {} is not a str", where.empty() ? "the dict" : where, short_repr(key)));
      const std::string k = key.cast<std::string>();
      out << (first ? "" : ", ");
      first = false;
      write_key(out, k);
      out << " = ";
      write_value(out, value, where.empty() ? k : where + "." + k);
    }
    out << (first ? "}" : " }");
  } else if (py::isinstance<py::bool_>(v)) {
    out << (v.cast<bool>() ? "true" : "false");
  } else if (py::isinstance<py::str>(v)) {
    out << toml::value<std::string>(v.cast<std::string>());
  } else if (py::hasattr(v, "__index__")) {
    out << object.attr("__index__")().cast<long long>();
  } else if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v) || py::isinstance<py::array>(v)) {
    out << "[";
    std::size_t i = 0;
    for (const py::handle item : object) {
      out << (i ? ", " : "");
      write_value(out, item, fmt::format("{}[{}]", where, i++));
    }
    out << "]";
  } else if (py::isinstance<py::float_>(v) || py::hasattr(v, "__float__")) {
    write_float(out, object.attr("__float__")().cast<double>(), where);
  } else {
    throw py::value_error(fmt::format("{} = {}: not a TOML value (a dict, list, str, bool, int or float)", where,
                                      short_repr(v)));
  }
}

py::object python_of(const toml::node& n) {
  if (const auto* t = n.as_table()) {
    py::dict d;
    for (const auto& [key, value] : *t) d[py::str(std::string(key.str()))] = python_of(value);
    return std::move(d);
  }
  if (const auto* a = n.as_array()) {
    py::list l;
    for (const auto& value : *a) l.append(python_of(value));
    return std::move(l);
  }
  if (const auto* s = n.as_string()) return py::str(s->get());
  if (const auto* i = n.as_integer()) return py::int_(i->get());
  if (const auto* f = n.as_floating_point()) return py::float_(f->get());
  if (const auto* b = n.as_boolean()) return py::bool_(b->get());
  throw py::value_error("a scene value of a type a scene does not use (a date or time)");
}

py_scene scene_from_dict(const py::dict& d) {
  std::ostringstream text;
  for (const auto& [key, value] : d) {
    if (!py::isinstance<py::str>(key)) throw py::value_error(fmt::format("the dict: key {} is not a str", short_repr(key)));
    write_key(text, key.cast<std::string>());
    text << " = ";
    write_value(text, value, key.cast<std::string>());
    text << "\n";
  }
  return scene_from_text(text.str(), "a dict");
}

py::dict scene_as_dict(const py_scene& s) {
  return python_of(toml::parse(s.parsed.source_text)).cast<py::dict>();
}

py::dict problems() {
  py::dict out;
  for (const auto& [name, path] : eulervop::scene::shipped_scenes()) out[py::str(name)] = path.string();
  return out;
}

}  // namespace

py_scene scene_of(const py::object& o) {
  if (py::isinstance<py_scene>(o)) return o.cast<py_scene>();
  if (const auto path = path_of(o)) return scene_load(*path);
  throw py::type_error(fmt::format("expected an eulervop.Scene, a scene file's path or a shipped scene's name; got {}",
                                   short_repr(o)));
}

void bind_scenes(py::module_& m) {
  py::class_<py_scene>(m, "Scene", "A parsed, validated scene (docs/scenes.md).")
      .def_static("load", &scene_load, py::arg("path"),
                  "Scene.load(path) -> Scene\n\nReads and validates the scene file at `path`, or the shipped scene "
                  "of that name (problems()).")
      .def_static("from_toml", [](const std::string& text) { return scene_from_text(text, "TOML text"); },
                  py::arg("text"), "Scene.from_toml(text) -> Scene\n\nParses and validates a scene given as TOML text.")
      .def_static("from_dict", &scene_from_dict, py::arg("scene"),
                  "Scene.from_dict(scene) -> Scene\n\nA scene from a dict of the TOML's tables (as as_dict() gives "
                  "them): floats are written as their shortest text, the decimal 0.1 for 0.1.")
      .def("as_dict", &scene_as_dict, "The scene's TOML as a dict, to change and give to Scene.from_dict.")
      .def_property_readonly("name", [](const py_scene& s) { return s.parsed.name; }, "The scene's name.")
      .def_property_readonly("form", &py_scene::form, "'normalized', 'physical' or 'coefficient'.")
      .def_property_readonly("text", [](const py_scene& s) { return s.parsed.source_text; }, "The TOML text.")
      .def_property_readonly("path", [](const py_scene& s) { return s.path; }, "The file it was read from, or None.")
      .def("__repr__", [](const py_scene& s) { return fmt::format("<eulervop.Scene {} ({})>", s.parsed.name, s.form()); });

  m.def("problems", &problems,
        "problems() -> dict\n\nThe shipped scenes by name (e.g. 'sciml-rigid-body') to their files. Every function "
        "that takes a scene takes these names too.");
  m.def("scene_template", [](const std::string& form) { return std::string(app::scene_template_text(form)); },
        py::arg("form") = "physical",
        "scene_template(form='physical') -> str\n\nAn annotated scene of that form ('normalized', 'physical' or "
        "'coefficient'), every key commented, as `eulervop scene-template` prints it: Scene.from_toml takes it as it "
        "is.");
}

}  // namespace eulervop::python
