// The certificate module: run_certificate (run_certificate.hpp) over certificate_of_run
// (certified_reference.hpp), in a unit of its own. The program loads it only for --certify
// (built as eulervop_certificate.so, linked with Arb, FLINT and MPFI); the Python module links it in.
#include "compute/certified_reference.hpp"
#include "compute/run_certificate.hpp"

#include <eulervop/model/wide_formula_cells.hpp>

#include <memory>
#include <utility>

namespace eulervop::app {
namespace {

class module_certificate final : public run_certificate {
 public:
  module_certificate(const scene& s, const eulervop::precision& p, unsigned workers) : body_(s, p, workers) {}

  void add_segment(const chebyshev_segment<double, 3>& seg, const std::vector<double>& nodes) override {
    body_.add_segment(seg, nodes);
  }
  void add_segment(const chebyshev_segment<double, 7>& seg, const std::vector<double>& nodes) override {
    body_.add_segment(seg, nodes);
  }
  void add_segment(const chebyshev_segment<quad, 3>& seg, const std::vector<quad>& nodes) override {
    body_.add_segment(seg, nodes);
  }
  void add_segment(const chebyshev_segment<quad, 7>& seg, const std::vector<quad>& nodes) override {
    body_.add_segment(seg, nodes);
  }
  void add_segment(const chebyshev_segment<mpfr_real, 3>& seg, const std::vector<mpfr_real>& nodes) override {
    body_.add_segment(seg, nodes);
  }
  void add_segment(const chebyshev_segment<mpfr_real, 7>& seg, const std::vector<mpfr_real>& nodes) override {
    body_.add_segment(seg, nodes);
  }
  void row(std::function<void()> task) override { body_.row(std::move(task)); }
  void finish() override { body_.finish(); }
  void close() override { body_.close(); }
  certified_radii radii(const double& tau, const double& t, const certified_cells& cells) override {
    return body_.radii(tau, t, cells);
  }
  certified_radii radii(const quad& tau, const quad& t, const certified_cells& cells) override {
    return body_.radii(tau, t, cells);
  }
  certified_radii radii(const mpfr_real& tau, const mpfr_real& t, const certified_cells& cells) override {
    return body_.radii(tau, t, cells);
  }
  const certified_maxima& maxima() const override { return body_.maxima(); }
  std::string method() const override { return body_.method(); }

 private:
  certificate_of_run body_;
};

run_certificate* make_module_certificate(const scene& s, const eulervop::precision& p, unsigned workers) {
  return new module_certificate(s, p, workers);
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
