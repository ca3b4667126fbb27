// The program in the user's terms: progress on a terminal, the annotated scene templates, help
// that points to the scene format, notes on torque windows outside the span, every reason
// --certify refuses a scene, messages that quote the scene's text and give the scene's time, and
// flags that complete a scene.
#include "cli_test_support.hpp"

#include <fmt/format.h>

#include <array>
#include <cerrno>
#include <string>
#include <vector>

#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {

using namespace eulervop::cli_test;

// A physical scene with a thruster window and an attitude: the new user's spacecraft.
std::string thruster_scene(const std::string& window, const std::string& thrust, const std::string& span) {
  return fmt::format(R"(name = "thruster"
[body]
inertia = [100.0, 150.0, 200.0]
[torque]
M = [0.0, 0.0, 0.0]
[[torque.piece]]
{}
M = {}
[initial]
omega = [0.02, 0.1, 0.05]
q = [1.0, 0.0, 0.0, 0.0]
[span]
{}
)",
                     window, thrust, span);
}

// Runs the binary in `dir` with its standard error on a pseudo-terminal (standard output to
// .stdout); returns what the terminal received, and the exit code in `exit_code`.
std::string run_on_terminal(const fs::path& dir, const std::vector<std::string>& args, int& exit_code) {
  int master = -1;
  const pid_t pid = ::forkpty(&master, nullptr, nullptr, nullptr);
  if (pid == 0) {
    if (::chdir(dir.c_str()) != 0) ::_exit(127);
    // stdin and stderr stay on the terminal; stdout goes to a file, as in a pipeline.
    FILE* out = std::freopen(".stdout", "w", stdout);
    if (!out) ::_exit(127);
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(binary.c_str()));
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(binary.c_str(), argv.data());
    ::_exit(127);
  }
  std::string seen;
  std::array<char, 4096> buffer{};
  while (true) {
    const ssize_t n = ::read(master, buffer.data(), buffer.size());
    if (n > 0) {
      seen.append(buffer.data(), static_cast<std::size_t>(n));
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else {
      break;  // EIO once the child has closed the terminal
    }
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  ::close(master);
  exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return seen;
}

// The reference file's lines without its wall-clock lines (which differ from run to run).
std::string without_timing(const std::string& csv) {
  std::string out;
  for (const std::string& l : lines_of(csv))
    if (!l.starts_with("# wall_seconds")) out += l + "\n";
  return out;
}

// A run of a few seconds on a terminal shows its progress: the stage, how far in t (seconds, for
// a physical scene), the segments and the time left; on a pipe, --progress and --quiet change
// nothing on standard output or in the file.
TEST(Progress, ShownOnATerminalInTheScenesTimeAndNeverInTheOutputs) {
  temp_dir dir;
  const std::string scene = source_dir + "/data/scenes/spacecraft-attitude.toml";
  const std::vector<std::string> args = {"reference", scene, "--t-end", "36000", "--samples", "5", "--out", "tty.csv"};
  int code = -1;
  const std::string terminal = run_on_terminal(dir.path(), args, code);
  ASSERT_EQ(code, 0) << terminal;
  EXPECT_NE(terminal.find("reference: t "), std::string::npos) << terminal;
  EXPECT_NE(terminal.find(" / 36000 s ("), std::string::npos) << terminal;
  EXPECT_NE(terminal.find(" segments"), std::string::npos) << terminal;
  EXPECT_NE(terminal.find(" left"), std::string::npos) << terminal;
  // Forced on a pipe (one line a second, so a short run shows its first), and turned off.
  std::vector<std::string> forced = args, quiet = args, plain = args;
  forced.back() = "forced.csv";
  forced.push_back("--progress");
  quiet.back() = "quiet.csv";
  quiet.push_back("--quiet");
  plain.back() = "plain.csv";
  const run_result f = run(dir.path(), forced), q = run(dir.path(), quiet), p = run(dir.path(), plain);
  ASSERT_EQ(f.exit_code, 0) << f.err;
  ASSERT_EQ(q.exit_code, 0) << q.err;
  ASSERT_EQ(p.exit_code, 0) << p.err;
  EXPECT_NE(f.err.find("reference: t "), std::string::npos) << f.err;
  EXPECT_EQ(q.err, "");
  EXPECT_EQ(p.err, "");
  const std::string expected = without_timing(read_file(dir.path() / "plain.csv"));
  for (const char* name : {"tty.csv", "forced.csv", "quiet.csv"})
    EXPECT_EQ(without_timing(read_file(dir.path() / name)), expected) << name;
  EXPECT_EQ(f.out, p.out);
  EXPECT_EQ(q.out, p.out);
  EXPECT_EQ(read_file(dir.path() / ".stdout"), "");  // the terminal run's standard output
  const run_result both = run(dir.path(), {"reference", "--progress", "--quiet"});
  EXPECT_EQ(both.exit_code, 2) << both.err;
}

// Every template runs as printed, and says what each key is.
TEST(SceneTemplate, EachFormRunsAsPrinted) {
  temp_dir dir;
  for (const char* form : {"normalized", "physical", "coefficient"}) {
    const run_result t = run(dir.path(), {"scene-template", form});
    ASSERT_EQ(t.exit_code, 0) << t.err;
    for (const char* key : {"name =", "[torque]", "[[torque.piece]]", "[initial]", "[span]", "[reference]",
                            "docs/scenes.md", "samples ="})
      EXPECT_NE(t.out.find(key), std::string::npos) << form << ": " << key;
    const std::string file = std::string(form) + ".toml";
    write_file(dir.path() / file, t.out);
    const run_result r = run(dir.path(), {"reference", file, "--samples", "3"});
    EXPECT_EQ(r.exit_code, 0) << form << ": " << r.err;
  }
  const run_result physical = run(dir.path(), {"scene-template"});
  EXPECT_NE(physical.out.find("q = [1.0, 0.0, 0.0, 0.0]"), std::string::npos);
  EXPECT_NE(physical.out.find("scalar first, body to inertial"), std::string::npos);
  const run_result to_file = run(dir.path(), {"scene-template", "coefficient", "--out", "c.toml"});
  ASSERT_EQ(to_file.exit_code, 0) << to_file.err;
  EXPECT_EQ(read_file(dir.path() / "c.toml"), run(dir.path(), {"scene-template", "coefficient"}).out);
  expect_one_line_error(run(dir.path(), {"scene-template", "spherical"}),
                        "form `spherical`: unknown (expected normalized, physical or coefficient)");
}

// Every command's help points to the scene templates and docs/scenes.md, and states the
// defaults of the flags that have one.
TEST(Help, EveryCommandPointsToTheSceneFormat) {
  temp_dir dir;
  for (const char* command : {"reference", "report", "sweep", "check", "batch", "map", "scene-template"}) {
    const run_result h = run(dir.path(), {command, "--help"});
    EXPECT_EQ(h.exit_code, 0) << command;
    EXPECT_NE(h.out.find("eulervop scene-template"), std::string::npos) << command;
    EXPECT_NE(h.out.find("docs/scenes.md"), std::string::npos) << command;
  }
  const run_result reference = run(dir.path(), {"reference", "--help"});
  EXPECT_NE(reference.out.find("--precision P               double | quad | mpfr:BITS (default: the scene's"),
            std::string::npos)
      << reference.out;
}

// A torque window that starts after the span ends (or ends before it starts) never applies: one
// note naming the piece as the scene wrote it, also in the file's metadata; the run succeeds.
TEST(TorqueWindows, OutsideTheSpanAreNoted) {
  temp_dir dir;
  write_file(dir.path() / "late.toml",
             thruster_scene("from = 5000.0\nto = \"5000 + 10\"", "[0.05, 0.0, 0.0]", "t_end = 600.0\nsamples = 3"));
  const run_result r = run(dir.path(), {"reference", "late.toml", "--out", "late.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string note =
      "[[torque.piece]] from = 5000.0 to = 5000 + 10 starts at or after the end of the span, t_end = 600.0: it "
      "never applies";
  EXPECT_EQ(r.err, "note: scene thruster: " + note + "\n");
  EXPECT_NE(read_file(dir.path() / "late.csv").find("# note: " + note), std::string::npos);
  // --t-end moves the end: the same window is inside a longer span, and no note is given.
  const run_result longer = run(dir.path(), {"reference", "late.toml", "--t-end", "6000"});
  EXPECT_EQ(longer.exit_code, 0) << longer.err;
  EXPECT_EQ(longer.err, "");
  write_file(dir.path() / "early.toml",
             thruster_scene("from = -20.0\nto = 0.0", "[0.05, 0.0, 0.0]", "t_end = 600.0\nsamples = 3"));
  const run_result early = run(dir.path(), {"reference", "early.toml"});
  EXPECT_EQ(early.exit_code, 0) << early.err;
  EXPECT_NE(early.err.find("from = -20.0 to = 0.0 ends at or before t = 0: it never applies"), std::string::npos)
      << early.err;
}

// --certify refuses a double reference in one line, and certifies a piecewise formula of the time
// beside the gravity gradient.
TEST(Certify, RefusesDoubleAndTakesFormulasBesideTheGravityGradient) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"reference", "--certify", "--precision", "double"});
  expect_one_line_error(r, "--certify: precision double is not certified");
  // A piecewise formula of the time beside the gravity gradient is certified.
  write_file(dir.path() / "s.toml",
             thruster_scene("from = 50.0\nto = 60.0", "[\"0.05*sin(t)\", 0.0, 0.0]",
                            "t_end = 600.0\nsamples = 3\n[torque.gravity_gradient]\nmean_motion = 0.0011"));
  const run_result ok = run(dir.path(), {"reference", "s.toml", "--certify", "--out", "c.csv"});
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
}

