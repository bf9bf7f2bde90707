// Input sizes and file readers: every defect that probing cmc with bad input found has a
// test here named after its label (D4 ... D14, the same labels as the cmc-program tests of
// tests/inputs.cmake and tests/resume.cmake), each failing on the code before its fix. They use
// only the API that code had (load_case, build_scene, run_scene, the surface writers,
// the cmc program), so that they can be built against it to show that.
#include "cmc/input/Case.hpp"
#include "cmc/run/Driver.hpp"
#include "cmc/scene/Scene.hpp"
#include "cmc/surface/SurfaceIO.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace cmc;
namespace fs = std::filesystem;

namespace {

const char* kCase = R"(
[case]
name = "inputs"
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

struct TempDir {
  fs::path path;
  TempDir() {
    std::string t = (fs::temp_directory_path() / "cmc_test_inputs_XXXXXX").string();
    path = ::mkdtemp(t.data());
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name, std::ios::binary) << text;
    return path / name;
  }
};

// The message of the CaseError that loading `text` with `overrides` throws ("" and a
// test failure when it loads).
std::string error_of(const std::string& text, const std::vector<std::string>& overrides = {}) {
  TempDir d;
  const fs::path f = d.write("case.toml", text);
  try {
    load_case(f.string(), overrides);
  } catch (const CaseError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(f.string()), std::string::npos) << "the message does not name the file: " << m;
    return m;
  }
  ADD_FAILURE() << "accepted: " << ::testing::PrintToString(overrides);
  return "";
}

#define EXPECT_HAS(text, fragment) EXPECT_NE(std::string(text).find(fragment), std::string::npos) << (text)

// The cmc program beside this test binary.
fs::path cmc_program() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec).parent_path() / "cmc";
  return fs::exists(p) ? p : fs::path{};
}

// Runs `cmd` with sh; its exit code, and its output in `out` when given.
int sh(const std::string& cmd, std::string* out = nullptr) {
  const std::string full = cmd + " >" + (out ? "/tmp/cmc_test_inputs_out." + std::to_string(::getpid()) : "/dev/null") +
                           " 2>&1";
  const int s = std::system(full.c_str());
  if (out) {
    const std::string f = "/tmp/cmc_test_inputs_out." + std::to_string(::getpid());
    std::ifstream in(f);
    std::ostringstream ss;
    ss << in.rdbuf();
    *out = ss.str();
    std::remove(f.c_str());
  }
  return WIFEXITED(s) ? WEXITSTATUS(s) : -1;
}

}  // namespace

// ------------------------------------------------------------------------ D4
// grid.n = 2^32 + 128 was narrowed to int and ran as 128²; sizes are bounded first.
TEST(Inputs, D4GridSizeWraps) {
  for (const char* o : {"grid.n=4294967424", "grid.n=2147483648", "grid.n=1048577"}) {
    const std::string m = error_of(kCase, {o});
    EXPECT_HAS(m, "[grid] n: expected a positive number of points per side (<= 1048576)");
  }
  std::string t = kCase;
  t.replace(t.find("n = 16"), 6, "nx = 4294967424\nny = 1");
  EXPECT_HAS(error_of(t), "[grid] nx: expected a positive number of points along x (or give n) (<= 1048576)");
}

// Large grids within the side bound got "needs about -2147483648 GB"; the message now
// names grid.n, the estimate (positive) and the memory available.
TEST(Inputs, D4MemoryMessageNamesEstimateAndAvailable) {
  for (const char* o : {"grid.n=1048576", "grid.n=1000000"}) {
    const std::string m = error_of(kCase, {o});
    EXPECT_HAS(m, "[grid] n: expected a grid whose run fits in the memory available");
    EXPECT_HAS(m, "points holds about ");
    EXPECT_HAS(m, " GB");
    EXPECT_HAS(m, " is available");
    EXPECT_EQ(m.find("about -"), std::string::npos) << m;
  }
}

