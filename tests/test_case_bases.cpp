// Case files with a shared base (base = "other.toml", input/CaseFile.cpp): the merge (the
// including file's keys over the base's, table by table), nested bases, relative paths,
// and every error (a missing base, a folder, a cycle, too deep a chain, a table against a
// value, a base that is not a string) exiting as a CaseError that names both files and the key.
#include "cmc/input/Case.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>

using namespace cmc;
namespace fs = std::filesystem;

namespace {

// A fresh folder for one test's files, removed afterwards.
class Folder {
 public:
  Folder() {
    static int k = 0;
    dir_ = fs::temp_directory_path() / ("cmc_case_bases_" + std::to_string(::getpid()) + "_" + std::to_string(k++));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  ~Folder() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string write(const std::string& name, const std::string& text) const {
    const fs::path p = dir_ / name;
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
    return p.string();
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

 private:
  fs::path dir_;
};

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}
// A base holding everything but the case's name and its surface: grid, material, load.
const std::string kBaseNoSurface = read_text(fs::path(CMC_SOURCE_DIR) / "tests/data/bases/common.toml");
// The same with a sphere: a whole case but for its name.
const std::string kBase = kBaseNoSurface + "[surface]\nkind = \"sphere\"\nradius = 1e-2\n";

// The message of the CaseError that loading `file` throws ("" and a failure if none).
std::string error_of(const std::string& file) {
  try {
    load_case(file);
  } catch (const CaseError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for " << file;
  return "";
}

void expect_names(const std::string& message, const std::vector<std::string>& parts) {
  for (const auto& p : parts) EXPECT_NE(message.find(p), std::string::npos) << "'" << p << "' not in: " << message;
}

}  // namespace

TEST(CaseBases, IncludingFileOverridesTableByTable) {
  Folder d;
  d.write("base.toml", kBase);
  const Case c = load_case(d.write("case.toml", R"(base = "base.toml"
[case]
name = "t"
[grid]
n = 32
[loading]
values = [3e-4]
)"));
  EXPECT_EQ(c.name, "t");
  EXPECT_EQ(c.grid.nx, 32);                 // the including file's key
  EXPECT_DOUBLE_EQ(c.grid.size_x, 1e-3);    // the rest of its table from the base
  EXPECT_DOUBLE_EQ(c.contact_modulus, 1e6);  // a table only the base has
  EXPECT_EQ(c.loading.values, std::vector<double>{3e-4});  // an array replaced whole
  EXPECT_DOUBLE_EQ(c.solver.tolerance, 1e-9);
  EXPECT_FALSE(c.resolved.contains("base"));  // the resolved case names no base
  EXPECT_EQ(c.file, d.path("case.toml"));
}

TEST(CaseBases, ResolvedCaseEqualsTheWrittenOutCase) {
  // A case with a base resolves to the same table as the one file it stands for.
  Folder d;
  d.write("base.toml", kBase);
  const Case with_base = load_case(d.write("case.toml", "base = \"base.toml\"\n[case]\nname = \"t\"\n"));
  const Case whole = load_case(d.write("whole.toml", kBase + "[case]\nname = \"t\"\n"));
  EXPECT_EQ(with_base.resolved, whole.resolved);
}

TEST(CaseBases, NestedBasesInOtherFolders) {
  // case -> sub/middle.toml -> ../common/root.toml; each base's path is relative to the
  // file that names it, and so is a relative [surface] path stated in a base.
  Folder d;
  d.write("common/root.toml", kBaseNoSurface + "[output]\nfields = false\n");
  d.write("sub/middle.toml", R"(base = "../common/root.toml"
[grid]
n = 8
[surface]
kind = "file"
path = "heights.txt"
format = "ascii"
)");
  const Case c = load_case(d.write("case.toml", "base = \"sub/middle.toml\"\n[case]\nname = \"t\"\n"));
  EXPECT_EQ(c.grid.nx, 8);
  EXPECT_FALSE(c.write_fields);
  EXPECT_EQ(c.surface.path, "sub/heights.txt");  // read from sub/, where middle.toml is
}

TEST(CaseBases, OverridesApplyAfterTheBase) {
  Folder d;
  d.write("base.toml", kBase);
  const Case c = load_case(d.write("case.toml", "base = \"base.toml\"\n[case]\nname = \"t\"\n"), {"grid.n=64"});
  EXPECT_EQ(c.grid.nx, 64);
}

TEST(CaseBases, MissingBaseNamesBothFiles) {
  Folder d;
  const std::string f = d.write("case.toml", "base = \"nope.toml\"\n[case]\nname = \"t\"\n");
  expect_names(error_of(f), {f, "base = \"nope.toml\"", d.path("nope.toml"), "no such file"});
}

TEST(CaseBases, BaseThatIsAFolderOrNotAStringIsRefused) {
  Folder d;
  fs::create_directories(d.path("dir.toml"));
  const std::string f = d.write("case.toml", "base = \"dir.toml\"\n[case]\nname = \"t\"\n");
  expect_names(error_of(f), {f, "base = \"dir.toml\"", "is a folder"});
  const std::string g = d.write("number.toml", "base = 3\n[case]\nname = \"t\"\n");
  expect_names(error_of(g), {g, "base: expected the path of a base case file (a string)", "an integer"});
}

TEST(CaseBases, BaseThatIsNotTomlNamesBothFiles) {
  Folder d;
  d.write("bad.toml", "[grid\n");
  const std::string f = d.write("case.toml", "base = \"bad.toml\"\n[case]\nname = \"t\"\n");
  expect_names(error_of(f), {f, "base = \"bad.toml\"", d.path("bad.toml"), "not valid TOML at line 1"});
}

TEST(CaseBases, CycleIsRefused) {
  Folder d;
  d.write("a.toml", "base = \"b.toml\"\n[case]\nname = \"t\"\n");
  d.write("b.toml", "base = \"a.toml\"\n");
  const std::string m = error_of(d.path("a.toml"));
  expect_names(m, {d.path("b.toml") + ": base = \"a.toml\"", "a.toml -> b.toml -> a.toml", "a cycle of bases"});
  const std::string self = d.write("self.toml", "base = \"self.toml\"\n");
  expect_names(error_of(self), {self + ": base = \"self.toml\"", "a cycle of bases"});
}

TEST(CaseBases, ChainDeeperThanTheLimitIsRefused) {
  Folder d;
  const int deep = CaseLimits::kMaxBaseDepth;
  // b0 -> b1 -> ... -> b<deep>: deep bases, accepted; one more is refused.
  d.write("b" + std::to_string(deep) + ".toml", kBase);
  for (int k = deep - 1; k >= 0; --k)
    d.write("b" + std::to_string(k) + ".toml", "base = \"b" + std::to_string(k + 1) + ".toml\"\n");
  EXPECT_EQ(load_case(d.write("ok.toml", "base = \"b1.toml\"\n[case]\nname = \"t\"\n")).grid.nx, 16);
  const std::string m = error_of(d.write("deep.toml", "base = \"b0.toml\"\n[case]\nname = \"t\"\n"));
  expect_names(m, {"base = \"b" + std::to_string(deep) + ".toml\"", "more than " + std::to_string(deep) + " bases deep"});
}

TEST(CaseBases, TableAgainstValueNamesBothFilesAndTheKey) {
  Folder d;
  const std::string base = d.write("base.toml", kBase);
  const std::string f = d.write("case.toml", "base = \"base.toml\"\ngrid = 3\n[case]\nname = \"t\"\n");
  expect_names(error_of(f), {f + ": [grid]: an integer here (line 2), a table in its base " + base,
                             "a table in both files or in neither"});
  const std::string g = d.write("sub.toml", "base = \"base.toml\"\n[case]\nname = \"t\"\n[grid.n]\nx = 1\n");
  expect_names(error_of(g), {g + ": [grid] n: a table here", "an integer in its base " + base});
}
