// docs/user-guide/case-files.md documents every key with its default; the code's defaults
// are the spec structs' initialisers, listed by case_defaults(). This test reads that page's
// tables and fails when a documented default differs from the code's, or when a key is
// documented in one and missing from the other, so the two cannot drift apart again.
#include "cmc/input/Case.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

using namespace cmc;

namespace {

using Key = std::pair<std::string, std::string>;  // section, key

std::string trim(std::string s) {
  const auto b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

// The cells of a markdown table row; "\|" inside a cell is not a separator.
std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::string cell;
  for (std::size_t i = 1; i < row.size(); ++i) {
    if (row[i] == '\\' && i + 1 < row.size() && row[i + 1] == '|') cell += row[++i];
    else if (row[i] == '|') out.push_back(trim(cell)), cell.clear();
    else cell += row[i];
  }
  return out;
}

std::string without_backticks(std::string s) {
  s.erase(std::remove(s.begin(), s.end(), '`'), s.end());
  return s;
}

// (section, key) -> default column, from every "### `[section]`" table with a default column.
std::map<Key, std::string> documented_defaults(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << "cannot read " << path;
  std::map<Key, std::string> out;
  const std::regex heading(R"(^### `\[(\w+)\]`)"), key_name("`(\\w+)`");
  std::string line, section;
  int default_column = -1;
  while (std::getline(in, line)) {
    std::smatch m;
    if (std::regex_search(line, m, heading)) {
      section = m[1], default_column = -1;
      continue;
    }
    if (section.empty() || line.rfind("|", 0) != 0) continue;
    const auto c = cells(line);
    if (default_column < 0) {  // the header row
      for (std::size_t i = 0; i < c.size(); ++i)
        if (c[i] == "default") default_column = int(i);
      if (default_column < 0) section.clear();  // a table without defaults ([validation])
      continue;
    }
    if (c.empty() || c[0].rfind("---", 0) == 0 || int(c.size()) <= default_column) continue;
    for (auto it = std::sregex_iterator(c[0].begin(), c[0].end(), key_name); it != std::sregex_iterator(); ++it)
      out[{section, (*it)[1]}] = without_backticks(c[std::size_t(default_column)]);
  }
  return out;
}

}  // namespace

TEST(Defaults, CaseFilesPageMatchesTheCode) {
  const auto docs = documented_defaults(std::string(CMC_SOURCE_DIR) + "/docs/user-guide/case-files.md");
  ASSERT_GT(docs.size(), 40u) << "the key tables of docs/user-guide/case-files.md were not found";
  std::map<Key, std::string> code;
  for (const auto& d : case_defaults()) code[{d.section, d.key}] = d.text;
  for (const auto& [key, text] : docs) {
    const auto it = code.find(key);
    if (it == code.end()) {
      ADD_FAILURE() << "[" << key.first << "] " << key.second << " is documented but has no default in the code";
      continue;
    }
    EXPECT_EQ(text, it->second) << "[" << key.first << "] " << key.second
                                << ": docs/user-guide/case-files.md documents the default on the left, the code uses the right";
  }
  for (const auto& [key, text] : code)
    EXPECT_TRUE(docs.count(key)) << "[" << key.first << "] " << key.second << " (default " << text
                                 << ") is not documented in docs/user-guide/case-files.md";
}

// The table states what the parser does: a case that gives only the required keys gets
// exactly these values.
TEST(Defaults, ParserUsesTheTable) {
  const toml::table t = toml::parse(R"(
[case]
name = "d"
[grid]
n = 8
size = 1.0
[material]
contact_modulus = 1.0
[surface]
kind = "self_affine"
[loading]
control = "force"
values = [0.1]
)");
  const Case c = parse_case(t, "mem");
  const SurfaceSpec sf;
  EXPECT_EQ(c.surface.hurst, sf.hurst);
  EXPECT_EQ(c.surface.seed, sf.seed);
  EXPECT_EQ(c.surface.rolloff_wavelength, SurfaceSpec::kRolloffFraction);
  EXPECT_EQ(c.surface.cutoff_wavelength, SurfaceSpec::kCutoffFraction);
  EXPECT_EQ(c.solver.recompute_every, SolverSpec{}.recompute_every);
  EXPECT_EQ(c.solver.tolerance, SolverSpec::kPolonskyKeerTolerance);
  EXPECT_EQ(c.loading.max_halvings, LoadingSpec{}.max_halvings);
  EXPECT_EQ(c.observables.cross_section_x, ObservablesSpec::kCrossSectionFraction);
  EXPECT_EQ(c.observables.stress_bins, ObservablesSpec{}.stress_bins);
  // And the resolved case shows them as docs/user-guide/case-files.md does.
  EXPECT_EQ(c.resolved["solver"]["recompute_every"].value<int64_t>(), 32);
  EXPECT_EQ(c.resolved["surface"]["hurst"].value<double>(), 0.8);
}
