// The certificate module: run_certificate (run_certificate.hpp) of a scene (certified_reference.hpp),
// made in certificate_module_general.cpp. The program loads it only for --certify (built as
// eulervop_certificate.so, linked with Arb and FLINT); the Python module links it in.
#include "compute/certified_reference.hpp"
#include "compute/run_certificate.hpp"

#include <eulervop/model/wide_formula_cells.hpp>
#include <eulervop/scene/scene_certification_problem.hpp>

// The certificate's problems (certificate_module_general.cpp), compiled here to share out the
// module's work between its units.
namespace eulervop::scene {
EULERVOP_CERTIFICATION_PROBLEM_CELL(, double)
EULERVOP_CERTIFICATION_PROBLEM_CELL(, quad)
EULERVOP_CERTIFICATION_PROBLEM_CELL(, mpfr_real)
}  // namespace eulervop::scene

namespace eulervop::app {
namespace {

run_certificate* make_module_certificate(const scene& s, const eulervop::precision& p, unsigned workers) {
  return make_general_certificate(s, p, workers).release();
}

// Linked into a program or module, the certificate is there from the start.
[[maybe_unused]] const bool registered = (link_run_certificate(&make_module_certificate), true);

}  // namespace
}  // namespace eulervop::app

// What the program looks up after loading the module (run_certificate.cpp).
extern "C" [[gnu::visibility("default")]] eulervop::app::run_certificate* eulervop_make_run_certificate(
    const eulervop::scene::scene& s, const eulervop::precision& p, unsigned workers) {
  return eulervop::app::make_module_certificate(s, p, workers);
}
