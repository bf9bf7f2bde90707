// Every size checked before it is used. The memory estimate against
// the peak memory of real runs, the memory available, the surface readers' shape
// limits, and `cmc check`'s coverage requirement and its sources.
#include "cmc/input/Case.hpp"
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
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

using namespace cmc;
namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path path;
  TempDir() {
    std::string t = (fs::temp_directory_path() / "cmc_test_limits_XXXXXX").string();
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

fs::path cmc_program() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec).parent_path() / "cmc";
  return fs::exists(p) ? p : fs::path{};
}

// Peak resident memory (bytes) of `cmc args...` run as a child, which must exit 0.
double peak_of_run(const fs::path& cmc, const std::vector<std::string>& args) {
  std::fflush(nullptr);  // the child must not write the parent's buffered output again
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (!std::freopen("/dev/null", "w", stdout) || !std::freopen("/dev/null", "w", stderr)) ::_exit(127);
    ::setenv("CMC_THREADS", "1", 1);  // one thread: fast on a shared machine, and per-thread arrays counted once
    std::vector<char*> argv = {const_cast<char*>("cmc")};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(cmc.c_str(), argv.data());
    ::_exit(127);
  }
  int status = 0;
  struct rusage ru {};
  if (::wait4(pid, &status, 0, &ru) != pid || !WIFEXITED(status)) return -1.0;
  EXPECT_EQ(WEXITSTATUS(status), 0) << ::testing::PrintToString(args);
  return double(ru.ru_maxrss) * 1024.0;
}

#define EXPECT_HAS(text, fragment) EXPECT_NE(std::string(text).find(fragment), std::string::npos) << (text)

}  // namespace

// The estimate is an upper bound of what a run holds at its peak, and not a gross one:
// for each solver and boundary, the growth of the peak resident memory of a real run
// from a 16² grid to a larger one is at most the growth of the estimate, and at least a
// third of it. The estimate counts every field the code allocates, which a run does not
// always hold at once, plus what glibc may keep of freed ones; the peak itself varies
// between runs and versions with how glibc reuses freed blocks (the same PK run measured
// 28.5 and 17.3 MB). Measured ratios estimate/peak: 1.1 to 2.3.
TEST(Limits, MemoryEstimateBoundsMeasuredPeak) {
  const fs::path cmc = cmc_program();
  if (cmc.empty()) GTEST_SKIP() << "no cmc program beside the test binary";
  TempDir d;
  const std::string src = CMC_SOURCE_DIR;
  const fs::path adhesive = d.write("adhesive.toml", R"(
[case]
name = "adhesive"
[grid]
n = 16
size = 1e-4
[material]
contact_modulus = 25e6
[surface]
kind = "wavy2d"
amplitude = 1e-6
[interaction]
kind = "exponential"
work_of_adhesion = 0.05
range = 2e-8
[loading]
control = "penetration"
values = [0.5e-6]
[observables]
enabled = true
)");
  struct Config {
    std::string what, file;
    int n;
    std::vector<std::string> sets;
  };
  const std::vector<Config> configs = {
      {"Polonsky-Keer, periodic", src + "/cases/validation/hertz-periodic.toml", 512, {}},
      {"Polonsky-Keer, free, observables", src + "/cases/validation/hertz-free.toml", 256, {"observables.enabled=true"}},
      {"adhesive CG, periodic, observables", adhesive.string(), 512, {"solver.kind=\"adhesive_cg\""}},
      {"quasi-static (auto on a loading path), periodic sphere, observables",
       src + "/cases/validation/hertz-periodic.toml",
       512,
       {"interaction.kind=\"exponential\"", "interaction.work_of_adhesion=1e-4", "interaction.range=1e-7",
        "observables.enabled=true"}},
      {"adhesive CG, free, load path with pull-off search", src + "/cases/validation/maugis-dugdale-lambda1.toml", 128,
       {}},
  };
  for (const Config& c : configs) {
    SCOPED_TRACE(c.what);
    auto run = [&](int n) {
      std::vector<std::string> args = {"run", c.file, "--quiet", "--out", (d.path / "out").string(), "--set",
                                       "grid.n=" + std::to_string(n)};
      std::vector<std::string> overrides = {"grid.n=" + std::to_string(n)};
      for (const auto& s : c.sets) args.push_back("--set"), args.push_back(s), overrides.push_back(s);
      return std::pair{peak_of_run(cmc, args), estimate_memory(load_case(c.file, overrides)).bytes};
    };
    const auto [peak0, est0] = run(16);
    const auto [peak1, est1] = run(c.n);
    const double measured = peak1 - peak0, estimated = est1 - est0;
    std::printf("  %s: peak %.1f MB measured, %.1f MB estimated (x%.2f)\n", c.what.c_str(), measured / 1e6,
                estimated / 1e6, estimated / measured);
    EXPECT_GT(measured, 0.0);
    EXPECT_LE(measured, estimated) << "the estimate is below the peak: " << measured / 1e6 << " MB measured, "
                                   << estimated / 1e6 << " MB estimated";
    EXPECT_LE(estimated, 3.0 * measured) << measured / 1e6 << " MB measured, " << estimated / 1e6 << " MB estimated";
  }
}

