// The case-file parser: every class of bad input stops with a message that names the
// file, the key and what was expected.
#include "cmc/grid/Backend.hpp"
#include "cmc/input/Case.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace cmc;

namespace {
const char* kGood = R"(
[case]
name = "t"
[grid]
n = 16
size = 1e-3
[material]
contact_modulus = 1e6
[surface]
kind = "sphere"
radius = 1e-2
[loading]
control = "force"
values = [1e-4]
)";

std::string write(const std::string& text) {
  static int k = 0;
  auto p = std::filesystem::temp_directory_path() / ("cmc_case_test_" + std::to_string(::getpid()) + "_" + std::to_string(k++) + ".toml");
  std::ofstream(p) << text;
  return p.string();
}

// The message of the CaseError that loading `text` (+ overrides) throws.
std::string error_of(const std::string& text, std::vector<std::string> overrides = {}) {
  const std::string f = write(text);
  try {
    load_case(f, overrides);
  } catch (const CaseError& e) {
    std::string m = e.what();
    EXPECT_NE(m.find(f), std::string::npos) << "message does not name the file: " << m;
    return m;
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return "";
}

std::string replace(std::string s, const std::string& a, const std::string& b) {
  const auto k = s.find(a);
  EXPECT_NE(k, std::string::npos) << a;
  return s.replace(k, a.size(), b);
}
}  // namespace

TEST(Case, GoodCaseParsesWithDefaults) {
  const Case c = load_case(write(kGood));
  EXPECT_EQ(c.name, "t");
  EXPECT_EQ(c.grid.nx, 16);
  EXPECT_EQ(c.grid.ny, 16);
  EXPECT_TRUE(c.grid.periodic);
  EXPECT_DOUBLE_EQ(c.grid.size_y, 1e-3);
  EXPECT_EQ(c.solver.kind, SolverKind::PolonskyKeer);
  EXPECT_DOUBLE_EQ(c.solver.tolerance, 1e-10);
  // Defaults are written into the resolved case.
  EXPECT_EQ(c.resolved["solver"]["tolerance"].value<double>(), 1e-10);
  EXPECT_EQ(c.resolved["grid"]["boundary"].value<std::string>(), "periodic");
  EXPECT_EQ(c.resolved["grid"]["backend"].value<std::string>(), "cpu");
}

// A build without the CUDA backend refuses "cuda" by name (the CUDA build's own
// refusals are in tests/gpu), and an unknown word lists the choices; "cpu" is accepted.
TEST(Case, BackendCudaIsRefusedByName) {
  EXPECT_EQ(load_case(write(replace(kGood, "n = 16", "n = 16\nbackend = \"cpu\""))).grid.backend, "cpu");
  auto m = error_of(replace(kGood, "n = 16", "n = 16\nbackend = \"cuda\""));
  if (!cuda::built())
    EXPECT_NE(m.find("[grid] backend: expected \"cpu\": this build of cmc has no CUDA backend"), std::string::npos) << m;
  m = error_of(replace(kGood, "n = 16", "n = 16\nbackend = \"tpu\""));
  EXPECT_NE(m.find("[grid] backend: expected one of"), std::string::npos) << m;
}

TEST(Case, MalformedToml) {
  const auto m = error_of("[case\nname = 1");
  EXPECT_NE(m.find("not valid TOML at line 1"), std::string::npos) << m;
}

TEST(Case, MissingFile) {
  EXPECT_THROW(load_case("/nonexistent/x.toml"), CaseError);
}

TEST(Case, UnknownKeyAndSection) {
  auto m = error_of(replace(kGood, "size = 1e-3", "size = 1e-3\nsizee = 2"));
  EXPECT_NE(m.find("[grid] sizee: unknown key"), std::string::npos) << m;
  m = error_of(std::string(kGood) + "\n[solvr]\nkind = 1\n");
  EXPECT_NE(m.find("[solvr]: unknown section"), std::string::npos) << m;
}

TEST(Case, WrongType) {
  auto m = error_of(replace(kGood, "n = 16", "n = \"sixteen\""));
  EXPECT_NE(m.find("[grid] n: expected a positive number of points per side, got a string 'sixteen'"), std::string::npos) << m;
  m = error_of(replace(kGood, "values = [1e-4]", "values = 1e-4"));
  EXPECT_NE(m.find("[loading] values: expected"), std::string::npos) << m;
}