// ------------------------------------------------------------------------ D5
// stress_bins = 1600000000 allocated 12.8 GB after the solve.
TEST(Inputs, D5BinCountsBounded) {
  EXPECT_HAS(error_of(kCase, {"observables.enabled=true", "observables.stress_bins=1600000000"}),
             "[observables] stress_bins: expected a positive number of bins (<= 100000)");
  EXPECT_HAS(error_of(kCase, {"observables.gap_bins_per_decade=5000000000"}),
             "[observables] gap_bins_per_decade: expected a positive number of bins (<= 1000)");
  EXPECT_HAS(error_of(kCase, {"observables.patch_bins_per_decade=1001"}),
             "[observables] patch_bins_per_decade: expected a positive number of bins (<= 1000)");
  // The limits themselves are accepted.
  TempDir d;
  const Case c = load_case(d.write("c.toml", kCase).string(),
                           {"observables.stress_bins=100000", "observables.gap_bins_per_decade=1000"});
  EXPECT_EQ(c.observables.stress_bins, 100000);
}

// ------------------------------------------------------------------------ D6
// max_halvings was unbounded (a failing step walked in 2^max_halvings sub-steps), and
// the other counts were narrowed to int unchecked.
TEST(Inputs, D6HalvingsAndCountsBounded) {
  EXPECT_HAS(error_of(kCase, {"loading.max_halvings=64"}),
             "[loading] max_halvings: expected a non-negative number of halvings (<= 10)");
  EXPECT_HAS(error_of(kCase, {"loading.max_halvings=4294967301"}), "[loading] max_halvings");
  EXPECT_HAS(error_of(kCase, {"loading.refine_pulloff=1000000"}), "[loading] refine_pulloff: expected a non-negative number of extra solves (<= 80)");
  EXPECT_HAS(error_of(kCase, {"solver.max_iterations=4294967297"}),
             "[solver] max_iterations: expected a positive iteration cap (<= 100000000)");
  EXPECT_HAS(error_of(kCase, {"solver.recompute_every=4294967297"}), "[solver] recompute_every");
  TempDir d;
  EXPECT_EQ(load_case(d.write("c.toml", kCase).string(), {"loading.max_halvings=10"}).loading.max_halvings, 10);
}

// ------------------------------------------------------------------------ D9, D10
// The case name becomes a folder name: it must be one short path component.
TEST(Inputs, D9NameCannotLeaveOutputFolder) {
  for (const char* name : {"../escape", "a/b", "..", ".", ".hidden", "a\\\\b", "/abs", ""}) {
    SCOPED_TRACE(name);
    EXPECT_HAS(error_of(kCase, {std::string("case.name=\"") + name + "\""}), "[case] name: expected a name usable as one folder name");
  }
  TempDir d;
  EXPECT_EQ(load_case(d.write("c.toml", kCase).string(), {"case.name=\"x y-1.2_z\""}).name, "x y-1.2_z");
}

TEST(Inputs, D10LongNameRefusedBeforeSolving) {
  const std::string m = error_of(kCase, {"case.name=\"" + std::string(300, 'x') + "\""});
  EXPECT_HAS(m, "[case] name: expected a name usable as one folder name of at most 100 bytes (this one has 300)");
  EXPECT_LT(m.size(), 400u) << "the message echoes the whole name";
  TempDir d;
  EXPECT_EQ(load_case(d.write("c.toml", kCase).string(), {"case.name=\"" + std::string(100, 'x') + "\""}).name.size(),
            100u);
}