// What the estimate is made of, and that it grows with every field a case adds.
TEST(Limits, MemoryEstimateCountsWhatTheCaseHolds) {
  TempDir d;
  const fs::path f = d.write("c.toml", R"(
[case]
name = "c"
[grid]
n = 1024
size = 1e-3
[material]
contact_modulus = 1e6
[surface]
kind = "sphere"
radius = 1e-2
[loading]
control = "force"
values = [1e-4]
)");
  const MemoryEstimate pk = estimate_memory(load_case(f.string()));
  EXPECT_HAS(pk.what, "fields of the grid and");
  EXPECT_HAS(pk.what, "of the periodic transform grid");
  const double field = 8.0 * 1024 * 1024;
  EXPECT_GT(pk.bytes, 10 * field);
  EXPECT_LT(pk.bytes, 30 * field);
  // The free boundary's transform grid is four times larger.
  const MemoryEstimate free = estimate_memory(load_case(f.string(), {"grid.boundary=\"free\""}));
  EXPECT_HAS(free.what, "zero-padded 2nx x 2ny");
  EXPECT_GT(free.bytes, 2.5 * pk.bytes);
  // Observables are measured after a solve has returned its own fields: they raise the
  // peak only by what they hold beyond the solve's (Polonsky-Keer: the direction, the
  // preconditioned gap and three spectra, more than the observables' 4.1 fields), but
  // inside the adhesive CG's load path they add to everything it holds.
  EXPECT_GE(estimate_memory(load_case(f.string(), {"observables.enabled=true"})).bytes, pk.bytes);
  const std::vector<std::string> cg = {"interaction.kind=\"exponential\"", "interaction.work_of_adhesion=1e-4",
                                       "interaction.range=1e-7", "solver.kind=\"adhesive_cg\""};
  std::vector<std::string> cg_obs = cg;
  cg_obs.push_back("observables.enabled=true");
  EXPECT_GT(estimate_memory(load_case(f.string(), cg_obs)).bytes, estimate_memory(load_case(f.string(), cg)).bytes);
  // A quasi-static solve holds more than measuring a step does: the observables add nothing.
  std::vector<std::string> qs = cg;
  qs.back() = "solver.kind=\"quasi_static\"";
  std::vector<std::string> qs_obs = qs;
  qs_obs.push_back("observables.enabled=true");
  EXPECT_EQ(estimate_memory(load_case(f.string(), qs_obs)).bytes, estimate_memory(load_case(f.string(), qs)).bytes);
  EXPECT_GT(estimate_memory(load_case(f.string(), qs)).bytes, pk.bytes);
  // The self-affine generator makes every mode of its band, whatever the grid: a band
  // of size/cutoff = 1e6 on a 16² grid needs (pi/2) 1e12 modes, and says so.
  std::string t = std::string(std::istreambuf_iterator<char>(std::ifstream(f).rdbuf()), {});
  t.replace(t.find("kind = \"sphere\"\nradius = 1e-2"), 29,
            "kind = \"self_affine\"\nrolloff_wavelength = 2e-4\ncutoff_wavelength = 1e-9");
  try {
    load_case(d.write("band.toml", t).string(), {"grid.n=16"});
    ADD_FAILURE() << "accepted";
  } catch (const CaseError& e) {
    EXPECT_HAS(e.what(), "[grid] n: expected a grid whose run fits in the memory available: a run on 16 x 16 points "
                         "holds about ");
    EXPECT_HAS(e.what(), "(the self-affine surface's 1.57e+12 Fourier modes while it is made)");
  }
}

// The memory available is known on Linux, positive and no more than the machine has.
TEST(Limits, AvailableMemory) {
  const std::optional<double> a = available_memory();
  ASSERT_TRUE(a.has_value());
  EXPECT_GT(*a, 0.0);
  std::ifstream in("/proc/meminfo");
  std::string key;
  double kb = 0;
  while (in >> key >> kb) {
    std::string rest;
    std::getline(in, rest);
    if (key == "MemTotal:") EXPECT_LE(*a, kb * 1024.0);
  }
  EXPECT_EQ(memory_text(1.5e9), "1.5 GB");
  EXPECT_EQ(memory_text(312e6), "312 MB");
}