TEST(Case, MissingRequired) {
  auto m = error_of(replace(kGood, "contact_modulus = 1e6", ""));
  EXPECT_NE(m.find("[material] contact_modulus: missing required key"), std::string::npos) << m;
  m = error_of(replace(kGood, "[material]\ncontact_modulus = 1e6", ""));
  EXPECT_NE(m.find("missing required section [material]"), std::string::npos) << m;
}

TEST(Case, PhysicallyInvalid) {
  auto m = error_of(replace(kGood, "contact_modulus = 1e6", "contact_modulus = -25e6"));
  EXPECT_NE(m.find("[material] contact_modulus: expected the contact modulus E* in Pa (> 0), got a number -25000000"), std::string::npos) << m;
  m = error_of(replace(kGood, "n = 16", "n = 0"));
  EXPECT_NE(m.find("[grid] n: expected a positive number of points per side (>= 1)"), std::string::npos) << m;
  m = error_of(replace(kGood, "radius = 1e-2", "radius = nan"));
  EXPECT_NE(m.find("[surface] radius"), std::string::npos) << m;
  m = error_of(replace(kGood, "values = [1e-4]", "values = [-1e-4]"));
  EXPECT_NE(m.find("[loading] values: expected non-negative loads"), std::string::npos) << m;
  m = error_of(replace(kGood, "kind = \"sphere\"", "kind = \"cube\""));
  EXPECT_NE(m.find("[surface] kind: expected one of"), std::string::npos) << m;
  // A side beyond the limit names it; a grid within it that no machine holds names the
  // memory it needs (every size is checked before it is used).
  m = error_of(replace(kGood, "n = 16", "n = 2000000"));
  EXPECT_NE(m.find("[grid] n: expected a positive number of points per side (<= 1048576)"), std::string::npos) << m;
  m = error_of(replace(kGood, "n = 16", "n = 1000000"));
  EXPECT_NE(m.find("[grid] n: expected a grid whose run fits in the memory available"), std::string::npos) << m;
}

// Found with tests/fuzz/fuzz_case (inputs with --set strings): integers beyond an int wrapped
// around (n = 2^32 + 1 was read as n = 1, max_iterations = 2^32 as 0), and two double ->
// int conversions out of range (undefined behaviour, reported by UBSan): a refinement
// grid of 1e300, and the memory estimate of a 2^31 - 1 grid in the error message.
TEST(Case, IntegerRangesFoundByFuzzing) {
  // (Grid sides, iteration caps and seeds have their own bounds since: CaseLimits,
  // tests/test_inputs.cpp.)
  auto m = error_of(kGood, {"grid.n=4294967297"});
  EXPECT_NE(m.find("[grid] n: expected a positive number of points per side (<= 1048576)"), std::string::npos) << m;
  m = error_of(kGood, {"solver.max_iterations=4294967296"});
  EXPECT_NE(m.find("[solver] max_iterations: expected a positive iteration cap (<= 100000000)"), std::string::npos) << m;
  m = error_of(kGood, {"grid.n=2147483647"});
  EXPECT_NE(m.find("[grid] n: expected a positive number of points per side (<= 1048576)"), std::string::npos) << m;
  m = error_of(kGood, {"loading.max_halvings=4294967296"});
  EXPECT_NE(m.find("[loading] max_halvings: expected a non-negative number of halvings (<= 10)"), std::string::npos) << m;
  const std::string validated = std::string(kGood) +
                                "[validation]\nreference = \"hertz\"\n[validation.refinement]\ngrids = [64, 128]\n"
                                "quantity = \"penetration\"\nmin_order = 1\n";
  EXPECT_EQ(load_case(write(validated)).validation->refinement->grids.back(), 128);
  m = error_of(validated, {"validation.refinement.grids=[64, 1e300]"});
  EXPECT_NE(m.find("[validation.refinement] grids: expected an increasing array"), std::string::npos) << m;
  // The seed: GSL's mt19937 uses its low 32 bits (seeds 1 and 2^32 + 1 give the same
  // surface), so seeds beyond 2^32 - 1 are refused rather than aliased.
  const std::string affine = replace(kGood, "kind = \"sphere\"\nradius = 1e-2", "kind = \"self_affine\"");
  EXPECT_EQ(load_case(write(affine), {"surface.seed=4294967295"}).surface.seed, 4294967295LL);
  m = error_of(affine, {"surface.seed=9223372036854775807"});
  EXPECT_NE(m.find("[surface] seed: expected a non-negative random seed (<= 4294967295)"), std::string::npos) << m;
}

