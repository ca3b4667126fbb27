// `eulervop batch` and the shipped reference datasets (docs/batch.md, docs/datasets.md).
//
// Small scenes with short spans are written into a temporary directory, so every test runs in
// a few seconds; the full hard-case suite is checked the same way by hand (docs/datasets.md).
#include "cli_test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <map>
#include <set>

namespace {

using namespace eulervop::cli_test;

std::string torque_free_scene(const std::string& name, double tau_end, int samples = 11) {
  return "name = \"" + name + "\"\n[initial]\nc1 = 0.5\nc2 = 1.0\nu = 0.0\n[span]\ntau_end = " + std::to_string(tau_end) +
         "\nsamples = " + std::to_string(samples) + "\n[reference]\nprecision = \"quad\"\n";
}

std::string torqued_scene(const std::string& name, double tau_end) {
  return "name = \"" + name + "\"\n[torque]\nG = [0.1, 0.2, 0.05]\n[initial]\nOmega = [0.5, 0.1, 1.0]\n[span]\ntau_end = " +
         std::to_string(tau_end) + "\nsamples = 7\n[reference]\nprecision = \"quad\"\n";
}

// scenes/a.toml ... in `dir`; returns the relative paths.
std::vector<std::string> write_scenes(const fs::path& dir, int n) {
  fs::create_directories(dir / "scenes");
  std::vector<std::string> paths;
  for (int i = 0; i < n; ++i) {
    const std::string name(1, static_cast<char>('a' + i));
    const std::string rel = "scenes/" + name + ".toml";
    write_file(dir / rel, i % 2 ? torqued_scene(name, 1.0 + 0.5 * i) : torque_free_scene(name, 2.0 + i));
    paths.push_back(rel);
  }
  return paths;
}

std::vector<std::string> batch_args(const std::vector<std::string>& scenes, const std::string& out,
                                    const std::vector<std::string>& extra = {}) {
  std::vector<std::string> args = {"batch"};
  args.insert(args.end(), scenes.begin(), scenes.end());
  args.push_back("--out-dir");
  args.push_back(out);
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

// Every regular file under `root`, by relative path, with its bytes.
std::map<std::string, std::string> tree(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.is_regular_file()) files[fs::relative(e.path(), root).string()] = read_file(e.path());
  return files;
}

nlohmann::json manifest(const fs::path& file) { return nlohmann::json::parse(read_file(file)); }

std::map<std::string, std::string> statuses(const nlohmann::json& m) {
  std::map<std::string, std::string> s;
  for (const auto& e : m["scenes"]) s[e["name"].get<std::string>()] = e["status"].get<std::string>();
  return s;
}

TEST(Batch, TwoJobsGiveTheSameFilesAsOneByteForByte) {
  temp_dir dir;
  const auto scenes = write_scenes(dir.path(), 5);
  const run_result one = run(dir.path(), batch_args(scenes, "out1", {"--jobs", "1", "--verify"}));
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const run_result two = run(dir.path(), batch_args(scenes, "out2", {"--jobs", "2", "--verify"}));
  ASSERT_EQ(two.exit_code, 0) << two.err;
  const auto a = tree(dir.path() / "out1"), b = tree(dir.path() / "out2");
  ASSERT_EQ(a.size(), b.size());
  // 5 reference CSVs, 5 hash stamps, the manifest.
  EXPECT_EQ(a.size(), 11u);
  for (const auto& [path, bytes] : a) {
    ASSERT_TRUE(b.contains(path)) << path;
    EXPECT_EQ(bytes, b.at(path)) << path;
  }
  const std::string csv = a.at("c/reference.csv");
  EXPECT_EQ(csv.find("# wall_seconds"), std::string::npos) << csv;
  EXPECT_NE(csv.find("# estimated_max_error: "), std::string::npos) << csv;
  EXPECT_NE(csv.find("# command: eulervop reference scenes/c.toml --verify\n"), std::string::npos) << csv;
  for (const auto& [name, status] : statuses(manifest(dir.path() / "out2/manifest.json"))) EXPECT_EQ(status, "ok") << name;
}

TEST(Batch, RerunSkipsEverythingAndChangedSceneIsRecomputed) {
  temp_dir dir;
  const auto scenes = write_scenes(dir.path(), 4);
  const run_result first = run(dir.path(), batch_args(scenes, "out", {"--jobs", "2"}));
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const auto before = tree(dir.path() / "out");

  const auto start = std::chrono::steady_clock::now();
  const run_result second = run(dir.path(), batch_args(scenes, "out", {"--jobs", "2"}));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(second.exit_code, 0) << second.err;
  EXPECT_LT(seconds, 2.0);
  for (const auto& [name, status] : statuses(manifest(dir.path() / "out/manifest.json")))
    EXPECT_EQ(status, "skipped-up-to-date") << name;
  auto after = tree(dir.path() / "out");
  after.erase("manifest.json");
  for (const auto& [path, bytes] : after) EXPECT_EQ(bytes, before.at(path)) << path;

  // Change b (its span) and delete c's output: both are recomputed, a and d are not.
  write_file(dir.path() / "scenes/b.toml", torqued_scene("b", 0.75));
  fs::remove(dir.path() / "out/c/reference.csv");
  const run_result third = run(dir.path(), batch_args(scenes, "out"));
  ASSERT_EQ(third.exit_code, 0) << third.err;
  const auto s = statuses(manifest(dir.path() / "out/manifest.json"));
  EXPECT_EQ(s.at("a"), "skipped-up-to-date");
  EXPECT_EQ(s.at("b"), "ok");
  EXPECT_EQ(s.at("c"), "ok");
  EXPECT_EQ(s.at("d"), "skipped-up-to-date");
  const std::string b = read_file(dir.path() / "out/b/reference.csv");
  EXPECT_NE(b, before.at("b/reference.csv"));
  EXPECT_NE(b.find("tau_end = 0.75"), std::string::npos) << b;
  EXPECT_EQ(read_file(dir.path() / "out/c/reference.csv"), before.at("c/reference.csv"));

  // Other flags are other outputs: --precision recomputes everything.
  const run_result fourth = run(dir.path(), batch_args(scenes, "out", {"--precision", "double"}));
  ASSERT_EQ(fourth.exit_code, 0) << fourth.err;
  for (const auto& [name, status] : statuses(manifest(dir.path() / "out/manifest.json"))) EXPECT_EQ(status, "ok") << name;
}

TEST(Batch, FailedScenesAreRecordedWhileOthersSucceed) {
  temp_dir dir;
  auto scenes = write_scenes(dir.path(), 2);
  write_file(dir.path() / "scenes/broken.toml", "name = \"broken\"\n[initial]\nc1 = \"x\"\n");
  write_file(dir.path() / "scenes/overflow.toml", overflow_scene());
  scenes.push_back("scenes/broken.toml");
  scenes.push_back("scenes/overflow.toml");
  scenes.push_back("scenes/missing.toml");

  const run_result r = run(dir.path(), batch_args(scenes, "out", {"--jobs", "2"}));
  EXPECT_EQ(r.exit_code, 2) << r.err;  // bad input outranks the numerical failure
  const auto m = manifest(dir.path() / "out/manifest.json");
  std::map<std::string, nlohmann::json> by_name;
  for (const auto& e : m["scenes"]) by_name[e["name"].get<std::string>()] = e;
  ASSERT_EQ(by_name.size(), 5u);
  EXPECT_EQ(by_name["a"]["status"], "ok");
  EXPECT_EQ(by_name["b"]["status"], "ok");
  EXPECT_TRUE(fs::exists(dir.path() / "out/a/reference.csv"));
  EXPECT_TRUE(fs::exists(dir.path() / "out/b/reference.csv"));
  EXPECT_EQ(by_name["broken"]["status"], "failed");
  EXPECT_EQ(by_name["broken"]["exit_code"], 2);
  EXPECT_NE(by_name["broken"]["message"].get<std::string>().find("c1"), std::string::npos) << by_name["broken"];
  EXPECT_EQ(by_name["missing"]["status"], "failed");
  EXPECT_EQ(by_name["missing"]["exit_code"], 2);
  EXPECT_EQ(by_name["overflow"]["status"], "failed");
  EXPECT_EQ(by_name["overflow"]["exit_code"], 3);
  EXPECT_NE(by_name["overflow"]["message"].get<std::string>().find("numerical failure at tau="), std::string::npos);
  EXPECT_FALSE(fs::exists(dir.path() / "out/overflow/reference.csv"));

  // Only the numerical failure left: exit 3. A rerun retries it (a failure is never up to date).
  const run_result only3 = run(dir.path(), batch_args({"scenes/a.toml", "scenes/overflow.toml"}, "out"));
  EXPECT_EQ(only3.exit_code, 3) << only3.err;
  const auto s = statuses(manifest(dir.path() / "out/manifest.json"));
  EXPECT_EQ(s.at("a"), "skipped-up-to-date");
  EXPECT_EQ(s.at("overflow"), "failed");
}

TEST(Batch, ShardsCoverEverySceneExactlyOnce) {
  temp_dir dir;
  const auto scenes = write_scenes(dir.path(), 5);
  std::multiset<std::string> seen;
  for (const char* shard : {"1/2", "2/2"}) {
    const run_result r = run(dir.path(), batch_args(scenes, "out", {"--shard", shard}));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  for (const char* file : {"out/manifest-1-of-2.json", "out/manifest-2-of-2.json"}) {
    const auto m = manifest(dir.path() / file);
    for (const auto& e : m["scenes"]) {
      EXPECT_EQ(e["status"], "ok");
      seen.insert(e["name"].get<std::string>());
    }
  }
  EXPECT_EQ(seen, (std::multiset<std::string>{"a", "b", "c", "d", "e"}));
  // Sorted by path, index % 2 == i - 1: shard 1 has a, c, e.
  const auto first = statuses(manifest(dir.path() / "out/manifest-1-of-2.json"));
  EXPECT_EQ(first.size(), 3u);
  EXPECT_TRUE(first.contains("a") && first.contains("c") && first.contains("e"));
  // The same scenes given in another order make the same shards.
  std::vector<std::string> reversed(scenes.rbegin(), scenes.rend());
  const run_result again = run(dir.path(), batch_args(reversed, "out", {"--shard", "1/2"}));
  ASSERT_EQ(again.exit_code, 0) << again.err;
  for (const auto& [name, status] : statuses(manifest(dir.path() / "out/manifest-1-of-2.json")))
    EXPECT_EQ(status, "skipped-up-to-date") << name;
}

TEST(Batch, ReportWritesItsFilesPerScene) {
  temp_dir dir;
  write_file(dir.path() / "r.toml", torque_free_scene("r", 3.0));
  const run_result r = run(dir.path(), {"batch", "r.toml", "--out-dir", "out", "--report"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : {"out/r/reference.csv", "out/r/report/errors.csv", "out/r/report/summary.json"})
    EXPECT_TRUE(fs::is_regular_file(dir.path() / f)) << f;
  const run_result again = run(dir.path(), {"batch", "r.toml", "--out-dir", "out", "--report"});
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(statuses(manifest(dir.path() / "out/manifest.json")).at("r"), "skipped-up-to-date");
}

TEST(Batch, BadFlagsExit2WithOneLine) {
  temp_dir dir;
  const auto scenes = write_scenes(dir.path(), 1);
  const std::vector<std::vector<std::string>> cases = {
      batch_args(scenes, "out", {"--shard", "0/2"}),  batch_args(scenes, "out", {"--shard", "3/2"}),
      batch_args(scenes, "out", {"--shard", "abc"}),  batch_args(scenes, "out", {"--shard", "1/0"}),
      batch_args(scenes, "out", {"--jobs", "0"}),     batch_args(scenes, "out", {"--jobs", "two"}),
      batch_args({}, "out"),                          {"batch", scenes[0]},
      batch_args(scenes, "out", {"--samples", "1"}), batch_args(scenes, "out", {"--precision", "triple"}),
  };
  for (const auto& args : cases) {
    std::string text;
    for (const auto& a : args) text += a + " ";
    const run_result r = run(dir.path(), args);
    EXPECT_EQ(r.exit_code, 2) << text << r.err;
    EXPECT_EQ(lines_of(r.err).size(), 1u) << text << r.err;
    EXPECT_TRUE(r.err.starts_with("eulervop: error: ")) << text << r.err;
    EXPECT_FALSE(fs::exists(dir.path() / "out/manifest.json")) << text;
  }
  // Two scenes that would share an output directory.
  fs::create_directories(dir.path() / "other");
  write_file(dir.path() / "other/a.toml", torque_free_scene("a2", 1.0));
  const run_result clash = run(dir.path(), batch_args({scenes[0], "other/a.toml"}, "out"));
  EXPECT_EQ(clash.exit_code, 2) << clash.err;
  EXPECT_EQ(lines_of(clash.err).size(), 1u) << clash.err;
}

// ---- the shipped datasets ------------------------------------------------------------------

// Runs the `# command:` line of a shipped dataset again (from the source tree, so its relative
// scene path resolves) and compares the data rows byte for byte.
TEST(ReferenceDatasets, ShortDatasetRegeneratesIdentically) {
  const fs::path shipped = fs::path(source_dir) / "data/reference/torque-free-short.csv";
  ASSERT_TRUE(fs::exists(shipped)) << shipped;
  const std::string text = read_file(shipped);
  std::vector<std::string> args;
  std::vector<std::string> rows;
  std::string estimated;
  for (const auto& l : lines_of(text)) {
    if (l.starts_with("# command: eulervop ")) {
      std::istringstream words(l.substr(std::string("# command: eulervop ").size()));
      for (std::string w; words >> w;) args.push_back(w);
    } else if (l.starts_with("# estimated_max_error: ")) {
      estimated = l;
    } else if (!l.starts_with("#")) {
      rows.push_back(l);
    }
  }
  ASSERT_FALSE(args.empty()) << "no # command: line";
  ASSERT_EQ(args[0], "reference");
  EXPECT_FALSE(estimated.empty()) << "made without --verify";
  EXPECT_LT(std::stod(estimated.substr(estimated.find(':') + 1)), 1e-25) << estimated;

  temp_dir dir;
  args.push_back("--out");
  args.push_back((dir.path() / "again.csv").string());
  const run_result r = run(source_dir, args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::vector<std::string> again;
  for (const auto& l : lines_of(read_file(dir.path() / "again.csv")))
    if (!l.starts_with("#")) again.push_back(l);
  ASSERT_EQ(again.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(again[i], rows[i]) << "data row " << i;
}

// Every shipped dataset says how it was made, how accurate it is estimated to be (--verify) and
// proven to be (--certify).
TEST(ReferenceDatasets, EveryDatasetCarriesCommandEstimateAndRadius) {
  const fs::path dir = fs::path(source_dir) / "data/reference";
  std::uintmax_t total = 0;
  int count = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".csv") continue;
    ++count;
    total += e.file_size();
    const std::string text = read_file(e.path());
    EXPECT_NE(text.find("\n# command: eulervop reference "), std::string::npos) << e.path();
    EXPECT_NE(text.find("\n# estimated_max_error: "), std::string::npos) << e.path();
    EXPECT_NE(text.find("\n# certified_max_error: "), std::string::npos) << e.path();
  }
  EXPECT_GE(count, 4);
  EXPECT_LT(total, 8u << 20) << "keep data/reference/ to a few MB";
}

}  // namespace

namespace {

// --certify reaches every scene's reference; a scene that cannot be certified fails alone, with
// its one-line reason.
TEST(Batch, CertifyGivesEachReferenceItsRadiusAndRefusesWhatItCannotCertify) {
  temp_dir dir;
  auto scenes = write_scenes(dir.path(), 2);
  scenes.push_back(source_dir + "/data/scenes/varying-torque.toml");  // a torque of sin(tau): the general path
  // Initial elements with u != 0 (Jacobi's functions enclosed) are certified; the same scene
  // asking for a double reference is refused, alone.
  const std::string elements =
      "[initial]\nc1 = 0.5\nc2 = 1.0\nu = 0.3\n[span]\ntau_end = 1.0\nsamples = 3\n";
  write_file(dir.path() / "scenes/elements.toml", "name = \"elements\"\n" + elements);
  write_file(dir.path() / "scenes/double.toml", "name = \"double\"\n[reference]\nprecision = \"double\"\n" + elements);
  scenes.push_back("scenes/elements.toml");
  scenes.push_back("scenes/double.toml");
  const run_result r = run(dir.path(), batch_args(scenes, "out", {"--certify"}));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  const auto m = manifest(dir.path() / "out/manifest.json");
  std::map<std::string, nlohmann::json> by_name;
  for (const auto& e : m["scenes"]) by_name[e["name"].get<std::string>()] = e;
  for (const char* name : {"a", "b", "varying-torque", "elements"}) {
    EXPECT_EQ(by_name[name]["status"], "ok") << name;
    const std::string csv = read_file(dir.path() / "out" / name / "reference.csv");
    EXPECT_NE(csv.find("\n# certified_max_error: "), std::string::npos) << name;
    EXPECT_NE(csv.find("\ntau,Omega1,Omega2,Omega3,radius\n"), std::string::npos) << name;
  }
  EXPECT_EQ(by_name["double"]["status"], "failed");
  EXPECT_NE(by_name["double"]["message"].get<std::string>().find("precision double is not certified"),
            std::string::npos)
      << by_name["double"]["message"];
}

}  // namespace
