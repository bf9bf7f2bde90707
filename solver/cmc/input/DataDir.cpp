#include "cmc/input/DataDir.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>

namespace cmc::data {

namespace fs = std::filesystem;

namespace {

// How many folders above the running code's own are looked at: PREFIX/lib/python3.X/
// site-packages/cmc/_core.so is four below PREFIX.
constexpr int kLevelsUp = 4;

bool is_data_folder(const fs::path& dir) {
  std::error_code ec;
  return fs::is_directory(dir / "cases", ec) && fs::is_directory(dir / "reference", ec);
}

// The files the running code was loaded from: the object that holds this function (the
// program, or the Python module) and the program itself.
std::vector<fs::path> loaded_from() {
  std::vector<fs::path> out;
  std::error_code ec;
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&is_data_folder), &info) != 0 && info.dli_fname && *info.dli_fname &&
      fs::path(info.dli_fname).is_absolute())
    out.push_back(fs::weakly_canonical(info.dli_fname, ec));
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) out.push_back(self);
  return out;
}

void add(std::vector<fs::path>& out, const fs::path& p) {
  const fs::path clean = p.lexically_normal();
  if (!clean.empty() && std::find(out.begin(), out.end(), clean) == out.end()) out.push_back(clean);
}

}  // namespace

std::vector<fs::path> places() {
  std::vector<fs::path> out;
  if (const char* env = std::getenv("CMC_DATA_DIR"); env && *env) add(out, env);
  for (const fs::path& file : loaded_from()) {
    fs::path dir = file.parent_path();
    for (int level = 0; level <= kLevelsUp && !dir.empty(); ++level, dir = dir.parent_path()) {
      add(out, dir / "share" / "cmc");
      add(out, dir);
      if (dir == dir.root_path()) break;
    }
  }
#ifdef CMC_INSTALL_DATA_DIR
  add(out, CMC_INSTALL_DATA_DIR);
#endif
#ifdef CMC_SOURCE_DIR
  add(out, CMC_SOURCE_DIR);
#endif
  return out;
}

fs::path root() {
  for (const fs::path& p : places())
    if (is_data_folder(p)) return p;
  return {};
}

std::string places_text() {
  std::string list;
  for (const fs::path& p : places()) list.append(list.empty() ? "" : ", ").append(p.string());
  return "looked for a folder holding cases/ and reference/ in " + list + " (set CMC_DATA_DIR to name it)";
}

fs::path find(const fs::path& path) {
  std::error_code ec;
  if (path.empty() || fs::exists(path, ec) || path.is_absolute()) return path;
  const fs::path dir = root();
  if (!dir.empty() && fs::exists(dir / path, ec)) return dir / path;
  return path;
}

}  // namespace cmc::data
