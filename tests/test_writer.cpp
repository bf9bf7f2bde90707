// Outputs: nothing presented as a result before a run finishes; interrupted runs resume.
#include "cmc/output/Writer.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>

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
  // What decides the round-off (docs/developer/reproducibility.md): the thread count and the
  // fingerprint of the build's FFT plans, 16 hex digits.
  EXPECT_NE(j.find("\"threads\" : " + std::to_string(thread_count())), std::string::npos);
  const std::string fp = builtin_wisdom_fingerprint();
  EXPECT_EQ(fp.size(), 16u);
  EXPECT_EQ(fp.find_first_not_of("0123456789abcdef"), std::string::npos);
  EXPECT_NE(j.find("\"fft_wisdom_fingerprint\" : \"" + fp + "\""), std::string::npos);
  fs::remove_all(dir);
}

// After a run's last solve only the output follows: no checkpoint of a state that is written
// next anyway (three fields: 26 GB at 32768²). Three load steps, two checkpoints, and the
// test point of the last step still passed (resume_test.py kills there).
TEST(Writer, NoCheckpointAfterTheLastStep) {
  const Case c = small_case();
  Scene s = build_scene(c);
  ASSERT_EQ(s.targets.size(), 3u);
  int checkpoints = 0;
  run_scene(c, s, {}, {}, nullptr, [&](const ContactState&, const PathState*, const OuterPoint*) { ++checkpoints; });
  EXPECT_EQ(checkpoints, 2);
}

TEST(Writer, ResumesAnInterruptedRun) {
  const Case c = small_case();
  const auto full_dir = fresh_dir("full"), dir = fresh_dir("resume");
  // Reference: an uninterrupted run.
  Scene s0 = build_scene(c);
  RunSummary full = run_scene(c, s0, {});
  // An interrupted run: two of three steps, then the program "dies" (no finish()) while the
  // third is being recorded, before its checkpoint. (Not by stopping at two targets: after a
  // run's last step no checkpoint is written, Driver.cpp's after_step.)
  struct Died {};
  {
    Scene s = build_scene(c);
    Writer w(dir, c, s);
    EXPECT_THROW(run_scene(
                     c, s,
                     [&](const StepRecord& r, const ContactState& st) {
                       if (r.index == 2) throw Died{};
                       w.add_step(r, st);
                     },
                     {}, nullptr,
                     [&](const ContactState& st, const PathState* p, const OuterPoint* in) { w.checkpoint(st, p, in); }),
                 Died);
  }
  EXPECT_FALSE(fs::exists(dir / "summary.json"));
  EXPECT_TRUE(fs::exists(dir / "INCOMPLETE"));
  // Resumed: skips the finished steps and warm-starts from the checkpoint.
  Scene s = build_scene(c);
  Writer w(dir, c, s, true);
  ASSERT_TRUE(w.resuming());
  ASSERT_EQ(w.resume_point().done.size(), 2u);
  int solved = 0;
  RunSummary run = run_scene(c, s, [&](const StepRecord& r, const ContactState& st) { w.add_step(r, st), ++solved; }, {},
                             &w.resume_point());
  w.finish(run);
  EXPECT_EQ(solved, 1);
  ASSERT_EQ(run.steps.size(), 3u);
  EXPECT_EQ(run.status, RunStatus::Converged);
  // Bit for bit: the resumed run goes on from the exact state the interrupted one stopped at.
  for (int k = 0; k < 3; ++k) EXPECT_EQ(run.steps[k].penetration, full.steps[k].penetration);
  EXPECT_FALSE(fs::exists(dir / "INCOMPLETE"));
  EXPECT_FALSE(fs::exists(dir / ".partial"));
  // A different case (another --set) does not resume from these files.
  Case other = small_case();
  other.resolved.insert_or_assign("solver", toml::table{{"tolerance", 1e-6}});
  {
    Scene s2 = build_scene(c);
    Writer w2(dir, c, s2);
    run_scene(c, s2, [&](const StepRecord& r, const ContactState& st) { w2.add_step(r, st); }, {}, nullptr,
              [&](const ContactState& st, const PathState* p, const OuterPoint* in) { w2.checkpoint(st, p, in); });
  }
  Scene s3 = build_scene(other);
  EXPECT_THROW(Writer(dir, other, s3, true), CaseError);
  fs::remove_all(dir);
  fs::remove_all(full_dir);
}

// RAII for HDF5 handles (surface/H5Handle.hpp): a write that fails half-way through a
// step (here an observables array whose name HDF5 rejects, after the step's group and
// its observables group were opened) throws, and leaves no HDF5 object open, not even
// the step's file (the Writer holds no file open between calls).
TEST(Writer, FailedWriteLeaksNoHdf5Handle) {
  const Case c = small_case();
  Scene s = build_scene(c);
  const auto dir = fresh_dir("leak");
  const unsigned objects = H5F_OBJ_GROUP | H5F_OBJ_DATASET | H5F_OBJ_DATATYPE | H5F_OBJ_ATTR;
  const ssize_t files_before = H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_FILE);
  ASSERT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, objects), 0);
  {
    Writer w(dir, c, s);
    bool threw = false;
    run_scene(c, s, [&](const StepRecord& r, const ContactState& st) {
      if (r.index != 0) return;
      StepRecord bad = r;
      bad.observables = ObservablesRecord{};
      bad.observables->arrays["no/such/group"] = {{1.0, 2.0}, "m"};
      try {
        w.add_step(bad, st);
      } catch (const std::runtime_error&) {
        threw = true;
      }
    });
    EXPECT_TRUE(threw);
    EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, objects), 0) << "a group or dataset was left open";
    EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_FILE), files_before);
  }
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_FILE), files_before);
  fs::remove_all(dir);
}
