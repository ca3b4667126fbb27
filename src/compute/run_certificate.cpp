#include "compute/run_certificate.hpp"

#include "compute/certified_reference.hpp"

#include <eulervop/model/wide_formula_cells.hpp>

#include <algorithm>
#include <thread>
#include <utility>

#include <sched.h>

namespace eulervop::app {

void require_certifiable(const eulervop::precision& p) {
  if (p.type == eulervop::precision::kind::binary64)
    throw input_error("--certify: precision double is not certified (its segments do not join exactly in double; "
                      "use quad or mpfr:BITS)");
}

unsigned certify_workers() {
  unsigned cores = std::thread::hardware_concurrency();
  cpu_set_t allowed;
  if (sched_getaffinity(0, sizeof allowed, &allowed) == 0) cores = static_cast<unsigned>(CPU_COUNT(&allowed));
  return cores >= 2 ? std::min(cores, 4u) : 0;
}

run_certificate::run_certificate(const scene& s, const eulervop::precision& p, unsigned workers)
    : body_(std::make_unique<certificate_of_run>(s, p, workers)) {}
run_certificate::~run_certificate() = default;

template <scalar T, std::size_t D>
void run_certificate::add_segment(const chebyshev_segment<T, D>& seg, const std::vector<T>& nodes) {
  body_->add_segment(seg, nodes);
}

void run_certificate::row(std::function<void()> task) { body_->row(std::move(task)); }
void run_certificate::finish() { body_->finish(); }
void run_certificate::close() { body_->close(); }

template <scalar T>
certified_radii run_certificate::radii(const T& tau, const T& t, const certified_cells& cells) {
  return body_->radii(tau, t, cells);
}

const certified_maxima& run_certificate::maxima() const { return body_->maxima(); }
std::string run_certificate::method() const { return body_->method(); }

// The precisions a reference runs in (a double run is refused before it starts, by
// require_certifiable, but its code calls these too), each with the rates alone and with the
// rates and the attitude as one problem.
#define EULERVOP_RUN_CERTIFICATE_FOR(T)                                                                   \
  template void run_certificate::add_segment<T, 3>(const chebyshev_segment<T, 3>&, const std::vector<T>&); \
  template void run_certificate::add_segment<T, 7>(const chebyshev_segment<T, 7>&, const std::vector<T>&); \
  template certified_radii run_certificate::radii<T>(const T&, const T&, const certified_cells&);
EULERVOP_RUN_CERTIFICATE_FOR(double)
EULERVOP_RUN_CERTIFICATE_FOR(quad)
EULERVOP_RUN_CERTIFICATE_FOR(mpfr_real)
#undef EULERVOP_RUN_CERTIFICATE_FOR

}  // namespace eulervop::app
