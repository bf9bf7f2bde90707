// Where cmc finds the files it ships (input/DataDir.hpp): $CMC_DATA_DIR first, then beside
// the running program (here the test program in the build folder, below the checkout), and
// the stored references and case files looked up there. An installed cmc relies on this to
// run `cmc run cases/...` from any folder; tests/install/install_test.py checks it on an
// installed tree, these the rules themselves.
#include "References.hpp"
#include "cmc/input/Case.hpp"
#include "cmc/input/DataDir.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

using namespace cmc;
namespace fs = std::filesystem;

namespace {

// Sets an environment variable for one test and puts back what was there.
class EnvVar {
 public:
  EnvVar(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~EnvVar() { old_ ? ::setenv(name_, old_->c_str(), 1) : ::unsetenv(name_); }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

// A data folder of one test (cases/ and reference/), removed afterwards.
class DataFolder {
 public:
  DataFolder() : dir_(fs::temp_directory_path() / ("cmc_data_dir_" + std::to_string(::getpid()))) {
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "cases" / "mine");
    fs::create_directories(dir_ / "reference");
  }
  ~DataFolder() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  const fs::path& path() const { return dir_; }

 private:
  fs::path dir_;
};

std::string error_of(const std::string& file) {
  try {
    load_case(file);
  } catch (const CaseError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// $CMC_DATA_DIR is looked at first; the running program's own folder and the ones above it
// follow, each as FOLDER/share/cmc (an install) and as FOLDER (a checkout).
TEST(DataDir, LooksInTheNamedFolderFirstThenBesideTheProgram) {
  DataFolder data;
  EnvVar env("CMC_DATA_DIR", data.path().string());
  const auto places = data::places();
  ASSERT_FALSE(places.empty());
  EXPECT_EQ(places.front(), data.path());
  EXPECT_EQ(data::root(), data.path());
  const fs::path program_dir = fs::read_symlink("/proc/self/exe").parent_path();
  EXPECT_NE(std::find(places.begin(), places.end(), program_dir / "share" / "cmc"), places.end());
  EXPECT_NE(data::places_text().find(data.path().string()), std::string::npos) << data::places_text();
}

// Without $CMC_DATA_DIR the test program (BUILD/cmc_tests) finds the checkout above its
// build folder: the cases and references it ships.
TEST(DataDir, TheBuildFindsItsCheckout) {
  ::unsetenv("CMC_DATA_DIR");
  EXPECT_TRUE(fs::exists(data::root() / "cases" / "validation" / "hertz-free.toml")) << data::places_text();
  EXPECT_TRUE(fs::exists(data::root() / "reference" / "challenge")) << data::places_text();
}

// A relative case file, or a relative base, that is not where it was named is taken from the
// data folder; a missing one's message names both places looked.
TEST(DataDir, CaseFilesAndBasesFromTheDataFolder) {
  DataFolder data;
  EnvVar env("CMC_DATA_DIR", data.path().string());
  std::ifstream common(fs::path(CMC_SOURCE_DIR) / "tests" / "data" / "bases" / "common.toml");
  std::ofstream(data.path() / "cases" / "mine" / "base.toml")
      << common.rdbuf() << "[surface]\nkind = \"sphere\"\nradius = 1e-2\n";
  std::ofstream(data.path() / "cases" / "mine" / "case.toml") << "base = \"base.toml\"\n[case]\nname = \"installed\"\n";
  EXPECT_EQ(load_case("cases/mine/case.toml").name, "installed");  // not in the working folder
  EXPECT_EQ(data::find("cases/mine/case.toml"), data.path() / "cases" / "mine" / "case.toml");

  const fs::path own = data.path().parent_path() / ("cmc_own_case_" + std::to_string(::getpid()) + ".toml");
  std::ofstream(own) << "base = \"cases/mine/base.toml\"\n[case]\nname = \"own\"\n";
  EXPECT_EQ(load_case(own.string()).name, "own");  // its base: not beside it, found installed
  std::ofstream(own) << "base = \"cases/mine/nope.toml\"\n[case]\nname = \"own\"\n";
  const std::string m = error_of(own.string());
  EXPECT_NE(m.find("no such file (nor " + (data.path() / "cases" / "mine" / "nope.toml").string() + ")"),
            std::string::npos)
      << m;
  fs::remove(own);
  const std::string missing = error_of("cases/mine/absent.toml");
  EXPECT_NE(missing.find("(nor " + (data.path() / "cases" / "mine" / "absent.toml").string() + ")"), std::string::npos)
      << missing;
}

// The stored references: $CMC_REFERENCE_DIR, else the data folder's reference/.
TEST(DataDir, StoredReferencesAreTheDataFoldersUnlessNamed) {
  DataFolder data;
  EnvVar env("CMC_DATA_DIR", data.path().string());
  EXPECT_EQ(reference::default_reference_dir(), (data.path() / "reference").string());
  EXPECT_EQ(reference::reference_dir_note(), "");
  EnvVar named("CMC_REFERENCE_DIR", "/elsewhere/refs");
  EXPECT_EQ(reference::default_reference_dir(), "/elsewhere/refs");
}
