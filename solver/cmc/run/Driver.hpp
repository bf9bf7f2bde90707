// Runs a scene's load steps with the case's solver, one after the other, each warm
// started from the previous one. Knows algorithms, not files: the caller decides
// what to do with each solved step (the Writer saves it).
#pragma once

#include "cmc/contact/LoadPath.hpp"
#include "cmc/contact/quasi_static/QuasiStaticAdhesion.hpp"
#include "cmc/observe/StepObservables.hpp"
#include "cmc/scene/Scene.hpp"

#include <optional>

#include <functional>
#include <string>
#include <vector>

namespace cmc {

// One load step in SI units, as written to summary.json.
struct StepRecord {
  int index = 0;
  Branch branch = Branch::Loading;
  double mean_pressure = 0.0;    // Pa
  double force = 0.0;            // N (mean pressure x nominal area)
  double penetration = 0.0;      // m, rigid-body approach δ
  double mean_gap = 0.0;         // m
  double contact_fraction = 0.0; // fraction of grid points in contact (Scene::contact_rule)
  double energy = 0.0;           // J: elastic energy plus interaction energy (adhesion), if any
  bool jump = false;             // an instability (jump in or out of contact) before this step
  int halvings = 0;              // how often the step had to be halved to get here
  SolveResult result;
  std::optional<ObservablesRecord> observables;  // when the case asks for them
};

// How a run ended; status_name() gives the word summary.json uses ("converged",
// "not_converged", "failed"): the Writer writes it, `cmc run` prints it.
enum class RunStatus { Converged, NotConverged, Failed };
const char* status_name(RunStatus s);

struct RunSummary {
  RunStatus status = RunStatus::Converged;
  std::string message;
  std::vector<StepRecord> steps;
  double wall_s = 0.0;
  double fft_pairs = 0.0;
  // Cost against the FFT floor: one FFT pair of the run's operator timed at its start,
  // the steps' solver time over (their FFT pairs x that time) and over (their iterations
  // x that time): 1.0 would be nothing but transforms; the target is 1.3 per iteration.
  int iterations = 0;
  double fft_pair_s = 0.0;
  double time_per_fft_pair = 0.0;   // in units of fft_pair_s
  double time_per_iteration = 0.0;  // in units of fft_pair_s
  // The same against the faster of that pair and the row-column pair that Polonsky-Keer's
  // fused sweeps run (HalfSpace::time_row_column_pair, timed right after it where those
  // sweeps run; else 0 and the floor is fft_pair_s): the strictest yardstick of the run.
  // (FFTW's 2-D pair at 2048² took 28-37 ms in runs where the row-column pair took 22.)
  double row_column_pair_s = 0.0;
  double floor_pair_s = 0.0;
  double time_per_floor_pair = 0.0;
  // The steps' seconds inside the FFTs over their solver time: 1 - fft_share of the time
  // went to everything else (the solver's passes over the fields).
  double fft_share = 0.0;
  // Load path (adhesive runs): pull-off = the most negative load of every converged
  // solve, sub-steps included; steps that needed halving; steps after a jump.
  bool load_path = false;
  double pulloff_mean_pressure = 0.0, pulloff_force = 0.0;  // Pa, N
  std::optional<Branch> pulloff_branch;  // none without a converged solve
  int halved_steps = 0, jumps = 0;
};

// Where a run stands, enough to continue it exactly as if it had not stopped (what a
// checkpoint holds, output/Checkpoint.cpp): the steps finished, the state the next solve
// starts from, and for a load path (adhesive runs) where its walk stands.
struct RunPoint {
  std::vector<StepRecord> done;
  ContactState state;
  PathState path;  // unused by Polonsky–Keer
  // Inside the next step (quasi-static solver only): where its solve stood between two
  // outer steps. `state` is then not needed (empty in a checkpoint).
  std::optional<OuterPoint> inside;
};

using StepCallback = std::function<void(const StepRecord&, const ContactState&)>;
// Called wherever the run can be continued from: after every step (after the
// StepCallback) and after every pull-off refinement solve, with the state the run goes on
// from and, for a load path, its walk (null for Polonsky–Keer). With the steps handed to
// the StepCallback so far, that is a RunPoint. The quasi-static solver also calls it
// between two outer steps of a step, with `inside` (null otherwise) and the state the step
// started from: a caller saves those when it wants (a long step's solve is continued
// from there; writing a checkpoint after every outer step would cost more than it saves).
// In a distributed run every rank must make the same choice.
using CheckpointCallback = std::function<void(const ContactState&, const PathState*, const OuterPoint* inside)>;

// `from`: where an interrupted run stood (its finished steps are skipped and kept in the
// summary; its state and `inside` are moved from); null: from the start.
RunSummary run_scene(const Case& c, Scene& s, const StepCallback& on_step, const Progress& progress = {},
                     RunPoint* from = nullptr, const CheckpointCallback& on_checkpoint = {});

}  // namespace cmc
