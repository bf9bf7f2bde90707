// The folder layout of solver/cmc/ shows the data flow
//     case file -> input -> scene -> contact (solvers) -> observe -> run -> output,
// with grid/ (fields, FFTs, reductions), elastic/ (the half-space) and surface/
// (topographies) underneath and analytic/ (closed-form references) on its own. A folder may
// include only the folders upstream of it: this test reads every #include "cmc/<folder>/…"
// and fails on one that points downstream (e.g. a solver that includes the writer). One
// exception: input/ asks each solver for its memory count (contact/Memory.hpp and
// contact/<solver>/Memory.hpp), headers of plain numbers that include nothing of cmc but
// each other.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {
// What each folder may include (besides itself). Keep the table of
// docs/developer/architecture.md in step.
const std::map<std::string, std::set<std::string>> kAllowed = {
    {"grid", {}},
    {"analytic", {}},
    {"input", {}},
    {"elastic", {"grid"}},
    {"surface", {"grid"}},
    {"contact", {"grid", "elastic"}},
    {"scene", {"grid", "input", "surface", "elastic", "contact"}},
    {"observe", {"grid", "input", "surface", "elastic", "contact", "scene"}},
    {"run", {"grid", "input", "surface", "elastic", "contact", "scene", "observe"}},
    {"output", {"grid", "input", "surface", "elastic", "contact", "scene", "observe", "run"}},
};
// The solvers' memory counts, which input/ may include.
const std::regex kMemoryCount(R"(#\s*include\s*"cmc/contact/([a-z_]+/)?Memory\.hpp")");
bool is_memory_count(const fs::path& relative) {
  return std::regex_match(relative.generic_string(), std::regex(R"(contact/([a-z_]+/)?Memory\.hpp)"));
}
}  // namespace

TEST(Layout, FoldersIncludeOnlyUpstream) {
  const fs::path root = fs::path(CMC_SOURCE_DIR) / "solver" / "cmc";
  const std::regex include(R"(#\s*include\s*"cmc/([a-z]+)/)");
  std::ostringstream bad;
  std::set<std::string> seen;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    if (!e.is_regular_file()) continue;
    const std::string folder = fs::relative(e.path(), root).begin()->string();
    seen.insert(folder);
    const auto it = kAllowed.find(folder);
    if (it == kAllowed.end()) {
      bad << "\n  " << e.path().string() << ": folder '" << folder << "' is not in the layout (add it to kAllowed and docs/developer/architecture.md)";
      continue;
    }
    const bool memory_count = is_memory_count(fs::relative(e.path(), root));
    std::ifstream in(e.path());
    std::string line;
    for (int no = 1; std::getline(in, line); ++no) {
      std::smatch m;
      if (!std::regex_search(line, m, include)) continue;
      const std::string dep = m[1];
      const bool counts = std::regex_search(line, kMemoryCount);
      if (memory_count && !counts)
        bad << "\n  " << e.path().string() << ":" << no << ": a memory count includes more than the other counts";
      else if (dep != folder && !it->second.count(dep) && !(folder == "input" && counts))
        bad << "\n  " << e.path().string() << ":" << no << ": " << folder << "/ includes " << dep << "/ (downstream)";
    }
  }
  EXPECT_TRUE(bad.str().empty()) << "layout broken:" << bad.str();
  EXPECT_TRUE(seen.count("grid") && seen.count("contact") && seen.count("output")) << "did not find the sources";
}
