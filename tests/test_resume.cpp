// Resume that loses nothing (issue 12): a load path continued from any of its checkpoints
// makes exactly the solves of the uninterrupted path.
#include "cmc/contact/LoadPath.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

using namespace cmc;

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