TEST(Case, Overrides) {
  const std::string f = write(kGood);
  const Case c = load_case(f, {"grid.n=32", "solver.tolerance=1e-6", "grid.boundary=free", "case.name=\"x y\""});
  EXPECT_EQ(c.grid.nx, 32);
  EXPECT_DOUBLE_EQ(c.solver.tolerance, 1e-6);
  EXPECT_FALSE(c.grid.periodic);
  EXPECT_EQ(c.name, "x y");
  // The resolved case records the override.
  EXPECT_EQ(c.resolved["grid"]["n"].value<int64_t>(), 32);
  // An override of an unknown key is caught like one in the file.
  const auto m = error_of(kGood, {"grid.nn=3"});
  EXPECT_NE(m.find("[grid] nn: unknown key"), std::string::npos) << m;
  EXPECT_THROW(load_case(f, {"gridn3"}), CaseError);
  EXPECT_THROW(load_case(f, {"n=3"}), CaseError);
}

TEST(Case, SelfAffineAndObservablesKeys) {
  std::string t = replace(kGood, "kind = \"sphere\"\nradius = 1e-2",
                          "kind = \"self_affine\"\nrolloff_wavelength = 2e-4\ncutoff_wavelength = 1e-5");
  const Case c = load_case(write(t + "\n[observables]\nenabled = true\n"));
  EXPECT_EQ(c.surface.kind, SurfaceKind::SelfAffine);
  EXPECT_DOUBLE_EQ(c.surface.hurst, 0.8);
  EXPECT_TRUE(c.observables.enabled);
  EXPECT_DOUBLE_EQ(c.observables.cross_section_x, 0.5e-3);
  auto m = error_of(replace(t, "cutoff_wavelength = 1e-5", "cutoff_wavelength = 3e-4"));
  EXPECT_NE(m.find("[surface] cutoff_wavelength: expected cutoff_wavelength < rolloff_wavelength"), std::string::npos) << m;
  m = error_of(replace(t, "rolloff_wavelength = 2e-4", "rolloff_wavelength = 2e-4\nhurst = 1.5"));
  EXPECT_NE(m.find("[surface] hurst"), std::string::npos) << m;
  m = error_of(t + "\n[observables]\nenabled = true\nstress_bins = 0\n");
  EXPECT_NE(m.find("[observables] stress_bins"), std::string::npos) << m;
}

// [solver] kind = "polonsky_keer" (a hard-wall solver) with adhesion is an error naming the
// key and what to use instead: a parser that read the key and then ignored it would
// silently run the adhesive solver.
TEST(Case, HardWallSolverWithAdhesionIsAnError) {
  const std::string adhesive = std::string(kGood) +
                               "\n[interaction]\nkind = \"exponential\"\nwork_of_adhesion = 0.05\nrange = 2e-9\n";
  const auto m = error_of(adhesive + "\n[solver]\nkind = \"polonsky_keer\"\n");
  EXPECT_NE(m.find("[solver] kind: expected \"adhesive_cg\", \"quasi_static\" or \"auto\" with an adhesive interaction"), std::string::npos)
      << m;
  EXPECT_NE(m.find("'polonsky_keer'"), std::string::npos) << m;  // what was given
  // The same through --set, and for Dugdale's law.
  EXPECT_NE(error_of(adhesive, {"solver.kind=polonsky_keer"}).find("[solver] kind"), std::string::npos);
  const std::string dugdale = std::string(kGood) + "\n[interaction]\nkind = \"dugdale\"\nwork_of_adhesion = 0.05\n"
                                                   "range = 2e-9\n[solver]\nkind = \"polonsky_keer\"\n";
  EXPECT_NE(error_of(dugdale).find("[solver] kind"), std::string::npos);
  // An unknown solver is an error that lists the known ones.
  const auto u = error_of(std::string(kGood) + "\n[solver]\nkind = \"newton\"\n");
  EXPECT_NE(u.find("[solver] kind: expected one of \"adhesive_cg\" \"auto\" \"polonsky_keer\" \"quasi_static\""),
            std::string::npos)
      << u;
}

