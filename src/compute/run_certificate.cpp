#include "compute/run_certificate.hpp"

#include <eulervop/core/scalar.hpp>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <future>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <utility>

#include <dlfcn.h>
#include <sched.h>

// The install layout's path from the program's directory to the certificate module (set by
// CMakeLists.txt, as the plot scripts' is).
#ifndef EULERVOP_MODULES_FROM_BINDIR
#define EULERVOP_MODULES_FROM_BINDIR "../lib/eulervop"
#endif

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

namespace {

std::atomic<run_certificate_factory> linked_factory{nullptr};

// The module beside the program (its own path from /proc/self/exe): installed, or in a build tree.
// Loaded once and never unloaded; its symbols stay local, and those it takes from the program (the
// scene, the formulas, the integrator's types) resolve to the program's own (linked with
// ENABLE_EXPORTS), so that both share one copy of everything.
run_certificate_factory load_certificate_module() {
  namespace fs = std::filesystem;
  const char* name = "eulervop_certificate.so";
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec || exe.empty())
    throw std::runtime_error(std::string("--certify: cannot load the certificate module ") + name +
                             ": it lies beside the program, whose own path (/proc/self/exe) is unknown");
  const fs::path dir = exe.parent_path();
  std::string searched, failure;
  for (const fs::path& p : {(dir / EULERVOP_MODULES_FROM_BINDIR / name).lexically_normal(),
                            (dir / "lib" / "eulervop" / name).lexically_normal()}) {
    searched += (searched.empty() ? "" : " or ") + p.string();
    if (!fs::is_regular_file(p, ec)) continue;
    if (void* module = dlopen(p.c_str(), RTLD_NOW | RTLD_LOCAL)) {
      if (void* make = dlsym(module, "eulervop_make_run_certificate"))
        return reinterpret_cast<run_certificate_factory>(make);
      failure = p.string() + " has no eulervop_make_run_certificate";
    } else {
      failure = dlerror();
    }
    break;
  }
  throw std::runtime_error("--certify: cannot load the certificate module " + std::string(name) + ": " +
                           (failure.empty() ? "not found at " + searched : failure));
}

// The certificate of a module being loaded on another thread: loading it (Arb and FLINT, which
// bind every symbol at load, about 15 million instructions) then overlaps the integrator's own
// set-up instead of preceding it. Every call waits for it, and a module that could not be loaded
// throws at the first (close() then has nothing to close).
class deferred_certificate final : public run_certificate {
 public:
  explicit deferred_certificate(std::shared_future<std::shared_ptr<run_certificate>> made) : made_(std::move(made)) {}

  void add_segment(const chebyshev_segment<double, 3>& seg, const std::vector<double>& nodes) override { get().add_segment(seg, nodes); }
  void add_segment(const chebyshev_segment<double, 7>& seg, const std::vector<double>& nodes) override { get().add_segment(seg, nodes); }
  void add_segment(const chebyshev_segment<quad, 3>& seg, const std::vector<quad>& nodes) override { get().add_segment(seg, nodes); }
  void add_segment(const chebyshev_segment<quad, 7>& seg, const std::vector<quad>& nodes) override { get().add_segment(seg, nodes); }
  void add_segment(const chebyshev_segment<mpfr_real, 3>& seg, const std::vector<mpfr_real>& nodes) override {
    get().add_segment(seg, nodes);
  }
  void add_segment(const chebyshev_segment<mpfr_real, 7>& seg, const std::vector<mpfr_real>& nodes) override {
    get().add_segment(seg, nodes);
  }
  void expect_rows(const std::vector<double>& tau) override { get().expect_rows(tau); }
  void expect_rows(const std::vector<quad>& tau) override { get().expect_rows(tau); }
  void expect_rows(const std::vector<mpfr_real>& tau) override { get().expect_rows(tau); }
  void row(std::function<void()> task) override { get().row(std::move(task)); }
  void finish() override { get().finish(); }
  void close() override {
    try {
      get().close();
    } catch (...) {  // never made: nothing runs
    }
  }
  certified_radii radii(const double& tau, const double& t, const certified_cells& cells) override { return get().radii(tau, t, cells); }
  certified_radii radii(const quad& tau, const quad& t, const certified_cells& cells) override { return get().radii(tau, t, cells); }
  certified_radii radii(const mpfr_real& tau, const mpfr_real& t, const certified_cells& cells) override {
    return get().radii(tau, t, cells);
  }
  const certified_maxima& maxima() const override { return get().maxima(); }
  std::string method() const override { return get().method(); }

 private:
  run_certificate& get() const { return *made_.get(); }  // shared_future::get: safe from any thread
  std::shared_future<std::shared_ptr<run_certificate>> made_;
};

// The module's factory, loaded once on a thread of its own from the first call on.
std::shared_future<run_certificate_factory> loaded_module() {
  static const std::shared_future<run_certificate_factory> loading =
      std::async(std::launch::async, load_certificate_module).share();
  return loading;
}

}  // namespace

void link_run_certificate(run_certificate_factory make) { linked_factory = make; }

void start_loading_certificate_module() {
  if (!linked_factory) (void)loaded_module();
}

std::unique_ptr<run_certificate> make_run_certificate(const scene& s, const eulervop::precision& p, unsigned workers) {
  if (run_certificate_factory make = linked_factory) return std::unique_ptr<run_certificate>(make(s, p, workers));
  // The thread takes the caller's MPFR precision (a thread-local setting), as the pipeline's do.
  const unsigned digits10 = mpfr_real::thread_default_precision();
  std::shared_future<std::shared_ptr<run_certificate>> made =
      std::async(std::launch::async, [module = loaded_module(), &s, &p, workers, digits10] {
        mpfr_real::thread_default_precision(digits10);
        return std::shared_ptr<run_certificate>(module.get()(s, p, workers));
      }).share();
  return std::make_unique<deferred_certificate>(std::move(made));
}

}  // namespace eulervop::app