// Values are echoed as the scene wrote them, and a physical scene's failure gives t first, then
// tau, and the piece in force.
TEST(Messages, QuoteTheScenesTextAndGiveItsTime) {
  temp_dir dir;
  write_file(dir.path() / "q.toml",
             thruster_scene("from = 50.0\nto = 60.0", "[0.05, 0.0, 0.0]", "t_end = 600.0\nsamples = 3"));
  std::string text = read_file(dir.path() / "q.toml");
  text.replace(text.find("q = [1.0, 0.0, 0.0, 0.0]"), 24, "q = [0.9, 0.3, 0.3, 0.2]");
  write_file(dir.path() / "q.toml", text);
  expect_one_line_error(run(dir.path(), {"reference", "q.toml"}),
                        "[initial] q = [0.9, 0.3, 0.3, 0.2]: its norm is 1.01488915650922");
  write_file(dir.path() / "nf.toml",
             thruster_scene("from = 50.0\nto = 60.0", "[\"log(omega1 - 1)\", 0.0, 0.0]", "t_end = 600.0\nsamples = 3"));
  const run_result nf = run(dir.path(), {"reference", "nf.toml"});
  EXPECT_EQ(nf.exit_code, 3) << nf.err;
  EXPECT_TRUE(nf.err.starts_with("eulervop: numerical failure at t=50 s (tau=14.4337567)")) << nf.err;
  EXPECT_NE(nf.err.find("M1 = log(omega1 - 1) is nan at t = 50, in the piece [50.0, 60.0)"), std::string::npos)
      << nf.err;
  EXPECT_EQ(lines_of(nf.err).size(), 1u) << nf.err;
}

