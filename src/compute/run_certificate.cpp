#include "compute/run_certificate.hpp"

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <stdexcept>
#include <system_error>
#include <thread>

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

}  // namespace

void link_run_certificate(run_certificate_factory make) { linked_factory = make; }

std::unique_ptr<run_certificate> make_run_certificate(const scene& s, const eulervop::precision& p, unsigned workers) {
  run_certificate_factory make = linked_factory;
  if (!make) {
    static const run_certificate_factory loaded = load_certificate_module();
    make = loaded;
  }
  return std::unique_ptr<run_certificate>(make(s, p, workers));
}

}  // namespace eulervop::app
