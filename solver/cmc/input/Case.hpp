// A case file, parsed and validated into a typed Case (SI units, as written).
//
// The schema (every key, its unit and default) is documented in cases/README.md;
// this file is its single implementation. Anything wrong — malformed TOML, an
// unknown key, a wrong type, a missing required key, a physically invalid value —
// throws CaseError with a message naming the file, the key and what was expected.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "cmc/input/Kinds.hpp"

namespace cmc {

struct CaseError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Defaults: the default member initialisers below are the case defaults; the parser
// starts from a default-constructed spec and case_defaults() lists them in the form
// cases/README.md documents (tests/test_defaults.cpp compares the two).
struct GridSpec {
  int nx = 0, ny = 0;
  double size_x = 0.0, size_y = 0.0;  // m
  bool periodic = true;
  // Where fields live and passes run (grid/Backend.hpp): "cpu" (FFTW and OpenMP) or
  // "cuda" (cuFFT and kernels on one GPU: builds with -DCMC_CUDA=ON, periodic boundary,
  // the polonsky_keer and quasi_static solvers; others refuse it naming the key).
  std::string backend = "cpu";
};

struct SurfaceSpec {
  SurfaceKind kind = SurfaceKind::Flat;  // required in a case file
  double radius = 0.0;                    // m (sphere)
  std::optional<std::vector<double>> center;  // m (sphere apex), default: box centre
  double amplitude = 0.0;                 // m (wavy)
  double wavelength = 0.0;                // m (wavy), default: the grid size
  // self_affine (the challenge's spectrum; Müser & Dapp, section "Surface Topography")
  double hurst = 0.8;
  double rolloff_wavelength = 0.0;        // m, default: kRolloffFraction x grid size
  double cutoff_wavelength = 0.0;         // m, default: kCutoffFraction x grid size
  static constexpr double kRolloffFraction = 0.2, kCutoffFraction = 1e-3;
  double rms_gradient = 1.0;
  long long seed = 28;
  // file
  std::string path;
  SurfaceFormat format = SurfaceFormat::ChallengeHdf5;  // required for a file
  std::string dataset = "surface";
  double height_unit = 0.0;               // m per height unit in the file (0: the format's own)
};

struct ObservablesSpec {
  bool enabled = false;
  double cross_section_x = 0.0;  // m, default: kCrossSectionFraction x grid size
  static constexpr double kCrossSectionFraction = 0.5;
  int stress_bins = 100;
  int gap_bins_per_decade = 10;
  int patch_bins_per_decade = 5;
  double contact_gap_threshold = 0.0;  // m: a point is in contact where g <= this (contact/ContactRule.hpp)
};

struct InteractionSpec {
  InteractionKind kind = InteractionKind::HardWall;
  double work_of_adhesion = 0.0;   // J/m^2
  // Exactly one of: range (m; rho of the exponential law, h0 of Dugdale's), tabor
  // (Müser's mu_T = R^{1/3} (w/E*)^{2/3} / rho with R the sphere radius or the surface's
  // R_c; exponential), maugis_lambda (Dugdale, sphere). 0 = not given.
  double range = 0.0, tabor = 0.0, maugis_lambda = 0.0;
  double smoothing = 0.0;  // m, Dugdale only; 0: the smallest that keeps grid points stable
  CoarseGraining coarse_graining = CoarseGraining::None;  // exponential only
};

struct LoadingSpec {
  LoadControl control = LoadControl::Force;  // required in a case file
  std::vector<double> values;  // N | Pa | m | m: the loading branch
  std::vector<double> unloading;  // same units: steps after `values`, on the unloading branch
  int max_halvings = 5;        // a step that fails or jumps is halved up to this often
  double jump_fraction = 0.5;  // a jump: contact fraction or mean pressure changes by more
  double jump_pressure_floor = 0.0;  // Pa: mean-pressure changes count relative to at least this
  int refine_pulloff = 0;      // extra solves to locate the pull-off between path steps
};

struct SolverSpec {
  SolverKind kind = SolverKind::Auto;  // resolved by the parser: never Auto in a parsed Case
  // Default tolerance: each solver's own residual (see PolonskyKeer.hpp, AdhesiveSolver.hpp).
  static constexpr double kPolonskyKeerTolerance = 1e-10, kAdhesiveTolerance = 1e-8;
  double tolerance = kPolonskyKeerTolerance;
  int max_iterations = 2000;
  // The case default for both solvers: the driver passes it to whichever it runs.
  int recompute_every = 32;
  // quasi_static only: outer convergence on the adhesive tension (QuasiStaticAdhesion.hpp).
  double tension_tolerance = 1e-3;
  // quasi_static only: the most outer steps a load step may take; one that reaches it stops
  // with status not_converged. A stopping limit: a resumed run may change it (CaseDiff.hpp).
  int max_outer_steps = 1000;
  // quasi_static only: the most seconds a load step's solve may take in one process (0: no
  // limit); one that reaches it stops at the end of an outer step, not_converged, with the
  // state it stands at. For a machine lent for minutes; where it stops depends on the
  // machine's speed, so such a run does not repeat bit for bit.
  double max_seconds = 0.0;
  // Polonsky-Keer (also inside quasi_static): precondition its conjugate gradients with the
  // half-space's stiffness on a periodic boundary (PolonskyKeer.hpp).
  bool precondition = true;
  // Iterations between two progress reports. Not a case key: the validation harness sets 1
  // to keep every iteration's residual.
  int progress_every = 25;
};

struct ValidationCheck {
  ValidationQuantity quantity = ValidationQuantity::Penetration;
  double tolerance = 0.0;
};

struct RefinementSpec {
  std::vector<int> grids;  // points per side, increasing
  ValidationQuantity quantity = ValidationQuantity::Penetration;
  double min_order = 0.0;  // the observed order must be at least this
};

// A stability check: a property any solved case must have, with its bound
// (validation/Stability.hpp). The key that states the bound is per kind: `budget`
// (iterations), `factor` (residual_growth), `tolerance` (the others that have one).
struct StabilityCheck {
  StabilityKind kind = StabilityKind::Iterations;
  double bound = 0.0;
  // continuity: the case key changed ("interaction.work_of_adhesion"; a number or an array
  // of numbers, each scaled), by how much (relative), what is compared, and the steps left
  // out because a jump lies between the two answers there (each documented in the case).
  std::string parameter;
  double change = 0.01;
  PathObservable observable = PathObservable::ContactFraction;
  std::vector<int> skip_steps;
  // agreement: the other solver, run on the case's loading branch, and compared there by
  // `observable` (skip_steps as for continuity).
  SolverKind solver = SolverKind::QuasiStatic;
  // Not empty: cmc does not pass this check yet, and this says why. The check runs; a
  // failure is reported as expected, a pass as a change to look at.
  std::string expected_failure;
};

struct ValidationSpec {
  // The analytic reference of the `quantity` checks and the refinement study; a case with
  // stability checks alone has none.
  std::optional<ValidationReference> reference;
  std::vector<ValidationCheck> checks;
  std::vector<StabilityCheck> stability;
  std::optional<RefinementSpec> refinement;
};

struct Case {
  std::string file;  // where it came from (for messages)
  std::string name, description;
  GridSpec grid;
  double contact_modulus = 0.0;  // Pa
  SurfaceSpec surface;
  InteractionSpec interaction;
  LoadingSpec loading;
  SolverSpec solver;
  bool write_fields = true;  // [output] fields
  ObservablesSpec observables;
  std::optional<ValidationSpec> validation;
  toml::table resolved;  // the case as run: overrides applied, defaults filled in
};

// The bounds of every size a case file sets, checked where the key is read
// (input/CaseSections.cpp) and listed in cases/README.md ("Limits"). A value beyond one is bad
// input (CaseError naming the file, the key and the limit), never wrapped or clamped.
struct CaseLimits {
  // Points per side: 2^20. FFT sizes and grid indices are ints; the free boundary pads
  // to twice this. Whether a grid fits is decided by the memory estimate below.
  static constexpr long long kMaxGridSide = 1LL << 20;
  // [case] name: it names output folders (cmc validate --out DIR/<name>/), so it must be
  // one path component that every file system takes (NAME_MAX is 255 bytes).
  static constexpr std::size_t kMaxNameBytes = 100;
  static constexpr std::size_t kMaxDescriptionBytes = 1000;
  // Histogram bins: a stress histogram's counts are kept per thread chunk.
  static constexpr long long kMaxStressBins = 100000;
  static constexpr long long kMaxBinsPerDecade = 1000;
  // A step that fails is walked in sub-steps of 2^-max_halvings of it: at most 1024.
  static constexpr long long kMaxHalvings = 10;
  // Golden-section solves: 80 shrink the bracket by 0.618^80 < 2^-52 (round-off).
  static constexpr long long kMaxRefinePulloff = 80;
  // solver.tolerance, a relative residual: a looser one stops a solve far from the answer
  // (hard-wall challenge at 64²: 0.1 left the contact area 13 % off in 5 iterations, 1 and
  // 10 stopped after 1 and 0 iterations at 61 % and full contact; 1e-2 was 0.7 % off).
  static constexpr double kMaxSolverTolerance = 1e-2;
  static constexpr long long kMaxIterations = 100000000;  // solver.max_iterations, recompute_every
  static constexpr std::size_t kMaxLoadSteps = 100000;    // loading.values + unloading
  // GSL's mt19937 uses the low 32 bits of the seed.
  static constexpr long long kMaxSeed = 4294967295LL;
  // self_affine: the band up to L/cutoff_wavelength is generated in full (about
  // (pi/2) (L/cutoff)^2 modes, whatever the grid); the generator refuses more than 1e6.
  static constexpr double kMaxBandRatio = 1e6;
  // A case file is a few kB; anything this large is not one.
  static constexpr std::uintmax_t kMaxCaseFileBytes = 16u << 20;
  // base = "other.toml": a base may name a base of its own, this many deep (CaseFile.cpp).
  static constexpr int kMaxBaseDepth = 8;
};

// The memory a run of a case holds at its peak: every field of the grid and of the
// solver's transform grid (twice the size per side on a free boundary), the solver's
// work arrays, the load path's copies of the state, the observables and the output
// buffers, and the generated surface's Fourier band. Counted from the code in
// estimate_memory (input/Case.cpp); tests/test_limits.cpp compares it with the peak
// memory of real runs.
struct MemoryEstimate {
  double bytes = 0.0;  // the peak: the larger of making the surface and solving
  std::string what;    // what it is made of, for messages ("13 fields of the grid, ...")
};
MemoryEstimate estimate_memory(const Case& c);
// The fields the case's solver holds besides every run's own, counted from its code
// (contact/*/Memory.hpp), in fields of the grid and of the transform grid: for the whole
// run and while a solve runs (summary.json "model").
struct SolverFields {
  double run_grid = 0.0, run_transform = 0.0, solve_grid = 0.0, solve_transform = 0.0;
};
SolverFields solver_fields(const Case& c);
// How a distributed run (MPI) splits the memory: its ranks, each holding a slab of every
// field, and those on this machine, which share its memory. The program sets it once
// MPI has started (main.cpp); estimate_memory and the check of a case's grid against the
// available memory are then per rank. {1, 1} for a serial run.
struct MemorySplit {
  int ranks = 1, ranks_here = 1;
};
const MemorySplit& memory_split();
void set_memory_split(const MemorySplit& s);
// Memory this machine can give a new run now, in bytes: /proc/meminfo's MemAvailable,
// or what the process's cgroup (v2 memory.max, v1 memory.limit_in_bytes) leaves if that
// is less; sysconf(_SC_AVPHYS_PAGES) where /proc is missing. nullopt: unknown.
std::optional<double> available_memory();
// "1.5 GB", "312 MB": a byte count as messages write it.
std::string memory_text(double bytes);

// Apply "section.key=value" (value in TOML syntax; bare words are strings).
void apply_override(toml::table& t, const std::string& assignment);

Case parse_case(const toml::table& t, const std::string& file);

// The default of every key of the sections that cases/README.md documents with a
// default column, written as that column writes it ("required", "0.8", "0.2 size",
// "\"periodic\"" ...). Numbers come from the spec structs above, so the docs can be
// checked against the code (tests/test_defaults.cpp).
struct DocumentedDefault {
  std::string section, key, text;
};
std::vector<DocumentedDefault> case_defaults();

// The table of the case file at `path` with the bases it names merged under it
// (input/CaseFile.cpp; docs/user-guide/case-files.md, "Shared bases"): what load_case
// applies the overrides to.
toml::table read_case_file(const std::string& path);

// Read (with its bases), apply overrides, validate.
Case load_case(const std::string& path, const std::vector<std::string>& overrides = {});

}  // namespace cmc