TEST(Case, SolverKindAutoAndExplicit) {
  const std::string adhesive = std::string(kGood) +
                               "\n[interaction]\nkind = \"exponential\"\nwork_of_adhesion = 0.05\nrange = 2e-9\n";
  // auto (the default): Polonsky-Keer for a hard wall; with exponential adhesion on a
  // loading path the quasi-static loading-branch solver, and the adhesive CG when the path
  // unloads; each with its default tolerance. The resolved case names the solver that runs.
  Case c = load_case(write(adhesive));
  EXPECT_EQ(c.solver.kind, SolverKind::QuasiStatic);
  EXPECT_DOUBLE_EQ(c.solver.tolerance, 1e-8);
  EXPECT_DOUBLE_EQ(c.solver.tension_tolerance, 1e-3);
  EXPECT_EQ(c.resolved["solver"]["kind"].value<std::string>(), "quasi_static");
  const std::string unloads = replace(adhesive, "values = [1e-4]", "values = [1e-4]\nunloading = [0.0]");
  c = load_case(write(unloads));
  EXPECT_EQ(c.solver.kind, SolverKind::AdhesiveCg);
  EXPECT_EQ(c.resolved["solver"]["kind"].value<std::string>(), "adhesive_cg");
  // A decreasing force is unloading too.
  c = load_case(write(replace(adhesive, "values = [1e-4]", "values = [2e-4, 1e-4]")));
  EXPECT_EQ(c.solver.kind, SolverKind::AdhesiveCg);
  // ... while a decreasing mean gap is loading.
  c = load_case(write(replace(replace(adhesive, "control = \"force\"", "control = \"mean_gap\""), "values = [1e-4]",
                              "values = [2e-6, 1e-6]")));
  EXPECT_EQ(c.solver.kind, SolverKind::QuasiStatic);
  c = load_case(write(std::string(kGood) + "\n[solver]\nkind = \"auto\"\n"));
  EXPECT_EQ(c.solver.kind, SolverKind::PolonskyKeer);
  EXPECT_EQ(c.resolved["solver"]["kind"].value<std::string>(), "polonsky_keer");
  // The adhesive CG solves a hard wall too: asked for, it is what runs.
  c = load_case(write(std::string(kGood) + "\n[solver]\nkind = \"adhesive_cg\"\n"));
  EXPECT_EQ(c.solver.kind, SolverKind::AdhesiveCg);
  EXPECT_DOUBLE_EQ(c.solver.tolerance, 1e-8);
  // quasi_static where it cannot run: an error naming the key and what to use instead.
  auto e = error_of(unloads + "[solver]\nkind = \"quasi_static\"\n");
  EXPECT_NE(e.find("[solver] kind"), std::string::npos) << e;
  EXPECT_NE(e.find("loading path only"), std::string::npos) << e;
  e = error_of(std::string(kGood) + "\n[interaction]\nkind = \"dugdale\"\nwork_of_adhesion = 0.05\nrange = 2e-9\n"
               "[solver]\nkind = \"quasi_static\"\n");
  EXPECT_NE(e.find("needs [interaction] kind = \"exponential\""), std::string::npos) << e;
  e = error_of(adhesive + "[solver]\ntension_tolerance = -1\n");
  EXPECT_NE(e.find("[solver] tension_tolerance"), std::string::npos) << e;
  // The time limit: none by default, seconds >= 0.
  EXPECT_EQ(load_case(write(adhesive)).solver.max_seconds, 0.0);
  EXPECT_EQ(load_case(write(adhesive + "[solver]\nmax_seconds = 200\n")).solver.max_seconds, 200.0);
  e = error_of(adhesive + "[solver]\nmax_seconds = -1\n");
  EXPECT_NE(e.find("[solver] max_seconds: expected seconds a load step's solve may take (quasi_static), 0 for no "
                   "limit (>= 0)"),
            std::string::npos)
      << e;
  // Polonsky-Keer's stiffness preconditioner: on by default, off on request, a boolean.
  EXPECT_TRUE(load_case(write(adhesive)).solver.precondition);
  c = load_case(write(std::string(kGood) + "\n[solver]\nprecondition = false\n"));
  EXPECT_FALSE(c.solver.precondition);
  EXPECT_EQ(c.resolved["solver"]["precondition"].value<bool>(), false);
  e = error_of(std::string(kGood) + "\n[solver]\nprecondition = \"yes\"\n");
  EXPECT_NE(e.find("[solver] precondition"), std::string::npos) << e;
  EXPECT_NE(e.find("true or false"), std::string::npos) << e;
}

TEST(Case, KindsAreTyped) {
  const Case c = load_case(write(replace(kGood, "control = \"force\"", "control = \"mean_gap\"")));
  EXPECT_EQ(c.loading.control, LoadControl::MeanGap);
  EXPECT_EQ(c.interaction.kind, InteractionKind::HardWall);
  EXPECT_EQ(kind_name(LoadControl::MeanGap), "mean_gap");
  EXPECT_EQ(kind_name(SurfaceFormat::ChallengeHdf5), "challenge_hdf5");
  EXPECT_EQ(kind_name(ValidationReference::MaugisDugdale), "maugis_dugdale");
}
