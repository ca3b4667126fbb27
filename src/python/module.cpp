// The module's entry: exceptions, Ctrl-C and the progress of long runs (module.hpp has the map).
//
// The GIL is released while the library runs. Ctrl-C is noticed between segments of the
// integration (a few per second at the least) and raises KeyboardInterrupt. Bad input raises
// ValueError with the library's one-line message in Python's terms (messages.hpp), a numerical
// failure eulervop.NumericalFailure (an ArithmeticError) with the time and the cause. A run that
// will take long says so once, as a warning with its estimate, after a few seconds. The module
// writes no file.
#include "module.hpp"

#include "compute/progress.hpp"

#include <eulervop/core/numerical_failure.hpp>

#include <fmt/format.h>

#include <chrono>
#include <memory>
#include <string>

namespace eulervop::python {

namespace {

// Thrown by the progress display when Ctrl-C was pressed; becomes KeyboardInterrupt.
struct interrupted {};

// A duration as a reader wants it: seconds, minutes, hours or days.
std::string duration_text(double seconds) {
  if (seconds < 120) return fmt::format("{:.0f} s", seconds);
  if (seconds < 7200) return fmt::format("{:.0f} min", seconds / 60);
  if (seconds < 2 * 86400) return fmt::format("{:.1f} h", seconds / 3600);
  if (seconds < 2 * 365.25 * 86400) return fmt::format("{:.0f} days", seconds / 86400);
  return fmt::format("{:.2g} years", seconds / (365.25 * 86400));
}

// The display the module installs for the library's progress: every 100 ms it takes the GIL to
// let Python see a pending signal, and once, after `warn_after` seconds, a run whose estimate is
// over `long_run` seconds is announced as a warning (the command line shows the same estimate on
// its progress line).
class python_progress final : public app::progress_display {
 public:
  python_progress(std::string label, double total, app::progress_unit unit)
      : label_(std::move(label)), total_(total), unit_(std::move(unit)) {}

  void update(double reached, std::size_t) override {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) {
      PyErr_Clear();
      throw interrupted{};
    }
    if (!warned_ && elapsed > warn_after && reached > 0 && total_ > 0) {
      warned_ = true;
      const double estimate = elapsed * total_ / reached;
      if (estimate > long_run) warn(reached, elapsed, estimate);
    }
  }
  void clear() override {}

 private:
  static constexpr double warn_after = 2, long_run = 60;

  void warn(double reached, double elapsed, double estimate) const {
    const std::string unit = unit_.unit.empty() ? "" : " " + unit_.unit;
    const std::string message = fmt::format(
        "eulervop {}: {} = {:.4g}{} of {:.4g}{} after {:.1f} s: about {} in all at this pace (Ctrl-C stops it)",
        label_, unit_.name, reached, unit, total_, unit, elapsed, duration_text(estimate));
    if (PyErr_WarnEx(PyExc_RuntimeWarning, message.c_str(), 1) != 0) throw py::error_already_set();
  }

  std::string label_;
  double total_;
  app::progress_unit unit_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now(), last_ = start_;
  bool warned_ = false;
};

// eulervop.NumericalFailure: created once and never freed (it lives as long as the interpreter).
PyObject* numerical_failure_type = nullptr;

}  // namespace

}  // namespace eulervop::python

PYBIND11_MODULE(eulervop, m) {
  namespace python = eulervop::python;
  m.doc() =
      "eulervop: high-precision reference solutions of Euler's rigid-body equations, and an oracle "
      "for other integrators' trajectories (docs/python.md).";
  m.attr("__version__") = EULERVOP_VERSION;
  python::numerical_failure_type = PyErr_NewExceptionWithDoc(
      "eulervop.NumericalFailure",
      "The reference integrator gave up; the message gives the time (in the scene's own units first) and the cause.",
      PyExc_ArithmeticError, nullptr);
  m.attr("NumericalFailure") = pybind11::handle(python::numerical_failure_type);
  pybind11::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const python::interrupted&) {
      PyErr_SetNone(PyExc_KeyboardInterrupt);
    } catch (const eulervop::scene::input_error& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const eulervop::numerical_failure& e) {
      PyErr_SetString(python::numerical_failure_type, e.what());
    }
  });
  eulervop::app::set_progress_display(
      [](const std::string& label, double total, const eulervop::app::progress_unit& unit) {
        return std::make_unique<python::python_progress>(label, total, unit);
      });
  python::bind_scenes(m);
  python::bind_reference(m);
  python::bind_check(m);
}