// ------------------------------------------------------------------------ D11
// A folder or a device read as an empty file: "missing required section [case]".
TEST(Inputs, D11CaseFileMustBeARegularFile) {
  TempDir d;
  auto message = [](const std::string& path) {
    try {
      load_case(path);
    } catch (const CaseError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_HAS(message(d.path.string()), d.path.string() + ": is a folder, expected a case file (TOML)");
  EXPECT_HAS(message("/dev/null"), "/dev/null: is not a regular file (a pipe, terminal or device)");
  EXPECT_HAS(message((d.path / "missing.toml").string()), "missing.toml: cannot open the case file: no such file");
  // A case file of more than 16 MB is not one (checked before it is read).
  std::string big = kCase;
  big += "# " + std::string(17 << 20, 'x') + "\n";
  EXPECT_HAS(message(d.write("big.toml", big).string()), "expected a case file (TOML) of at most 16.8 MB");
}

// ------------------------------------------------------------------------ smaller ones
// cross_section_x beyond the cell was wrapped around the period without a word.
TEST(Inputs, CrossSectionInsideTheCell) {
  for (const char* x : {"observables.cross_section_x=2.5e-3", "observables.cross_section_x=1e-3"})
    EXPECT_HAS(error_of(kCase, {x}), "[observables] cross_section_x: expected an x inside the cell, 0 <= x < size = 0.001 m");
  TempDir d;
  EXPECT_DOUBLE_EQ(load_case(d.write("c.toml", kCase).string(), {"observables.cross_section_x=0.999e-3"})
                       .observables.cross_section_x,
                   0.999e-3);
}

// A self-affine band beyond the generator's 1e6 x the grid size failed after parsing,
// with an exception that was not bad input.
TEST(Inputs, SelfAffineBandBounded) {
  std::string t = kCase;
  t.replace(t.find("kind = \"sphere\"\nradius = 1e-2"), 29,
            "kind = \"self_affine\"\nrolloff_wavelength = 2e-4\ncutoff_wavelength = 1e-10");
  EXPECT_HAS(error_of(t), "[surface] cutoff_wavelength: expected at least 1e-6 x the grid size, 1e-9 m");
}

// Refinement grids were read as numbers and narrowed to int unchecked.
TEST(Inputs, RefinementGridsBounded) {
  const std::string v = std::string(kCase) +
                        "[validation]\nreference = \"hertz\"\n[validation.refinement]\ngrids = [16, GRIDS]\n"
                        "quantity = \"penetration\"\nmin_order = 1\n";
  auto with = [&](const std::string& g) { return std::string(v).replace(v.find("GRIDS"), 5, g); };
  EXPECT_HAS(error_of(with("4294967312")), "[validation.refinement] grids: expected an increasing array of at least 2 grid sizes, each from 2 to 1048576");
  EXPECT_HAS(error_of(with("1048576")), "[validation.refinement] grids: expected a grid whose run fits in the memory available");
}

// `cmc refine --grids` narrowed its sizes to int: 2^32 + 128 ran as 128.
TEST(Inputs, RefineGridsBounded) {
  const fs::path cmc = cmc_program();
  if (cmc.empty()) GTEST_SKIP() << "no cmc program beside the test binary";
  TempDir d;
  std::string out;
  EXPECT_EQ(sh(cmc.string() + " refine " + CMC_SOURCE_DIR + "/cases/challenge/reference-load-hardwall.toml --grids 64 "
                   "4294967424 --quiet --out " + (d.path / "r").string(), &out),
            2);
  EXPECT_HAS(out, "--grids: expected increasing grid sizes from 2 to 1048576, got 4294967424");
  EXPECT_FALSE(fs::exists(d.path / "r")) << "a grid was run";
}

// ------------------------------------------------------------------------ D12
// An ASCII height file cut short at the end of a row (fewer rows than the grid) was
// read as a map coarser along y and interpolated.
TEST(Inputs, D12TruncatedAsciiFileRefused) {
  TempDir d;
  const int n = 16;
  HeightMap full{Grid{n, n, 1.0, 1.0}, Field(std::size_t(n) * n)};
  for (int iy = 0; iy < n; ++iy)
    for (int ix = 0; ix < n; ++ix) full.heights[std::size_t(iy) * n + ix] = 1e-6 * (1 + std::cos(2 * M_PI * (ix + 2 * iy) / n));
  write_ascii_heights(d.path / "full.txt", full);
  // The first 8 of its 16 rows.
  std::ifstream in(d.path / "full.txt");
  std::string text, row;
  for (int k = 0; k < n / 2 && std::getline(in, row); ++k) text += row + "\n";
  d.write("cut.txt", text);
  std::string t = kCase;
  t.replace(t.find("kind = \"sphere\"\nradius = 1e-2"), 29, "kind = \"file\"\npath = \"FILE\"\nformat = \"ascii\"");
  auto scene_error = [&](const std::string& file) {
    const fs::path f = d.write("case.toml", std::string(t).replace(t.find("FILE"), 4, file));
    try {
      build_scene(load_case(f.string()));
    } catch (const CaseError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string m = scene_error("cut.txt");
  EXPECT_HAS(m, "cut.txt has 16 x 8 points (x by y, 128 values); expected the case's 16 x 16 points or a coarser map "
                "with the same factor along x and y (a truncated file?");
  EXPECT_EQ(scene_error("full.txt"), "accepted");
  // A genuinely coarser map (the same factor along x and y) is still interpolated.
  HeightMap coarse{Grid{8, 8, 1.0, 1.0}, Field(64, 1e-6)};
  write_ascii_heights(d.path / "coarse.txt", coarse);
  EXPECT_EQ(scene_error("coarse.txt"), "accepted");
}

// ------------------------------------------------------------------------ D13
// The declared shape of an HDF5 dataset was not checked before reading: a header that
// claims 65536² (a file of a few kB, nothing stored) was allocated and read.
TEST(Inputs, D13LyingHdf5HeaderRefused) {
  TempDir d;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  auto make = [&](const std::string& name, hsize_t declared, bool write_one_chunk) {
    const fs::path p = d.path / name;
    const hid_t f = H5Fcreate(p.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t dims[2] = {declared, declared}, chunk[2] = {8, 8};
    const hid_t sp = H5Screate_simple(2, dims, nullptr);
    const hid_t pl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(pl, 2, chunk);
    const hid_t ds = H5Dcreate2(f, "surface", H5T_NATIVE_DOUBLE, sp, H5P_DEFAULT, pl, H5P_DEFAULT);
    if (write_one_chunk) {  // only the first 8 x 8 values
      const hsize_t start[2] = {0, 0};
      H5Sselect_hyperslab(sp, H5S_SELECT_SET, start, nullptr, chunk, nullptr);
      const hid_t mem = H5Screate_simple(2, chunk, nullptr);
      std::vector<double> v(64, 1e-3);
      H5Dwrite(ds, H5T_NATIVE_DOUBLE, mem, sp, H5P_DEFAULT, v.data());
      H5Sclose(mem);
    }
    H5Dclose(ds), H5Pclose(pl), H5Sclose(sp), H5Fclose(f);
    return p;
  };
  EXPECT_LT(fs::file_size(make("liar.h5", 65536, false)), 100000u);
  make("partial.h5", 16, true);
  std::string t = kCase;
  t.replace(t.find("kind = \"sphere\"\nradius = 1e-2"), 29, "kind = \"file\"\npath = \"FILE\"\nformat = \"challenge_hdf5\"");
  auto scene_error = [&](const std::string& file) {
    const fs::path f = d.write("case.toml", std::string(t).replace(t.find("FILE"), 4, file));
    try {
      build_scene(load_case(f.string()));
    } catch (const CaseError& e) {
      return std::string(e.what());
    } catch (const std::exception& e) {
      return std::string("not bad input: ") + e.what();
    }
    return std::string("accepted");
  };
  EXPECT_HAS(scene_error("liar.h5"), "[grid] n: " + (d.path / "liar.h5").string() +
                                         ": dataset 'surface' declares 65536 x 65536 points (x by y), more than the 16 x 16 expected");
  EXPECT_HAS(scene_error("partial.h5"), "[surface] path: " + (d.path / "partial.h5").string() +
                                            ": dataset 'surface' holds no data in 3 of its 4 chunks (never written)");
}

// ------------------------------------------------------------------------ D14
// A flat indenter under load control: the exact answer is full contact with p = p̄
// everywhere and gap 0. Polonsky-Keer found it; the adhesive CG's load control walked
// to full contact, found no bracket and reported the step not converged.
TEST(Inputs, D14FlatSurfaceUnderLoadControl) {
  TempDir d;
  const std::string flat = R"(
[case]
name = "flat"
[grid]
n = 32
size = 1e-3
[material]
contact_modulus = 1e6
[surface]
kind = "flat"
[loading]
control = "mean_pressure"
values = [1e3, 2e3]
)";
  const fs::path f = d.write("flat.toml", flat);
  const std::string adhesion[] = {"interaction.kind=\"exponential\"", "interaction.work_of_adhesion=1e-3",
                                  "interaction.range=1e-6"};  // peak tension w/rho = 1 kPa
  struct Run {
    std::string what;
    std::vector<std::string> overrides;
    std::vector<double> loads;
  };
  const std::vector<Run> runs = {
      {"Polonsky-Keer", {}, {1e3, 2e3}},
      {"adhesive CG, hard wall", {"solver.kind=\"adhesive_cg\""}, {1e3, 2e3}},
      {"adhesive CG, exponential adhesion", {adhesion[0], adhesion[1], adhesion[2], "loading.values=[1e3, -500]"},
       {1e3, -500}},
      {"quasi-static, exponential adhesion (auto on a loading path)", {adhesion[0], adhesion[1], adhesion[2]},
       {1e3, 2e3}},
  };
  for (const Run& r : runs) {
    SCOPED_TRACE(r.what);
    const Case c = load_case(f.string(), r.overrides);
    Scene s = build_scene(c);
    std::vector<ContactState> states;
    const RunSummary run = run_scene(c, s, [&](const StepRecord&, const ContactState& st) { states.push_back(st); });
    EXPECT_EQ(run.status, RunStatus::Converged) << run.message;
    ASSERT_EQ(states.size(), r.loads.size());
    for (std::size_t k = 0; k < states.size(); ++k) {
      const double pbar = s.units.pressure(r.loads[k]);
      EXPECT_NEAR(run.steps[k].mean_pressure, r.loads[k], 1e-12 * std::abs(r.loads[k]));
      EXPECT_EQ(run.steps[k].contact_fraction, 1.0);
      for (std::size_t i = 0; i < states[k].gap.size(); ++i) {
        ASSERT_EQ(states[k].gap[i], 0.0) << i;
        ASSERT_NEAR(states[k].pressure[i], pbar, 1e-12 * std::abs(pbar)) << i;
      }
    }
  }
  // Beyond the peak tension the surfaces part: no state carries it, and it says so.
  const Case c = load_case(f.string(), {adhesion[0], adhesion[1], adhesion[2], "loading.values=[-2e3]",
                                        "solver.kind=\"adhesive_cg\""});
  Scene s = build_scene(c);
  const RunSummary run = run_scene(c, s, {});
  EXPECT_EQ(run.status, RunStatus::NotConverged);
  EXPECT_HAS(run.message, "no penetration found that carries mean pressure");
}

// The same holds for any periodic surface pressed into full contact: a wavy surface
// above Westergaard's p* (the load that closes the last gap), where the adhesive CG
// stopped "beyond pull-off, or full contact". Full contact is exact there: p = p̄ − K h,
// the Polonsky-Keer answer to its tolerance.
TEST(Inputs, D14FullContactAboveWestergaardPressure) {
  const std::string wavy = std::string(CMC_SOURCE_DIR) + "/cases/validation/westergaard.toml";
  // p* = pi E* a / lambda = 3141.59 Pa
  const std::vector<std::string> o = {"grid.nx=256", "loading.values=[2827.4, 3141.6, 5000.0]"};
  auto solve = [&](const std::string& kind) {
    std::vector<std::string> ov = o;
    ov.push_back("solver.kind=\"" + kind + "\"");
    if (kind == "adhesive_cg") ov.push_back("solver.tolerance=1e-8");  // its own residual
    Case c = load_case(wavy, ov);
    c.validation.reset();
    Scene s = build_scene(c);
    std::vector<ContactState> states;
    const RunSummary run = run_scene(c, s, [&](const StepRecord&, const ContactState& st) { states.push_back(st); });
    EXPECT_EQ(run.status, RunStatus::Converged) << kind << ": " << run.message;
    return std::pair{run, states};
  };
  const auto [pk, pk_states] = solve("polonsky_keer");
  const auto [cg, cg_states] = solve("adhesive_cg");
  ASSERT_EQ(cg_states.size(), 3u);
  ASSERT_EQ(pk_states.size(), 3u);
  for (std::size_t k = 1; k < 3; ++k) {
    EXPECT_EQ(cg.steps[k].contact_fraction, 1.0);
    EXPECT_NEAR(cg.steps[k].energy, pk.steps[k].energy, 1e-8 * pk.steps[k].energy);
    double err = 0, pmax = 0;
    for (std::size_t i = 0; i < cg_states[k].pressure.size(); ++i) {
      err = std::max(err, std::abs(cg_states[k].pressure[i] - pk_states[k].pressure[i]));
      pmax = std::max(pmax, std::abs(pk_states[k].pressure[i]));
    }
    EXPECT_LT(err, 1e-6 * pmax) << "step " << k;
  }
}

// ------------------------------------------------------------------------ cmc check
namespace {
// A reference in the reference format: contact fraction 2.2 p/E* on 41 log-spaced
// pressures from 1 kPa to 2 MPa (3.3 decades), no min_coverage line.
fs::path write_reference(const TempDir& d) {
  std::string text =
      "# cmc-reference-csv: 1\n# name: ref\n# quantity: contact_area_vs_pressure\n# title: t\n# source: test\n"
      "# unit.pressure_Pa: Pa\n# unit.contact_fraction: 1\n# columns: pressure_Pa,contact_fraction\n"
      "# x: pressure_Pa\n# y: contact_fraction\n# representation: log-log\n# estimated_error: none\n"
      "# tolerance: 0.05\n# tolerance_metric: max_rel\npressure_Pa,contact_fraction\n";
  for (int k = 0; k <= 40; ++k) {
    const double p = 1e3 * std::pow(2000.0, k / 40.0);
    char row[80];
    std::snprintf(row, sizeof row, "%.12e,%.12e\n", p, 2.2 * p / 25e6);
    text += row;
  }
  return d.write("ref.csv", text);
}
}  // namespace

// Two rows covering 3.7 % of the reference's range passed.
TEST(Inputs, CheckRequiresRangeCoverage) {
  const fs::path cmc = cmc_program();
  if (cmc.empty()) GTEST_SKIP() << "no cmc program beside the test binary";
  TempDir d;
  const fs::path ref = write_reference(d);
  // 1e5 .. 1.3e5 Pa: log10(1.3) / log10(2000) = 3.45 % of the range, and exact values.
  const fs::path two = d.write("two.csv", "pressure_Pa,contact_fraction\n1e5,0.0088\n1.3e5,0.01144\n");
  std::string out;
  const std::string cmd = cmc.string() + " check " + two.string() + " --quantity contact_area_vs_pressure --reference " +
                          ref.string() + " --out " + (d.path / "o").string();
  EXPECT_EQ(sh("CMC_PYTHON=/nonexistent " + cmd, &out), 5);
  EXPECT_HAS(out, "FAIL: the prediction covers 3.45");
  EXPECT_HAS(out, "% of the reference's range of the mean pressure (100000 .. 130000 of 1000 .. 2e+06 Pa, in the "
                  "log-log representation); at least 50% is needed (default for contact_area_vs_pressure)");
  // The same values over the whole range pass.
  std::string all = "pressure_Pa,contact_fraction\n";
  for (double p : {1e3, 1e4, 1e5, 1e6, 2e6}) all += std::to_string(p) + "," + std::to_string(2.2 * p / 25e6) + "\n";
  EXPECT_EQ(sh("CMC_PYTHON=/nonexistent " + cmc.string() + " check " + d.write("all.csv", all).string() +
               " --quantity contact_area_vs_pressure --reference " + ref.string()),
            0);
}

// A 54 MB prediction took 1.4 GB and wrote a 293 MB check.json: the prediction is now
// streamed, and check.json echoes at most 1000 rows, saying so.
TEST(Inputs, CheckStreamsLargePredictions) {
  const fs::path cmc = cmc_program();
  if (cmc.empty()) GTEST_SKIP() << "no cmc program beside the test binary";
  TempDir d;
  const fs::path ref = write_reference(d);
  const int rows = 400000;  // 14 MB
  {
    std::ofstream f(d.path / "big.csv");
    f << "pressure_Pa,contact_fraction\n";
    char row[80];
    for (int i = 0; i < rows; ++i) {
      const double p = 1e3 * std::pow(2000.0, double(i) / (rows - 1));
      std::snprintf(row, sizeof row, "%.10e,%.10e\n", p, 1.01 * 2.2 * p / 25e6);
      f << row;
    }
  }
  EXPECT_GT(fs::file_size(d.path / "big.csv"), 12u << 20);
  std::fflush(nullptr);  // the child must not write the parent's buffered output again
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setenv("CMC_PYTHON", "/nonexistent", 1);
    if (!std::freopen("/dev/null", "w", stdout) || !std::freopen("/dev/null", "w", stderr)) ::_exit(127);
    ::execl(cmc.c_str(), "cmc", "check", (d.path / "big.csv").c_str(), "--quantity", "contact_area_vs_pressure",
            "--reference", ref.c_str(), "--out", (d.path / "o").c_str(), (char*)nullptr);
    ::_exit(127);
  }
  int status = 0;
  struct rusage ru {};
  ASSERT_EQ(::wait4(pid, &status, 0, &ru), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);  // 1 % off, tolerance 5 %
  // Peak memory: the program and the reference, not the 14 MB of rows (measured before
  // the fix: about 26 bytes of memory per byte of the file).
  EXPECT_LT(ru.ru_maxrss, 40L * 1024) << "kB";
  const fs::path json = d.path / "o" / "check.json";
  ASSERT_TRUE(fs::exists(json));
  EXPECT_LT(fs::file_size(json), 300u * 1024);
  std::ifstream in(json);
  std::ostringstream ss;
  ss << in.rdbuf();
  const std::string j = ss.str();
  EXPECT_HAS(j, "\"rows\" : 400000");
  EXPECT_HAS(j, "check.json echoes ");
  EXPECT_HAS(j, " of the prediction's 400000 rows");
  EXPECT_HAS(j, "\"max_rel\" : 0.0100000000");
}
