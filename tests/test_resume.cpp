// Resume that loses nothing: a load path continued from any of its checkpoints
// makes exactly the solves of the uninterrupted path, and a checkpoint written by the
// Writer gives back every piece of path state bit for bit. (The whole program, killed and
// resumed: tests/resume_test.py.)
#include "cmc/contact/LoadPath.hpp"
#include "cmc/output/OutputLock.hpp"
#include "cmc/output/Writer.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <vector>

using namespace cmc;
namespace fs = std::filesystem;

namespace {

// A made-up unloading path, cheap and deterministic: in contact above v = 0.6 with a
// contact fraction growing with v and p(v) = (v − 1.2)² − 1 (the pull-off, −1, at v = 1.2,
// between the path's samples), snapped off below (p = 0, no contact: a jump). The jump
// test measures pressure changes against the running max of |p| (pressure_floor 0), the
// state the D2 defect lost.
struct FakePath {
  std::vector<double> calls;  // the target of every solve, in order
  SolveResult operator()(const Target& t, ContactState& s) {
    calls.push_back(t.value);
    SolveResult r;
    r.converged = true;
    r.iterations = 1;
    const double v = t.value;
    const bool contact = v > 0.6;
    s.penetration = v;
    s.mean_pressure = contact ? (v - 1.2) * (v - 1.2) - 1.0 : 0.0;
    s.gap.assign(100, 1.0);
    const int nc = contact ? int(20 + 10 * v) : 0;
    for (int i = 0; i < nc && i < 100; ++i) s.gap[i] = 0.0;
    s.pressure.assign(100, s.mean_pressure);
    s.displacement.assign(100, v);
    return r;
  }
};

LoadPathOptions options() {
  LoadPathOptions lo;
  lo.max_halvings = 3;
  lo.refine_pulloff = 6;
  return lo;
}

std::vector<Target> targets() { return ramp(Control::Penetration, 3.0, 0.0, 6); }

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

struct Interrupted {};

}  // namespace

TEST(Resume, LoadPathContinuesExactlyFromEveryCheckpoint) {
  const LoadPathOptions lo = options();
  FakePath whole_solver;
  ContactState whole_state;
  PathState whole_path;
  int checkpoints = 0;
  const LoadPathResult whole = run_load_path(std::ref(whole_solver), targets(), whole_state, whole_path, lo, {},
                                             [&](const PathState&, const ContactState&) { ++checkpoints; });
  // The path has what the test is about: halving, a jump, and a refined pull-off.
  ASSERT_TRUE(whole.completed);
  ASSERT_GT(whole.halved_steps, 0);
  ASSERT_GT(whole.jumps, 0);
  ASSERT_GE(whole.pulloff_refinement_solves, 3);
  ASSERT_EQ(checkpoints, int(targets().size()) + whole.pulloff_refinement_solves);

  for (int stop = 1; stop <= checkpoints; ++stop) {
    SCOPED_TRACE("interrupted at checkpoint " + std::to_string(stop));
    // The interrupted walk: keeps copies of what the checkpoint holds, then "dies".
    FakePath first;
    ContactState state, saved_state;
    PathState path, saved_path;
    std::vector<LoadStep> recorded;
    int seen = 0;
    try {
      run_load_path(
          std::ref(first), targets(), state, path, lo, [&](const LoadStep& s, const ContactState&) { recorded.push_back(s); },
          [&](const PathState& p, const ContactState& st) {
            if (++seen < stop) return;
            saved_path = p, saved_state = st;
            throw Interrupted{};
          });
      FAIL() << "not interrupted";
    } catch (const Interrupted&) {
    }
    // Continued from the copies.
    FakePath second;
    const LoadPathResult rest = run_load_path(std::ref(second), targets(), saved_state, saved_path, lo,
                                              [&](const LoadStep& s, const ContactState&) { recorded.push_back(s); });
    // The same solves at the same targets, bit for bit.
    std::vector<double> calls = first.calls;
    calls.insert(calls.end(), second.calls.begin(), second.calls.end());
    ASSERT_EQ(calls.size(), whole_solver.calls.size());
    for (std::size_t i = 0; i < calls.size(); ++i) EXPECT_TRUE(same_bits(calls[i], whole_solver.calls[i])) << "solve " << i;
    // The same steps, counters and pull-off.
    ASSERT_EQ(recorded.size(), whole.steps.size());
    for (std::size_t k = 0; k < recorded.size(); ++k) {
      EXPECT_EQ(recorded[k].halvings, whole.steps[k].halvings) << "step " << k;
      EXPECT_EQ(recorded[k].jump, whole.steps[k].jump) << "step " << k;
      EXPECT_EQ(recorded[k].solves, whole.steps[k].solves) << "step " << k;
      EXPECT_EQ(recorded[k].branch, whole.steps[k].branch) << "step " << k;
      EXPECT_TRUE(same_bits(recorded[k].mean_pressure, whole.steps[k].mean_pressure)) << "step " << k;
    }
    EXPECT_EQ(rest.halved_steps, whole.halved_steps);
    EXPECT_EQ(rest.jumps, whole.jumps);
    EXPECT_EQ(rest.max_halvings, whole.max_halvings);
    EXPECT_EQ(rest.failed_steps, whole.failed_steps);
    EXPECT_EQ(rest.pulloff_refinement_solves, whole.pulloff_refinement_solves);
    EXPECT_TRUE(same_bits(rest.pulloff_mean_pressure, whole.pulloff_mean_pressure));
    EXPECT_TRUE(same_bits(rest.pulloff_target.value, whole.pulloff_target.value));
    EXPECT_EQ(rest.pulloff_branch, whole.pulloff_branch);
  }
}

