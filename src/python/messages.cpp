#include "messages.hpp"

#include <pybind11/numpy.h>

#include <fmt/format.h>

#include <cctype>

namespace eulervop::python {

void replace_all(std::string& s, std::string_view from, std::string_view to) {
  if (from.empty()) return;
  for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
}

std::string py_repr(const py::handle& o) { return py::repr(o).cast<std::string>(); }
std::string py_repr(double x) { return py_repr(py::float_(x)); }

std::string short_repr(const py::handle& o) {
  std::string s = py_repr(o);
  replace_all(s, "\n", " ");
  return s.size() > 60 ? s.substr(0, 57) + "..." : s;
}

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

keyword plain_keyword(const std::string& flag, const std::string& name) {
  keyword k;
  k.flag = flag;
  k.name = name;
  return k;
}

keyword number_keyword(const std::string& flag, const std::string& name, const std::optional<double>& x) {
  keyword k = plain_keyword(flag, name);
  if (x) k.text = fmt::format("{}", *x), k.shown = py_repr(*x);
  return k;
}

keyword text_keyword(const std::string& flag, const std::string& name, const std::optional<std::string>& x) {
  keyword k = plain_keyword(flag, name);
  if (x) k.text = *x, k.shown = py_repr(py::str(*x));
  return k;
}

keyword switch_keyword(const std::string& flag, const std::string& name) {
  keyword k = plain_keyword(flag, name);
  k.is_switch = true;
  return k;
}

namespace {

bool word_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_'; }

// Every mention of k.flag in `m` as the keyword: with its value where the message quotes it,
// alone where it heads a clause ("attitude_tol: required"), else as "tol=" (a keyword to give).
void put_keyword(std::string& m, const keyword& k) {
  for (std::size_t at = m.find(k.flag); at != std::string::npos; at = m.find(k.flag, at)) {
    std::size_t end = at + k.flag.size();
    if (end < m.size() && word_char(m[end])) {  // a longer flag: --tol in --tolerance
      at = end;
      continue;
    }
    std::string to;
    const auto followed_by = [&](const std::string& s) { return m.compare(end, s.size(), s) == 0; };
    if (k.text && followed_by(" " + *k.text) &&
        (end + 1 + k.text->size() == m.size() || !word_char(m[end + 1 + k.text->size()]))) {
      to = k.name + "=" + k.shown;
      end += 1 + k.text->size();
    } else if (k.flag == "--attitude-tol" && followed_by(" RAD")) {
      to = k.name + "=<radians>";
      end += 4;
    } else if (k.is_switch) {
      to = k.name + "=True";
    } else if (followed_by(":") || followed_by(" and ")) {
      to = k.name;
    } else {
      to = k.name + "=";
    }
    m.replace(at, end - at, to);
    at += to.size();
  }
}

// A sample-time message's tail about the Reference: its lines are those of a CSV the caller never
// saw, so the nearest samples are named by their times alone.
std::string reference_tail(std::string tail) {
  const std::string reference = "the Reference";
  if (!tail.starts_with(reference)) return tail;
  for (std::size_t p = tail.find(" (line "); p != std::string::npos; p = tail.find(" (line ", p)) {
    const std::size_t close = tail.find(')', p);
    if (close == std::string::npos) break;
    tail.erase(p, close + 1 - p);
  }
  tail.insert(reference.size(), " (ref.t)");
  return tail;
}

}  // namespace

std::string python_terms::row_message(std::size_t line, std::string rest) const {
  if (line <= 1) {  // the header: the column names
    const std::string q = "columns q0..q3: ";
    if (rest.starts_with(q) && rest.find(" has no attitude") != std::string::npos)
      return fmt::format("y has q0..q3 in {}, but {}; give the rates alone", q_place, rest.substr(q.size()));
    replace_all(rest, "the header has no column", "no column");
    // The library's hint is a --columns map of a file's names; here the names are columns=.
    if (const std::size_t hint = rest.find("; the header has "); hint != std::string::npos)
      rest = rest.substr(0, hint) + "; name t's column, then each of y's, in columns= (" + names_wanted + ")";
    return header + ": " + rest;
  }
  const std::size_t row = line - 2;  // the header is line 1, row 0 line 2
  const std::string at = fmt::format("t[{}]", row) + (times && row < rows ? " = " + py_repr(times[row]) : "");
  const std::string sample = " is not a sample time of ";
  const std::size_t k = rest.find(sample);
  if (k == std::string::npos) return fmt::format("row {} of t and y ({}): {}", row, at, rest);
  return at + sample + reference_tail(rest.substr(k + sample.size()));
}

std::string python_terms::operator()(std::string m) const {
  if (arrays) {
    const std::string file = "trajectory " + std::string(arrays_name);
    const std::string at = file + ": line ";
    if (m.starts_with(at)) {
      std::size_t end = at.size(), line = 0;
      while (end < m.size() && std::isdigit(static_cast<unsigned char>(m[end]))) line = line * 10 + (m[end++] - '0');
      if (m.compare(end, 2, ": ") == 0) m = row_message(line, m.substr(end + 2));
    }
    replace_all(m, file + " has columns q0..q3", "y has q0..q3 in " + q_place);
    replace_all(m, file + " has no columns q0..q3", y_named + " has no columns q0..q3");
    replace_all(m, file, "t and y");
  }
  for (const keyword& k : keywords) put_keyword(m, k);
  return m;
}

}  // namespace eulervop::python
