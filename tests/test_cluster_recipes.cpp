// The GNU parallel recipes of docs/batch.md, run as written over the hard-case suite: each
// line of that page's `parallel` block is executed by bash in a directory holding the
// suite as scenes/*.toml, with the built program first on PATH. The union of the reference
// files each recipe leaves must be byte for byte what `eulervop batch scenes/*.toml --jobs 1`
// writes, every scene exactly once, and every manifest must list its scenes as ok.
#include "cli_test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace eulervop::cli_test;

// The lines of docs/batch.md's code block that follows "GNU parallel," and start with "parallel ".
std::vector<std::string> documented_parallel_lines() {
  const std::vector<std::string> lines = lines_of(read_file(fs::path(source_dir) / "docs/batch.md"));
  std::vector<std::string> out;
  bool after_title = false, in_block = false;
  for (const std::string& l : lines) {
    if (l.starts_with("GNU parallel,")) after_title = true;
    else if (after_title && !in_block && l.starts_with("```")) in_block = true;
    else if (in_block && l.starts_with("```")) break;
    else if (in_block && l.starts_with("parallel ")) out.push_back(l);
  }
  return out;
}

// A directory with the hard-case suite copied to scenes/.
void copy_suite(const fs::path& dir) {
  fs::create_directories(dir / "scenes");
  for (const auto& e : fs::directory_iterator(fs::path(source_dir) / "data/scenes/hard"))
    if (e.path().extension() == ".toml") fs::copy_file(e.path(), dir / "scenes" / e.path().filename());
}

// Runs a shell line in `dir` with the program on PATH; returns its exit status.
int shell(const fs::path& dir, const std::string& line) {
  const std::string bin_dir = fs::path(binary).parent_path().string();
  const std::string command = "cd " + shell_quote(dir.string()) + " && HOME=" + shell_quote(dir.string()) +
                              " PATH=" + shell_quote(bin_dir) + ":\"$PATH\" bash -c " + shell_quote(line) +
                              " > out.log 2>&1";
  return std::system(command.c_str());
}

// Every reference.csv under `root`, by scene name (the directory holding it), with its bytes.
std::map<std::string, std::vector<std::string>> references_under(const fs::path& root) {
  std::map<std::string, std::vector<std::string>> found;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.path().filename() == "reference.csv")
      found[e.path().parent_path().filename().string()].push_back(read_file(e.path()));
  return found;
}

// Every manifest under `root` lists its scenes as ok; returns how many scenes they list in all.
std::size_t scenes_in_manifests(const fs::path& root) {
  std::size_t n = 0;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    const std::string name = e.path().filename().string();
    if (!name.starts_with("manifest") || e.path().extension() != ".json") continue;
    const nlohmann::json m = nlohmann::json::parse(read_file(e.path()));
    for (const auto& s : m["scenes"]) {
      EXPECT_EQ(s["status"], "ok") << e.path() << ": " << s.dump();
      ++n;
    }
  }
  return n;
}

TEST(ClusterRecipes, GnuParallelLinesOfTheBatchDocsMatchASequentialBatch) {
  ASSERT_EQ(std::system("command -v parallel > /dev/null"), 0)
      << "GNU parallel is not installed (tools/setup.sh installs the Debian package `parallel`)";
  const std::vector<std::string> recipes = documented_parallel_lines();
  ASSERT_EQ(recipes.size(), 2u) << "the GNU parallel block of docs/batch.md changed";

  temp_dir root;
  const fs::path base = root.path() / "sequential";
  copy_suite(base);
  ASSERT_EQ(shell(base, "eulervop batch scenes/*.toml --out-dir out --jobs 1"), 0) << read_file(base / "out.log");
  const auto expected = references_under(base / "out");
  ASSERT_GE(expected.size(), 8u);

  for (std::size_t i = 0; i < recipes.size(); ++i) {
    SCOPED_TRACE(recipes[i]);
    const fs::path dir = root.path() / ("recipe" + std::to_string(i));
    copy_suite(dir);
    ASSERT_EQ(shell(dir, recipes[i]), 0) << read_file(dir / "out.log");
    const auto got = references_under(dir / "out");
    EXPECT_EQ(got.size(), expected.size());
    for (const auto& [name, texts] : expected) {
      ASSERT_TRUE(got.contains(name)) << name << " has no output";
      ASSERT_EQ(got.at(name).size(), 1u) << name << " was written more than once";
      EXPECT_TRUE(got.at(name)[0] == texts[0]) << name << ": differs from the sequential batch";
    }
    EXPECT_EQ(scenes_in_manifests(dir / "out"), expected.size()) << "every scene in exactly one manifest";
  }
}

}  // namespace
