// Outputs: nothing presented as a result before a run finishes; interrupted runs resume.
#include "cmc/output/Writer.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace cmc;
namespace fs = std::filesystem;

namespace {
Case small_case() {
  return parse_case(toml::parse(R"(
[case]
name = "w"
[grid]
n = 32
size = 1e-3
boundary = "free"
[material]
contact_modulus = 1e6
[surface]
kind = "sphere"
radius = 1e-2
[loading]
control = "force"
values = [1e-4, 2e-4, 4e-4]
[solver]
tolerance = 1e-12
)"),
                    "mem");
}
fs::path fresh_dir(const std::string& name) {
  auto d = fs::temp_directory_path() / ("cmc_writer_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(d);
  return d;
}
std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

TEST(Writer, WritesSummaryAndFieldsOnlyWhenFinished) {
  const Case c = small_case();
  Scene s = build_scene(c);
  const auto dir = fresh_dir("finish");
  {
    Writer w(dir, c, s);
    RunSummary run = run_scene(c, s, [&](const StepRecord& r, const ContactState& st) {
      w.add_step(r, st);
      EXPECT_FALSE(fs::exists(dir / "summary.json"));  // nothing final mid-run
      EXPECT_FALSE(fs::exists(dir / "result.h5"));
    });
    w.finish(run);
  }
  ASSERT_TRUE(fs::exists(dir / "summary.json"));
  ASSERT_TRUE(fs::exists(dir / "result.h5"));
  ASSERT_TRUE(fs::exists(dir / "result.xdmf"));
  EXPECT_FALSE(fs::exists(dir / ".progress.toml"));  // partial-run files are gone
  const std::string j = slurp(dir / "summary.json");
  const auto st = j.find("\"status\"");
  ASSERT_NE(st, std::string::npos);
  EXPECT_EQ(j.find("\"converged\"", st), j.find('"', j.find(':', st)));  // "status" : "converged"
  EXPECT_NE(j.find("\"steps\""), std::string::npos);
  fs::remove_all(dir);
}

TEST(Writer, ResumesAnInterruptedRun) {
  const Case c = small_case();
  const auto full_dir = fresh_dir("full"), dir = fresh_dir("resume");
  // Reference: an uninterrupted run.
  Scene s0 = build_scene(c);
  RunSummary full = run_scene(c, s0, {});
  // An interrupted run: two of three steps, then the program "dies" (no finish()).
  {
    Scene s = build_scene(c);
    s.targets.resize(2);
    Writer w(dir, c, s);
    run_scene(c, s, [&](const StepRecord& r, const ContactState& st) { w.add_step(r, st); });
  }
  EXPECT_FALSE(fs::exists(dir / "summary.json"));
  // Resumed: skips the finished steps and warm-starts from the checkpoint.
  Scene s = build_scene(c);
  Writer w(dir, c, s, true);
  ASSERT_EQ(w.resume_point().done.size(), 2u);
  int solved = 0;
  RunSummary run = run_scene(c, s, [&](const StepRecord& r, const ContactState& st) { w.add_step(r, st), ++solved; }, {},
                             &w.resume_point().done, &w.resume_point().state);
  w.finish(run);
  EXPECT_EQ(solved, 1);
  ASSERT_EQ(run.steps.size(), 3u);
  EXPECT_EQ(run.status, RunStatus::Converged);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(run.steps[k].penetration, full.steps[k].penetration, 1e-9 * full.steps[k].penetration);
  // A different case (another --set) does not resume from these files.
  Case other = small_case();
  other.resolved.insert_or_assign("solver", toml::table{{"tolerance", 1e-6}});
  {
    Scene s2 = build_scene(c);
    Writer w2(dir, c, s2);
    run_scene(c, s2, [&](const StepRecord& r, const ContactState& st) { w2.add_step(r, st); });
  }
  Scene s3 = build_scene(other);
  EXPECT_THROW(Writer(dir, other, s3, true), CaseError);
  fs::remove_all(dir);
  fs::remove_all(full_dir);
}