// The readers check a file's shape against their limit before allocating it.
TEST(Limits, SurfaceReadersHonourTheirLimit) {
  TempDir d;
  HeightMap m{Grid{8, 4, 1.0, 1.0}, Field(32, 1.0)};
  write_ascii_heights(d.path / "m.txt", m);
  write_hdf5_heights(d.path / "m.h5", m);
  auto shape_error = [](auto&& read) {
    try {
      read();
    } catch (const SurfaceShapeError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_HAS(shape_error([&] { read_ascii_heights(d.path / "m.txt", 1, 1, 1.0, false, MapLimit{4, 4}); }),
             "line 1 has 8 values, more than the 4 columns (points along x) expected");
  EXPECT_HAS(shape_error([&] { read_ascii_heights(d.path / "m.txt", 1, 1, 1.0, false, MapLimit{8, 2}); }),
             "line 3: more than the 2 rows (points along y) expected");
  EXPECT_HAS(shape_error([&] { read_hdf5_heights(d.path / "m.h5", "surface", 1, 1, 1.0, false, MapLimit{8, 2}); }),
             "dataset 'surface' declares 8 x 4 points (x by y), more than the 8 x 2 expected");
  EXPECT_EQ(read_ascii_heights(d.path / "m.txt", 1, 1, 1.0, false, MapLimit{8, 4}).grid.size(), 32u);
  // A text file beyond 100 bytes per allowed value (plus 1 MiB) is not read at all.
  {
    std::ofstream f(d.path / "long.txt");
    f << "1 2\n3 4\n# " << std::string(2 << 20, 'x') << "\n";
  }
  try {
    read_ascii_heights(d.path / "long.txt", 1, 1, 1.0, false, MapLimit{2, 2});
    ADD_FAILURE() << "accepted";
  } catch (const SurfaceFileError& e) {
    EXPECT_HAS(e.what(), "more than a height file of the expected size takes (at most 1.05 MB)");
  }
}

// cmc check: the coverage a prediction needs comes from --min-coverage, else the
// reference's "# min_coverage:" line, else the default (Inputs.CheckRequiresRangeCoverage).
TEST(Limits, CheckCoverageSources) {
  const fs::path cmc = cmc_program();
  if (cmc.empty()) GTEST_SKIP() << "no cmc program beside the test binary";
  TempDir d;
  std::string ref =
      "# cmc-reference-csv: 1\n# name: ref\n# quantity: contact_area_vs_pressure\n# title: t\n# source: test\n"
      "# MINCOV"
      "# unit.pressure_Pa: Pa\n# unit.contact_fraction: 1\n# columns: pressure_Pa,contact_fraction\n"
      "# x: pressure_Pa\n# y: contact_fraction\n# representation: log-log\n# estimated_error: none\n"
      "# tolerance: 0.05\n# tolerance_metric: max_rel\npressure_Pa,contact_fraction\n";
  for (int k = 0; k <= 40; ++k) {
    const double p = 1e3 * std::pow(2000.0, k / 40.0);
    char row[80];
    std::snprintf(row, sizeof row, "%.12e,%.12e\n", p, 2.2 * p / 25e6);
    ref += row;
  }
  auto reference = [&](const std::string& line) {
    return d.write("ref.csv", std::string(ref).replace(ref.find("# MINCOV"), 8, line)).string();
  };
  const std::string two = d.write("two.csv", "pressure_Pa,contact_fraction\n1e5,0.0088\n1.3e5,0.01144\n").string();
  auto run = [&](const std::string& ref_file, const std::string& extra) {
    const std::string cmd = "CMC_PYTHON=/nonexistent " + cmc.string() + " check " + two +
                            " --quantity contact_area_vs_pressure --reference " + ref_file + " " + extra +
                            " >/dev/null 2>&1";
    const int s = std::system(cmd.c_str());
    return WIFEXITED(s) ? WEXITSTATUS(s) : -1;
  };
  EXPECT_EQ(run(reference(""), ""), 5);                      // default 0.5
  EXPECT_EQ(run(reference(""), "--min-coverage 0.03"), 0);   // covers 3.45 %
  EXPECT_EQ(run(reference(""), "--min-coverage 0.04"), 5);
  EXPECT_EQ(run(reference("# min_coverage: 0.03\n"), ""), 0);
  EXPECT_EQ(run(reference("# min_coverage: 0.03\n"), "--min-coverage 0.5"), 5);  // the command line wins
  EXPECT_EQ(run(reference(""), "--min-coverage 1.5"), 2);
  EXPECT_EQ(run(reference("# min_coverage: lots\n"), ""), 2);
}
