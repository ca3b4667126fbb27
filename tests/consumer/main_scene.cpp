// The optional scene reader of the installed package: loads a scene file (argv[1]), builds its
// quad problem and integrates a short span. Exit 0 if it runs and the initial state is the
// scene's; 1 otherwise.
#include <eulervop/oracle.hpp>
#include <eulervop/scene/scene_problem.hpp>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  if (argc != 2) return 1;
  try {
    using eulervop::quad;
    const eulervop::scene::scene s = eulervop::scene::load_scene_file(argv[1]);
    const eulervop::euler_problem<quad> p = eulervop::scene::to_problem<quad>(s);
    const eulervop::oracle::reference<quad> ref(p, quad(1));
    const eulervop::vec3<quad> Om0 = ref(quad(0));
    const double d = static_cast<double>(eulervop::eq20_error(p.Omega0, Om0));
    std::printf("scene %s: Omega(0) reproduced to %.3e, %zu segments to tau = 1\n", s.name.c_str(), d,
                ref.stats().segments);
    return d < 1e-30 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
}