namespace {
Case small_case() {
  return parse_case(toml::parse(R"(
[case]
name = "r"
[grid]
n = 8
size = 1e-3
boundary = "free"
[material]
contact_modulus = 1e6
[surface]
kind = "sphere"
radius = 1e-2
[loading]
control = "penetration"
values = [1e-6, 2e-6]
)"),
                    "mem");
}
ContactState state_of(std::size_t n, double seed) {
  ContactState s;
  for (std::size_t i = 0; i < n; ++i) {
    s.pressure.push_back(seed * std::sin(double(i) + 0.1));
    s.displacement.push_back(seed / (1.0 + double(i)));
    s.gap.push_back(i % 3 ? 0.0 : 1.0 / 3.0 + double(i));
  }
  s.penetration = 0.1 + 0.2;  // not a short decimal
  s.mean_pressure = -std::numeric_limits<double>::denorm_min();
  return s;
}
}  // namespace

// Every field of the path state and both states come back bit for bit (NaN, −0, a
// denormal, a value with 17 significant digits included).
TEST(Resume, CheckpointKeepsEveryPieceOfPathStateBitForBit) {
  const Case c = small_case();
  Scene s = build_scene(c);
  const auto dir = fs::temp_directory_path() / ("cmc_resume_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::size_t n = s.grid.size();
  PathState p;
  p.started = true;
  p.next = 0;
  p.have_prev = true;
  p.value = 1.0 / 3.0;
  p.contact_fraction = 0.1 + 0.7;
  p.mean_pressure = -0.0;
  p.pressure_scale = 1e-300;
  p.branch = Branch::Unloading;
  p.pulloff_mean_pressure = -std::nextafter(1.0, 2.0);
  p.pulloff_value = 2.0 / 7.0;
  p.pulloff_branch = Branch::Unloading;
  p.pulloff_before = std::numeric_limits<double>::quiet_NaN();
  p.pulloff_after = 5e-324;
  p.pulloff_is_last = true;
  p.have_last = true;
  p.last_value = -1.0 / 9.0;
  p.pulloff_state = state_of(n, 2.5);
  p.failed_steps = 1, p.halved_steps = 2, p.jumps = 3, p.max_halvings = 4;
  p.refinement = PathState::Refinement::Running;
  p.lo = 0.1, p.hi = 0.7, p.x1 = 0.1 + 0.6 * 0.381966, p.x2 = 0.7 - 0.6 * 0.381966, p.f1 = -1.0 / 3.0, p.f2 = 1e308;
  p.have_f1 = true, p.have_f2 = false;
  p.refinement_solves = 5;
  const ContactState st = state_of(n, -1.25);
  {
    Writer w(dir, c, s);
    w.checkpoint(st, &p);
  }
  Writer w(dir, c, s, /*resume=*/true);
  ASSERT_TRUE(w.resuming());
  const RunPoint& r = w.resume_point();
  const PathState& q = r.path;
  EXPECT_TRUE(r.done.empty());
  EXPECT_EQ(q.started, p.started);
  EXPECT_EQ(q.next, p.next);
  EXPECT_EQ(q.have_prev, p.have_prev);
  EXPECT_EQ(q.branch, p.branch);
  EXPECT_EQ(q.pulloff_branch, p.pulloff_branch);
  EXPECT_EQ(q.pulloff_is_last, p.pulloff_is_last);
  EXPECT_EQ(q.have_last, p.have_last);
  EXPECT_EQ(q.failed_steps, p.failed_steps);
  EXPECT_EQ(q.halved_steps, p.halved_steps);
  EXPECT_EQ(q.jumps, p.jumps);
  EXPECT_EQ(q.max_halvings, p.max_halvings);
  EXPECT_EQ(q.refinement, p.refinement);
  EXPECT_EQ(q.have_f1, p.have_f1);
  EXPECT_EQ(q.have_f2, p.have_f2);
  EXPECT_EQ(q.refinement_solves, p.refinement_solves);
  const std::pair<double, double> scalars[] = {
      {q.value, p.value},
      {q.contact_fraction, p.contact_fraction},
      {q.mean_pressure, p.mean_pressure},
      {q.pressure_scale, p.pressure_scale},
      {q.pulloff_mean_pressure, p.pulloff_mean_pressure},
      {q.pulloff_value, p.pulloff_value},
      {q.pulloff_after, p.pulloff_after},
      {q.last_value, p.last_value},
      {q.lo, p.lo}, {q.hi, p.hi}, {q.x1, p.x1}, {q.x2, p.x2}, {q.f1, p.f1}, {q.f2, p.f2},
      {q.pulloff_state.penetration, p.pulloff_state.penetration},
      {q.pulloff_state.mean_pressure, p.pulloff_state.mean_pressure},
      {r.state.penetration, st.penetration},
      {r.state.mean_pressure, st.mean_pressure}};
  for (std::size_t i = 0; i < std::size(scalars); ++i)
    EXPECT_TRUE(same_bits(scalars[i].first, scalars[i].second))
        << "scalar " << i << ": " << scalars[i].first << " != " << scalars[i].second;
  EXPECT_TRUE(std::isnan(q.pulloff_before));
  for (const auto& [got, want] : {std::pair{&r.state, &st}, {&q.pulloff_state, &p.pulloff_state}}) {
    ASSERT_EQ(got->pressure.size(), n);
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_TRUE(same_bits(got->pressure[i], want->pressure[i]));
      EXPECT_TRUE(same_bits(got->displacement[i], want->displacement[i]));
      EXPECT_TRUE(same_bits(got->gap[i], want->gap[i]));
    }
  }
  fs::remove_all(dir);
}

