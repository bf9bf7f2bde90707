// The one output-file helper (grid/FilePaths.hpp) and the run folder's rules
// (output/RunFolder.hpp): only new paths and regular files are written, atomically, and a
// failed write leaves no temporary file behind.
#include "cmc/grid/FilePaths.hpp"
#include "cmc/output/RunFolder.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

using namespace cmc;
namespace fs = std::filesystem;

namespace {
// An empty folder of this test's own (the process id keeps parallel runs apart).
fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("cmc_paths_" + std::to_string(::getpid()) + "_" + name);
  return fs::remove_all(d), fs::create_directories(d), d;
}
// The first line of a file.
std::string line_of(const fs::path& p) {
  std::string l;
  std::getline(std::ifstream(p) >> std::ws, l);
  return l;
}
// The message of the OutputPathError `f` throws ("" when it throws none).
template <class F>
std::string refusal(F&& f) {
  try {
    f();
  } catch (const OutputPathError& e) {
    return e.what();
  }
  return "";
}
std::size_t entries(const fs::path& d) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(d)) ++n;
  return n;
}
}  // namespace

TEST(OutputPaths, RefusesSpecialFilesAndLeavesThemAsTheyAre) {
  const fs::path d = fresh_dir("special");
  ASSERT_EQ(::mkfifo((d / "fifo").c_str(), 0644), 0);
  fs::create_directory(d / "folder");
  fs::create_symlink("target.txt", d / "link");
  for (const char* name : {"fifo", "folder", "link"}) {
    const std::string e = refusal([&] { write_output_text(d / name, "text"); });
    EXPECT_NE(e.find(name), std::string::npos) << name << ": " << e;
  }
  EXPECT_TRUE(fs::is_fifo(d / "fifo"));
  EXPECT_TRUE(fs::is_directory(d / "folder"));
  EXPECT_TRUE(fs::is_symlink(d / "link"));
  EXPECT_FALSE(fs::exists(d / "target.txt"));  // not written through the link
  EXPECT_NE(refusal([&] { write_output_text(d / "link", "x"); }).find("symbolic link (to target.txt)"),
            std::string::npos);
  EXPECT_EQ(entries(d), 3u);  // no temporary file left
  // A device is refused by the check alone (nothing is opened or written).
  EXPECT_NE(refusal([] { check_output_file("/dev/null"); }).find("character device"), std::string::npos);
  EXPECT_NE(refusal([&] { remove_output_file(d / "fifo"); }).find("FIFO"), std::string::npos);
}

TEST(OutputPaths, WritesNewPathsAndReplacesRegularFiles) {
  const fs::path d = fresh_dir("regular");
  write_output_text(d / "a.txt", "one");
  EXPECT_EQ(line_of(d / "a.txt"), "one");
  write_output_text(d / "a.txt", "two");
  EXPECT_EQ(line_of(d / "a.txt"), "two");
  EXPECT_EQ(entries(d), 1u);
  // A folder that does not exist is bad input (it was exit 4, "cannot create .x.tmpPID").
  EXPECT_NE(refusal([&] { write_output_text(d / "absent" / "x.txt", "x"); }).find("its folder"), std::string::npos);
}

TEST(OutputPaths, AFailedWriteLeavesNoTemporaryFile) {
  // As a full disk would: the temporary file is written, then writing fails.
  const fs::path d = fresh_dir("failed");
  write_output_text(d / "kept.txt", "earlier");
  EXPECT_THROW(write_output_file(d / "kept.txt",
                                 [](const fs::path& tmp) {
                                   std::ofstream(tmp) << "half";
                                   throw std::runtime_error("write failed (disk full?)");
                                 }),
               std::runtime_error);
  EXPECT_EQ(line_of(d / "kept.txt"), "earlier");
  EXPECT_EQ(entries(d), 1u);
}

TEST(OutputPaths, OutputFolders) {
  EXPECT_NE(refusal([] { check_output_folder("/"); }).find("root folder"), std::string::npos);
  EXPECT_NE(refusal([] { check_output_folder("/dev/null"); }).find("expected a folder"), std::string::npos);
  const fs::path d = fresh_dir("folders");
  EXPECT_EQ(refusal([&] { check_output_folder(d); }), "");
  EXPECT_EQ(refusal([&] { check_output_folder(d / "new"); }), "");
}

TEST(OutputPaths, InputFileProblemsSayWhatThePathIs) {
  const fs::path d = fresh_dir("inputs");
  fs::create_symlink("loop", d / "loop");
  EXPECT_EQ(input_file_problem(d), "is a folder, expected a file");
  EXPECT_NE(input_file_problem(d / "loop").find("symbolic link that cannot be resolved"), std::string::npos);
  EXPECT_EQ(input_file_problem(d / "absent"), "no such file");
  EXPECT_NE(input_file_problem("/dev/zero").find("character device"), std::string::npos);
}

TEST(RunFolder, ReplacesOnlyItsOwnResults) {
  const fs::path d = fresh_dir("foreign");
  std::ofstream(d / "summary.json") << "{\"mine\": 1}\n";
  EXPECT_NE(refusal([&] { clear_earlier_results(d); }).find("not a cmc run summary"), std::string::npos);
  EXPECT_EQ(line_of(d / "summary.json"), "{\"mine\": 1}");
  fs::remove(d / "summary.json");
  std::ofstream(d / "result.h5") << "user's";
  EXPECT_NE(refusal([&] { clear_earlier_results(d); }).find("holds no cmc run"), std::string::npos);
  std::ofstream(d / "summary.json") << "{\"cmc_version\": \"0.1.0\"}\n";
  // What a process killed while writing leaves: removed; a user's file alike in name: kept.
  fs::create_directory(d / ".partial");
  std::ofstream(d / ".partial" / ".checkpoint.h5.tmp123") << "half";
  std::ofstream(d / ".result.h5.tmp77") << "half";
  std::ofstream(d / ".notes.tmp5") << "mine";
  EXPECT_EQ(refusal([&] { clear_earlier_results(d); }), "");
  EXPECT_EQ(entries(d), 2u);  // .partial/ and .notes.tmp5
  EXPECT_EQ(entries(d / ".partial"), 0u);
}

TEST(RunFolder, DamagedStepFilesAreNamed) {
  const fs::path d = fresh_dir("steps");
  EXPECT_NE(step_file_problem(d / "step_0003.h5", 3, 64, 64, true).find("are missing"), std::string::npos);
  std::ofstream(d / "step_0003.h5") << std::string(1000, 'x');  // as a truncated file
  EXPECT_NE(step_file_problem(d / "step_0003.h5", 3, 64, 64, true).find("not a readable HDF5 file"), std::string::npos);
}
