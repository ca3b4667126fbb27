// `--certify` of a streamed reference run, as the reference job sees it: the segments go in as the
// integrator makes them, and each row's radii come out. Its body (certified_reference.hpp, the
// certifiers of include/eulervop/certify/) is compiled once, in run_certificate.cpp, so that the
// units which run references do not compile the certificate too.
#pragma once

#include "compute/certified_row.hpp"
#include "compute/scene_library.hpp"

#include <eulervop/core/precision.hpp>
#include <eulervop/reference/segment.hpp>

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace eulervop::app {

// --certify takes every scene in quad and MPFR; a double reference is refused (an input_error,
// exit 2): the joins step needs each segment's end, its start plus twice its half-length, to be
// the next segment's start exactly, which the double integrator does not guarantee
// (docs/certified.md, "What is not covered").
void require_certifiable(const eulervop::precision& p);

// The threads that prepare a certificate's segments (certify_pipeline.hpp): the cores this
// process may run on (its affinity, so that `taskset -c 0` means one), at most 4, as the
// integration and the in-order part then set the pace; none on one core, where the certificate
// runs in the integration's thread.
unsigned certify_workers();

class certificate_of_run;

// The certificate of one streamed run: created at the first segment (which tells the degree).
// With `workers` > 0 it runs on threads; rows then go through row(). T is double, quad or
// mpfr_real, D is 3 (the rates) or 7 (the rates and the attitude as one problem).
class run_certificate {
 public:
  run_certificate(const scene& s, const eulervop::precision& p, unsigned workers);
  ~run_certificate();
  run_certificate(const run_certificate&) = delete;
  run_certificate& operator=(const run_certificate&) = delete;

  template <scalar T, std::size_t D>
  void add_segment(const chebyshev_segment<T, D>& seg, const std::vector<T>& nodes);
  // Runs `task` (a row: it may call radii) once every segment added before it is checked, and
  // before any added after it.
  void row(std::function<void()> task);
  // Waits for every segment and row (rethrowing the first failure).
  void finish();
  // Stops the threads, dropping what has not run (for a run that is abandoned).
  void close();
  // The radii of a row at tau (and t, a physical scene's time) printed as `cells`.
  template <scalar T>
  certified_radii radii(const T& tau, const T& t, const certified_cells& cells);
  const certified_maxima& maxima() const;
  std::string method() const;

 private:
  std::unique_ptr<certificate_of_run> body_;
};

}  // namespace eulervop::app