// A checkpoint that does not fit the case is bad input naming the file, not a crash.
TEST(Resume, DamagedCheckpointIsAClearError) {
  const Case c = small_case();
  Scene s = build_scene(c);
  const auto dir = fs::temp_directory_path() / ("cmc_resume_bad_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / ".partial");
  { std::ofstream(dir / ".partial" / "checkpoint.h5") << "not HDF5"; }
  try {
    Writer w(dir, c, s, true);
    FAIL() << "no error";
  } catch (const CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("checkpoint.h5"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("without --resume"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

// One owner per output folder (D7; across processes: ctest lock.D7_one_owner). Within a
// process the holds of one folder are shared; the lock file names the process; a folder
// the lock made and nobody wrote into goes when the last hold does (bad input leaves
// nothing behind), one that held anything stays.
TEST(OutputLock, SharedWithinAProcessNamesItAndCleansUpAnEmptyFolder) {
  const auto dir = fs::temp_directory_path() / ("cmc_lock_" + std::to_string(::getpid())) / "out";
  fs::remove_all(dir.parent_path());
  {
    const OutputLock a(dir);
    const OutputLock b(dir / "." / "");  // the same folder, spelled differently
    EXPECT_TRUE(a.held() && b.held());
    std::ifstream in(dir / OutputLock::file_name());
    long pid = 0;
    in >> pid;
    EXPECT_EQ(pid, long(::getpid()));
  }
  EXPECT_FALSE(fs::exists(dir)) << "an empty folder made by the lock was left behind";
  {
    const OutputLock a(dir);
    std::ofstream(dir / "result.txt") << "x";
  }
  EXPECT_TRUE(fs::exists(dir / "result.txt"));
  EXPECT_EQ(fs::file_size(dir / OutputLock::file_name()), 0u);  // nobody holds it
  fs::remove_all(dir.parent_path());
}
