#include "io/output_dir.hpp"

#include "io/atomic_file.hpp"
#include "compute/scene_library.hpp"

#include <fmt/format.h>

namespace eulervop::app {

namespace fs = std::filesystem;

output_dir::output_dir(const fs::path& dir, const std::string& probe_file) : dir_(dir) {
  const std::string where = fmt::format("--out-dir {}", dir.string());
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) throw input_error(fmt::format("{}: exists and is not a directory", where));
  } else {
    created_ = fs::create_directories(dir, ec);
    if (ec) throw input_error(fmt::format("{}: cannot create the directory: {}", where, ec.message()));
  }
  try {
    atomic_file probe(dir / probe_file);  // removed again on scope exit
  } catch (const input_error& e) {
    std::string why = e.what();
    if (why.starts_with("--out ")) why = why.substr(6);
    remove_if_created();
    throw input_error(fmt::format("{}: {}", where, why));
  }
}

output_dir::~output_dir() {
  if (!kept_) remove_if_created();
}

void output_dir::remove_if_created() noexcept {
  std::error_code ec;
  if (created_) fs::remove(dir_, ec);  // only if empty
}

fs::path out_dir_of(const std::optional<std::string>& flag, std::string_view command) {
  if (flag && flag->empty()) throw input_error("--out-dir: empty path");
  return flag ? fs::path(*flag) : fs::path(fmt::format("eulervop-{}", command));
}

void write_atomically(const fs::path& path, const std::string& text) {
  atomic_file f(path);
  f.write(text);
  f.commit();
}

}  // namespace eulervop::app
