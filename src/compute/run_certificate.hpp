// `--certify` of a streamed reference run, as the reference job sees it: the segments go in as the
// integrator makes them, and each row's radii come out. Its body (certified_reference.hpp, the
// certifiers of include/eulervop/certify/) is compiled once, in certificate_module*.cpp, which the
// program loads only for --certify (a module of its own, linked with Arb and FLINT), so that
// every other run starts without loading those libraries (docs/design.md, "The certificate module").
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

// The certificate of one streamed run: created at the first segment (which tells the degree).
// With `workers` > 0 it runs on threads; rows then go through row(). The segments come in double,
// quad or MPFR, with the rates alone (3 states) or the rates and the attitude as one problem (7).
// An interface, implemented in the certificate module (certificate_module*.cpp).
class run_certificate {
 public:
  virtual ~run_certificate() = default;

  virtual void add_segment(const chebyshev_segment<double, 3>& seg, const std::vector<double>& nodes) = 0;
  virtual void add_segment(const chebyshev_segment<double, 7>& seg, const std::vector<double>& nodes) = 0;
  virtual void add_segment(const chebyshev_segment<quad, 3>& seg, const std::vector<quad>& nodes) = 0;
  virtual void add_segment(const chebyshev_segment<quad, 7>& seg, const std::vector<quad>& nodes) = 0;
  virtual void add_segment(const chebyshev_segment<mpfr_real, 3>& seg, const std::vector<mpfr_real>& nodes) = 0;
  virtual void add_segment(const chebyshev_segment<mpfr_real, 7>& seg, const std::vector<mpfr_real>& nodes) = 0;
  // The times of the rows to come (increasing), given before the first segment: each segment's
  // check then evaluates what a row takes from that segment alone while the segment's models are
  // in the cache. Rows at other times, or without this, are evaluated when they run.
  virtual void expect_rows(const std::vector<double>& tau) = 0;
  virtual void expect_rows(const std::vector<quad>& tau) = 0;
  virtual void expect_rows(const std::vector<mpfr_real>& tau) = 0;
  // Runs `task` (a row: it may call radii) once every segment added before it is checked, and
  // before any added after it.
  virtual void row(std::function<void()> task) = 0;
  // Waits for every segment and row (rethrowing the first failure).
  virtual void finish() = 0;
  // Stops the threads, dropping what has not run (for a run that is abandoned).
  virtual void close() = 0;
  // The radii of a row at tau (and t, a physical scene's time) printed as `cells`.
  virtual certified_radii radii(const double& tau, const double& t, const certified_cells& cells) = 0;
  virtual certified_radii radii(const quad& tau, const quad& t, const certified_cells& cells) = 0;
  virtual certified_radii radii(const mpfr_real& tau, const mpfr_real& t, const certified_cells& cells) = 0;
  virtual const certified_maxima& maxima() const = 0;
  virtual std::string method() const = 0;
};

// The certificate of a run of scene `s` in precision `p` (both must outlive it): from the
// certificate module, loaded at the first call (from beside the program: <bindir>/../lib/eulervop
// or, in a build tree, <bindir>/lib/eulervop) on a thread of its own while the caller goes on, or
// linked in (the Python module links it). A module that cannot be found or loaded is a
// std::runtime_error naming the places searched, thrown at the certificate's first use.
std::unique_ptr<run_certificate> make_run_certificate(const scene& s, const eulervop::precision& p, unsigned workers);

// Starts loading the certificate module (if it is not linked in) on a thread of its own, so that
// the load (Arb and FLINT bind every symbol at load: about 4 ms) overlaps the reading of the scene
// as well as the integrator's set-up; make_run_certificate then takes the module loaded. Any
// number of calls load it once.
void start_loading_certificate_module();

// What the certificate module defines under the name `eulervop_make_run_certificate`, and what it
// registers when linked into a program or module (certificate_module.cpp).
using run_certificate_factory = run_certificate* (*)(const scene&, const eulervop::precision&, unsigned);
void link_run_certificate(run_certificate_factory make);

}  // namespace eulervop::app