// A scene without samples or times is completed by --samples or --times; without either, the
// message names both ways. --t-end sets the end of a scene in the coefficient form, whose time is t.
TEST(Flags, CompleteAScene) {
  temp_dir dir;
  write_file(dir.path() / "open.toml", thruster_scene("from = 50.0\nto = 60.0", "[0.05, 0.0, 0.0]", "t_end = 100.0"));
  const run_result samples = run(dir.path(), {"reference", "open.toml", "--samples", "3", "--precision", "double"});
  ASSERT_EQ(samples.exit_code, 0) << samples.err;
  EXPECT_EQ(lines_of(samples.out).back().substr(0, 22), "1.0000000000000000e+02");
  const run_result times = run(dir.path(), {"reference", "open.toml", "--times", "0,55", "--precision", "double"});
  ASSERT_EQ(times.exit_code, 0) << times.err;
  EXPECT_EQ(lines_of(times.out).back().substr(0, 22), "5.5000000000000000e+01");
  expect_one_line_error(run(dir.path(), {"reference", "open.toml"}),
                        "[span] of scene thruster: no samples or times; give samples (a count) or times (a list) in "
                        "the scene, or --samples N or --times LIST");
  const std::string sciml = source_dir + "/data/scenes/problems/sciml-rigid-body.toml";
  const run_result t_end = run(dir.path(), {"reference", sciml, "--t-end", "2", "--samples", "2"});
  ASSERT_EQ(t_end.exit_code, 0) << t_end.err;
  EXPECT_TRUE(lines_of(t_end.out).back().starts_with("2.000000000000000000000000000000000000e+00,"));
  expect_one_line_error(run(dir.path(), {"reference", sciml, "--tau-end", "2"}),
                        "--tau-end 2: scene sciml-rigid-body is in the coefficient form ([equations]), whose time is "
                        "t; give --t-end");
}

}  // namespace
