// Tests of the prediction checker (validation/Check.*, `cmc check`): synthetic
// predictions with a known perturbation are scored with the expected metric, the verdict
// flips at the tolerance, and every class of malformed input is rejected with a message
// naming the problem -- and, through the cmc program, nothing is written.
#include "Check.hpp"
#include "References.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace cmc::check;
namespace ref = cmc::reference;

struct TempDir {
  fs::path path;
  TempDir() {
    std::string t = (fs::temp_directory_path() / "cmc_test_check_XXXXXX").string();
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

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

// A synthetic challenge reference: a_r = 2.2 p/E* (1 + 30 p/E*) on 41 log-spaced
// pressures from 1 kPa to 2 MPa, SI columns, tolerance 0.05 on max_rel.
struct Synthetic {
  std::vector<double> p, ar, gap;
};
Synthetic synthetic() {
  Synthetic s;
  for (int k = 0; k <= 40; ++k) {
    const double p = 1e3 * std::pow(2000.0, k / 40.0);
    s.p.push_back(p);
    const double t = p / kChallengeEstar;
    s.ar.push_back(2.2 * t * (1 + 30 * t));
    s.gap.push_back(1e-6 * (1.5 - 0.18 * std::log(p / 1e3)));  // m, positive over the range
  }
  return s;
}

// The provenance of the synthetic references.
ref::RunProvenance synthetic_provenance() {
  ref::RunProvenance how;
  how.case_file = "synthetic";
  how.grid = "none";
  how.solver_tolerance = "none";
  how.date = "2000-01-01T00:00:00Z";
  return how;
}

fs::path write_reference(const TempDir& d, const std::string& quantity, std::optional<double> tol = 0.05,
                         const std::string& metric = "max_rel") {
  const Synthetic s = synthetic();
  const ref::RunProvenance how = synthetic_provenance();
  ref::Curve c;
  if (quantity == "contact_area_vs_pressure")
    c = ref::make_run_curve(quantity, quantity, "synthetic", how,
                            {{"pressure_Pa", "Pa", "", s.p}, {"contact_fraction", "1", "", s.ar}}, "pressure_Pa",
                            "contact_fraction", "log-log", "exact (synthetic)", tol, metric);
  else
    c = ref::make_run_curve(quantity, quantity, "synthetic", how,
                            {{"pressure_Pa", "Pa", "", s.p}, {"mean_gap_m", "m", "", s.gap}}, "pressure_Pa",
                            "mean_gap_m", "log-lin", "exact (synthetic)", tol, metric);
  const fs::path f = d.path / (quantity + ".csv");
  ref::write_curve(f.string(), c);
  return f;
}

Report check(const fs::path& pred, const std::string& quantity, const fs::path& reference,
             std::optional<double> tol = std::nullopt, const std::string& metric = "") {
  Options o;
  o.prediction = pred.string();
  o.quantity = quantity;
  o.reference_file = reference.string();
  o.tolerance = tol;
  o.metric = metric;
  return run_check(o);
}

// ------------------------------------------------------------------------ scoring
TEST(CheckScoring, MultiplicativePerturbationOnLogAxis) {
  TempDir d;
  const fs::path r = write_reference(d, "contact_area_vs_pressure");
  const Synthetic s = synthetic();
  for (double eps : {0.03, 0.06}) {
    // Reduced units (p/E*), and only every third point: the prediction's x grid differs
    // from the reference's only in sampling, and the perturbation is exactly eps.
    std::string text = "# a prediction\np_over_Estar,contact_fraction\n";
    for (std::size_t i = 0; i < s.p.size(); i += 3)
      text += num(s.p[i] / kChallengeEstar) + "," + num(s.ar[i] * (1 + eps)) + "\n";
    const Report rep = check(d.write("pred.csv", text), "contact_area_vs_pressure", r);
    // The error is exactly eps on the prediction's points; on the reference's points in
    // between, the prediction is interpolated in log-log and adds the curvature of
    // log a_r(log p) (h^2/8 * second derivative, under 1% here) -- so the metric is
    // eps plus at most that, and the verdict follows eps against the tolerance 5%.
    EXPECT_NEAR(rep.metrics.max_rel, eps, 1e-2);
    EXPECT_GE(rep.metrics.max_rel, eps - 1e-12);
    EXPECT_EQ(rep.verdict.metric, "max_rel");
    EXPECT_EQ(rep.verdict.tolerance, 0.05);
    EXPECT_EQ(rep.verdict.pass, eps < 0.05);
  }
}

// A value <= 0 on a log y axis where the reference has one is a wrong prediction: the
// verdict fails naming its lines (it was left out, and the curve interpolated across it).
TEST(CheckScoring, NonPositiveOnALogAxisFails) {
  TempDir d;
  const fs::path r = write_reference(d, "contact_area_vs_pressure");
  const Synthetic s = synthetic();
  for (const double bad : {0.0, -0.01}) {
    std::string text = "pressure_Pa,contact_fraction\n";  // exact, but for every 6th point from the 3rd
    for (std::size_t i = 0; i < s.p.size(); ++i) text += num(s.p[i]) + "," + num(i % 6 == 2 ? bad : s.ar[i]) + "\n";
    text += "1e9,0\n";  // beyond the reference's range: only left out
    const Report rep = check(d.write("pred.csv", text), "contact_area_vs_pressure", r);
    EXPECT_FALSE(rep.verdict.pass);
    EXPECT_EQ(rep.metrics.nonpositive.count, 7u);
    EXPECT_NE(rep.verdict.reason.find("7 row(s)"), std::string::npos) << rep.verdict.reason;
    EXPECT_NE(rep.verdict.reason.find("lines 4, 10, 16, 22, 28, ..."), std::string::npos) << rep.verdict.reason;
  }
  std::string text = "pressure_Pa,contact_fraction\n";
  for (std::size_t i = 0; i < s.p.size(); ++i) text += num(s.p[i]) + "," + num(s.ar[i]) + "\n";
  const Report ok = check(d.write("pred.csv", text + "1e9,0\n"), "contact_area_vs_pressure", r);
  EXPECT_TRUE(ok.verdict.pass) << ok.verdict.reason;
  EXPECT_EQ(ok.metrics.excluded_prediction, 1u);
}

TEST(CheckScoring, ExactMetricsOnTheReferencesPoints) {
  TempDir d;
  const fs::path r = write_reference(d, "contact_area_vs_pressure");
  const Synthetic s = synthetic();
  const double eps = 0.03;
  std::string text = "pressure_kPa,contact_fraction\n";
  for (std::size_t i = 0; i < s.p.size(); ++i) text += num(s.p[i] / 1e3) + "," + num(s.ar[i] * (1 + eps)) + "\n";
  const Report rep = check(d.write("pred.csv", text), "contact_area_vs_pressure", r);
  EXPECT_NEAR(rep.metrics.max_rel, eps, 1e-12);
  EXPECT_NEAR(rep.metrics.rms_rel, eps, 1e-12);
  EXPECT_NEAR(rep.metrics.max_abs, std::log10(1 + eps), 1e-12);  // decades
  EXPECT_NEAR(rep.metrics.rms_abs, std::log10(1 + eps), 1e-12);
  EXPECT_NEAR(rep.metrics.coverage, 1.0, 1e-12);
  EXPECT_GE(rep.metrics.points, s.p.size());
  EXPECT_TRUE(rep.verdict.pass);
  // --tolerance and --metric override the reference's.
  const Report strict = check(d.path / "pred.csv", "contact_area_vs_pressure", r, 0.02);
  EXPECT_FALSE(strict.verdict.pass);
  EXPECT_EQ(strict.verdict.source, "--tolerance");
  const Report decades = check(d.path / "pred.csv", "contact_area_vs_pressure", r, 0.0129, "max_abs");
  EXPECT_TRUE(decades.verdict.pass);  // log10(1.03) = 0.01284
  const Report decades2 = check(d.path / "pred.csv", "contact_area_vs_pressure", r, 0.0128, "max_abs");
  EXPECT_FALSE(decades2.verdict.pass);
}

TEST(CheckScoring, ShiftInLogSpaceAndPartialOverlap) {
  TempDir d;
  const fs::path r = write_reference(d, "contact_area_vs_pressure");
  const Synthetic s = synthetic();
  // Shift by 0.02 decades, on the upper half of the range only, decreasing order.
  std::string text = "pressure_MPa,contact_fraction_percent\n";
  for (std::size_t i = s.p.size(); i-- > 20;)
    text += num(s.p[i] / 1e6) + "," + num(100 * s.ar[i] * std::pow(10.0, 0.02)) + "\n";
  const Report rep = check(d.write("pred.csv", text), "contact_area_vs_pressure", r);
  EXPECT_NEAR(rep.metrics.max_abs, 0.02, 1e-12);
  EXPECT_NEAR(rep.metrics.rms_abs, 0.02, 1e-12);
  EXPECT_NEAR(rep.metrics.max_rel, std::pow(10.0, 0.02) - 1, 1e-12);
  EXPECT_NEAR(rep.metrics.x_lo, s.p[20], 1e-9 * s.p[20]);
  EXPECT_NEAR(rep.metrics.x_hi, s.p.back(), 1e-9 * s.p.back());
  EXPECT_NEAR(rep.metrics.coverage, 0.5, 1e-12);
  // Reversed into increasing order, converted from MPa and percent.
  EXPECT_NEAR(rep.prediction.x.front(), s.p[20], 1e-9 * s.p[20]);
  EXPECT_LT(rep.prediction.x.front(), rep.prediction.x.back());
  EXPECT_NEAR(rep.prediction.y.front(), s.ar[20] * std::pow(10.0, 0.02), 1e-12);
}

TEST(CheckScoring, AdditiveOffsetOnLinearAxis) {
  TempDir d;
  const fs::path r = write_reference(d, "mean_gap_vs_pressure");
  const Synthetic s = synthetic();
  const double c = 0.02e-6;  // 20 nm
  std::string text = "pressure_Pa,mean_gap_um\n";
  for (std::size_t i = 0; i < s.p.size(); ++i) text += num(s.p[i]) + "," + num((s.gap[i] + c) * 1e6) + "\n";
  const Report rep = check(d.write("pred.csv", text), "mean_gap_vs_pressure", r);
  double gmax = 0;
  for (double g : s.gap) gmax = std::max(gmax, std::abs(g));
  EXPECT_NEAR(rep.metrics.max_abs, c, 1e-12 * c + 1e-18);  // metres
  EXPECT_NEAR(rep.metrics.rms_abs, c, 1e-9 * c);
  EXPECT_NEAR(rep.metrics.max_rel, c / gmax, 1e-9);
  EXPECT_TRUE(rep.verdict.pass);  // 0.02/1.5 = 1.3% < 5%
  // Ten times the offset: 13% > 5%.
  std::string bad = "pressure_Pa,mean_gap_m\n";
  for (std::size_t i = 0; i < s.p.size(); ++i) bad += num(s.p[i]) + "," + num(s.gap[i] + 10 * c) + "\n";
  EXPECT_FALSE(check(d.write("bad.csv", bad), "mean_gap_vs_pressure", r).verdict.pass);
}

TEST(CheckScoring, PowerLawIsInterpolatedInLogLog) {
  // A power law is a straight line in log-log: a prediction sampled elsewhere is scored
  // exactly, which fails if either curve were interpolated on linear axes.
  TempDir d;
  const Synthetic s = synthetic();
  ref::RunProvenance how{"", "synthetic", "none", "none", "2000-01-01T00:00:00Z", ""};
  std::vector<double> ar;
  for (double p : s.p) ar.push_back(3.0 * std::pow(p / kChallengeEstar, 0.9));
  ref::write_curve((d.path / "ref.csv").string(),
                   ref::make_run_curve("ref", "contact_area_vs_pressure", "", how,
                                       {{"pressure_Pa", "Pa", "", s.p}, {"contact_fraction", "1", "", ar}},
                                       "pressure_Pa", "contact_fraction", "log-log", "exact", 0.05));
  std::string text = "pressure_Pa,contact_fraction\n";
  for (double p = 1.7e3; p < 1.9e6; p *= 3.1) text += num(p) + "," + num(1.04 * 3.0 * std::pow(p / kChallengeEstar, 0.9)) + "\n";
  const Report rep = check(d.write("pred.csv", text), "contact_area_vs_pressure", d.path / "ref.csv");
  EXPECT_NEAR(rep.metrics.max_rel, 0.04, 1e-10);
  EXPECT_NEAR(rep.metrics.rms_rel, 0.04, 1e-10);
}

TEST(CheckScoring, DefaultToleranceOfTheQuantity) {
  TempDir d;
  const fs::path r = write_reference(d, "contact_area_vs_pressure", std::nullopt);
  const Synthetic s = synthetic();
  std::string text = "pressure_Pa,contact_fraction\n";
  for (std::size_t i = 0; i < s.p.size(); ++i) text += num(s.p[i]) + "," + num(s.ar[i]) + "\n";
  const Report rep = check(d.write("pred.csv", text), "contact_area_vs_pressure", r);
  EXPECT_EQ(rep.verdict.source, "default for contact_area_vs_pressure");
  EXPECT_EQ(rep.verdict.tolerance, quantity("contact_area_vs_pressure").tolerance);
  EXPECT_LT(rep.metrics.max_rel, 1e-11);  // the reference's 13-digit rounding only
  EXPECT_TRUE(rep.verdict.pass);
}

TEST(CheckScoring, ExtraColumnsAreIgnoredAndNoted) {
  TempDir d;
  const fs::path r = write_reference(d, "contact_area_vs_pressure");
  const Synthetic s = synthetic();
  std::string text = "pressure_Pa,mean_gap_m,contact_fraction\n";
  for (std::size_t i = 0; i < s.p.size(); ++i) text += num(s.p[i]) + ",1e-6," + num(s.ar[i]) + "\n";
  const Report rep = check(d.write("pred.csv", text), "contact_area_vs_pressure", r);
  ASSERT_EQ(rep.prediction.ignored_columns.size(), 1u);
  EXPECT_EQ(rep.prediction.ignored_columns[0], "mean_gap_m");
  const std::string json = report_json(rep);
  EXPECT_NE(json.find("\"verdict\""), std::string::npos);
  EXPECT_NE(json.find("columns not used: mean_gap_m"), std::string::npos);
}

// The layouts of the challenge's submissions: one curve written with commas, with
// semicolons, with spaces (reduced units, rows running down), with tabs and no header,
// and with spaces, no header and an extra column, all score exactly the same; a file
// without a header and without --columns, or with --columns of the wrong count, is bad
// input that says what to pass.
TEST(CheckLayouts, SubmissionLayoutsScoreTheSame) {
  TempDir d;
  const fs::path r = write_reference(d, "contact_area_vs_pressure");
  const Synthetic s = synthetic();
  auto rows = [&](const std::string& sep, bool reduced, bool down, const std::string& extra) {
    std::string t;
    for (std::size_t k = 0; k < s.p.size(); k += 2) {
      const std::size_t i = down ? s.p.size() - 1 - k : k;
      t += num(reduced ? s.p[i] / kChallengeEstar : s.p[i]) + sep + num(s.ar[i] * 1.02) + extra + "\n";
    }
    return t;
  };
  auto score = [&](const std::string& name, const std::string& text, std::vector<std::string> columns = {}) {
    Options o;
    o.prediction = d.write(name, text).string();
    o.quantity = "contact_area_vs_pressure";
    o.reference_file = r.string();
    o.columns = std::move(columns);
    return run_check(o);
  };
  const Report base = score("comma.csv", "# commas\npressure_Pa,contact_fraction\n" + rows(",", false, false, ""));
  // 2 % on every second point, plus the log-log interpolation's curvature in between
  // (under 1 %, as in MultiplicativePerturbationOnLogAxis).
  EXPECT_NEAR(base.metrics.max_rel, 0.02, 1e-2);
  EXPECT_GE(base.metrics.max_rel, 0.02 - 1e-12);
  const std::vector<Report> same = {
      score("semicolon.csv", "pressure_Pa;contact_fraction\n" + rows(";", false, false, "")),
      score("spaces.txt", "# reduced, rows running down\n  p_over_Estar    contact_fraction\n" + rows("   ", true, true, "")),
      score("tabs.dat", rows("\t", false, false, ""), {"pressure_Pa", "contact_fraction"}),
      score("extra.dat", rows(" ", true, false, " 7"), {"p_over_Estar", "contact_fraction", "patches"}),
  };
  for (const Report& rep : same) {
    SCOPED_TRACE(rep.prediction.rows);
    EXPECT_EQ(rep.prediction.rows, base.prediction.rows);
    EXPECT_NEAR(rep.metrics.max_rel, base.metrics.max_rel, 1e-12);
    EXPECT_NEAR(rep.metrics.rms_rel, base.metrics.rms_rel, 1e-12);
    EXPECT_EQ(rep.verdict.pass, base.verdict.pass);
  }
  try {
    score("headerless.dat", rows(" ", false, false, ""));
    ADD_FAILURE() << "a headerless file without --columns was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("name its columns with --columns"), std::string::npos) << e.what();
  }
  try {
    score("count.dat", rows(" ", false, false, ""), {"pressure_Pa", "contact_fraction", "patches"});
    ADD_FAILURE() << "--columns of the wrong count was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--columns names 3 columns, the file's rows have 2 whitespace-separated values"),
              std::string::npos) << e.what();
  }
}

// A reference with an error band ("# band:"): a_r ± 5 % of a_r. On the log y axis the
// band spans log10(0.95 a_r) .. log10(1.05 a_r); a prediction 3 % above lies at
// log10(1.03)/log10(1.05) = 0.606 bands (PASS), one 10 % above at log10(1.10)/log10(1.05)
// = 1.953 bands (FAIL, "by up to 1.95 times"), one 10 % below at
// log10(1/0.9)/log10(1/0.95) = 2.054 bands. --tolerance brings back the plain metric.
TEST(CheckBand, ScoredInUnitsOfTheReferencesBand) {
  TempDir d;
  const Synthetic s = synthetic();
  const ref::RunProvenance how = synthetic_provenance();
  std::vector<double> err;
  for (double a : s.ar) err.push_back(0.05 * a);
  ref::Curve c = ref::make_run_curve("contact_area_vs_pressure", "contact_area_vs_pressure", "synthetic", how,
                                     {{"pressure_Pa", "Pa", "", s.p},
                                      {"contact_fraction", "1", "", s.ar},
                                      {"contact_fraction_err", "1", "half-width", err}},
                                     "pressure_Pa", "contact_fraction", "log-log", "5 % band (synthetic)", 0.5,
                                     "max_rel");
  c.band = "contact_fraction_err";
  const fs::path r = d.path / "banded.csv";
  ref::write_curve(r.string(), c);
  EXPECT_EQ(ref::read_curve(r.string()).band, "contact_fraction_err");
  auto pred = [&](double factor) {
    std::string text = "pressure_Pa,contact_fraction\n";
    for (std::size_t i = 0; i < s.p.size(); ++i) text += num(s.p[i]) + "," + num(s.ar[i] * factor) + "\n";
    return d.write("pred.csv", text);
  };
  const Report in = check(pred(1.03), "contact_area_vs_pressure", r);
  ASSERT_TRUE(in.metrics.has_band);
  EXPECT_NEAR(in.metrics.max_band, std::log10(1.03) / std::log10(1.05), 1e-9);
  EXPECT_EQ(in.verdict.metric, "max_band");
  EXPECT_TRUE(in.verdict.pass);
  EXPECT_NE(report_text(in).find("inside the reference's error band"), std::string::npos) << report_text(in);
  const Report out = check(pred(1.10), "contact_area_vs_pressure", r);
  EXPECT_NEAR(out.metrics.max_band, std::log10(1.10) / std::log10(1.05), 1e-9);
  EXPECT_FALSE(out.verdict.pass);
  EXPECT_NE(report_text(out).find("outside the reference's error band by up to 1.95"), std::string::npos)
      << report_text(out);
  EXPECT_NE(report_json(out).find("\"max_band\""), std::string::npos);
  const Report below = check(pred(0.90), "contact_area_vs_pressure", r);
  EXPECT_NEAR(below.metrics.max_band, std::log10(1 / 0.90) / std::log10(1 / 0.95), 1e-9);
  // An explicit tolerance scores the plain metric (max_rel 0.10 against 0.2: a pass).
  const Report plain = check(pred(1.10), "contact_area_vs_pressure", r, 0.2);
  EXPECT_EQ(plain.verdict.metric, "max_rel");
  EXPECT_TRUE(plain.verdict.pass);
  // A band that is not a half-width > 0 in y's unit is refused, naming the column.
  std::string text = ref::format_curve(c);
  const auto bad = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    t.replace(at, from.size(), to);
    return d.write("bad.csv", t);
  };
  EXPECT_THROW(ref::read_curve(bad("# band: contact_fraction_err", "# band: nonexistent").string()), InputError);
  EXPECT_THROW(ref::read_curve(bad("# unit.contact_fraction_err: 1", "# unit.contact_fraction_err: percent").string()),
               InputError);
  c.columns[2].values[3] = -1e-3;
  EXPECT_THROW(ref::format_curve(c), std::invalid_argument);
}

TEST(CheckQuantities, EveryChallengeItemHasAQuantity) {
  std::vector<int> items;
  for (const auto& q : quantities()) items.push_back(q.item);
  for (int i = 1; i <= 9; ++i) EXPECT_NE(std::find(items.begin(), items.end(), i), items.end()) << "item " << i;
  // The representations the problem definition asks for.
  EXPECT_TRUE(quantity("gap_distribution").rep.log_y);
  EXPECT_FALSE(quantity("stress_distribution").rep.log_x);
  EXPECT_TRUE(quantity("stress_distribution").rep.log_y);
  EXPECT_TRUE(quantity("contact_area_vs_tabor").rep.log_x);
  EXPECT_TRUE(quantity("mean_gap_vs_tabor").rep.log_x);
  EXPECT_TRUE(quantity("mean_gap_vs_pressure").rep.log_x);
  EXPECT_THROW(quantity("contact_area"), InputError);
}

// ------------------------------------------------------------------------ malformed input
struct Bad {
  std::string what, text, expect;  // expect: a fragment the message must contain
};

std::vector<Bad> malformed() {
  return {
      {"empty file", "", "the file is empty"},
      {"comments only", "# nothing here\n", "no header row"},
      {"header only", "pressure_Pa,contact_fraction\n", "0 data rows"},
      {"one data row", "pressure_Pa,contact_fraction\n1e4,0.001\n", "1 data row"},
      {"no header row", "1e4,0.001\n2e4,0.002\n", ":1: the file has no header row (this line is 2 numbers); name its columns with --columns"},
      {"one column", "pressure_Pa\n1e4\n2e4\n", "names one column"},
      {"separators mixed", "pressure_Pa contact_fraction\n1e4,0.001\n2e4,0.002\n", ":2: expected 2 whitespace-separated values"},
      {"wrong columns", "pressure_Pa,mean_gap_m\n1e4,1e-6\n2e4,0.9e-6\n", "no column for the relative contact area"},
      {"missing abscissa", "load_N,contact_fraction\n1e-3,0.001\n2e-3,0.002\n", "no column for the mean pressure"},
      {"unknown unit", "pressure_psi,contact_fraction\n1,0.001\n2,0.002\n", "unknown unit 'psi'"},
      {"two abscissae", "pressure_Pa,p_MPa,contact_fraction\n1e4,0.01,0.001\n2e4,0.02,0.002\n", "both give the mean pressure"},
      {"NaN", "pressure_Pa,contact_fraction\n1e4,0.001\n2e4,nan\n3e4,0.003\n", ":3: column 2 ('contact_fraction'): 'nan' is not a finite"},
      {"infinity", "pressure_Pa,contact_fraction\n1e4,0.001\ninf,0.002\n", ":3: column 1 ('pressure_Pa'): 'inf' is not a finite"},
      {"overflow", "pressure_Pa,contact_fraction\n1e4,0.001\n1e999,0.002\n", "not a finite"},
      {"text", "pressure_Pa,contact_fraction\n1e4,0.001\n2e4,abc\n", "'abc' is not a number"},
      {"empty field", "pressure_Pa,contact_fraction\n1e4,\n2e4,0.002\n", "empty field"},
      {"ragged row", "pressure_Pa,contact_fraction\n1e4,0.001\n2e4,0.002,7\n", "expected 2 comma-separated values"},
      {"non-monotonic", "pressure_Pa,contact_fraction\n1e4,0.001\n3e4,0.003\n2e4,0.002\n",
       ":4: column 1 ('pressure_Pa'): 20000 after 30000 (line 3)"},
      {"duplicate abscissa", "pressure_Pa,contact_fraction\n1e4,0.001\n1e4,0.002\n", ":3: column 1 ('pressure_Pa'): 10000 repeats the value of line 2: duplicate mean pressure"},
      {"duplicate names", "pressure_Pa,pressure_Pa\n1,2\n3,4\n", "appears twice"},
      {"no overlap", "pressure_Pa,contact_fraction\n1e7,0.5\n2e7,0.6\n", "no overlap"},
      {"nothing positive on log axes", "pressure_Pa,contact_fraction\n1e4,0\n2e4,-1\n", "positive on the log axes"},
      // Found with tests/fuzz/fuzz_check_csv: finite in the file, not in SI or in the
      // errors; these were scored as NaN (a FAIL with "NaN" in check.json, and no figure).
      {"overflow in SI", "pressure_GPa,contact_fraction\n1e4,0.001\n1e300,0.002\n",
       ":3: column 1 ('pressure_GPa'): 1e+300 is too large to convert to SI units (Pa)"},
      {"errors overflow", "pressure_Pa,contact_fraction\n1e4,1e308\n2e4,1e308\n", "overflow a double"},
  };
}

TEST(CheckMalformed, EachClassIsRejectedWithAClearMessage) {
  TempDir d;
  const fs::path r = write_reference(d, "contact_area_vs_pressure");
  for (const auto& b : malformed()) {
    SCOPED_TRACE(b.what);
    const fs::path f = d.write("bad.csv", b.text);
    try {
      check(f, "contact_area_vs_pressure", r);
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(b.expect), std::string::npos) << msg;
      EXPECT_NE(msg.find(f.string()), std::string::npos) << "message does not name the file: " << msg;
    }
  }
}

TEST(CheckMalformed, ArgumentsAndReferences) {
  TempDir d;
  const fs::path r = write_reference(d, "contact_area_vs_pressure");
  const fs::path good = d.write("good.csv", "pressure_Pa,contact_fraction\n1e4,0.001\n2e4,0.002\n");
  auto message = [&](Options o) {
    try {
      run_check(o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  Options o;
  o.prediction = good.string();
  o.quantity = "contact_area_vs_pressure";
  o.reference_file = r.string();
  Options x = o;
  x.prediction = (d.path / "missing.csv").string();
  EXPECT_NE(message(x).find("missing.csv: no such file"), std::string::npos);
  x = o;
  x.quantity = "area";
  EXPECT_NE(message(x).find("unknown quantity 'area'"), std::string::npos);
  x = o;
  x.quantity = "mean_gap_vs_pressure";  // the reference is for another quantity
  EXPECT_NE(message(x).find("is for quantity 'contact_area_vs_pressure'"), std::string::npos);
  x = o;
  x.metric = "median";
  EXPECT_NE(message(x).find("unknown metric 'median'"), std::string::npos);
  x = o;
  x.reference_file.clear();
  setenv("CMC_REFERENCE_DIR", d.path.c_str(), 1);  // no challenge/ folder there
  EXPECT_NE(message(x).find("no stored reference for quantity 'contact_area_vs_pressure' yet"), std::string::npos);
  EXPECT_NE(message(x).find("--reference"), std::string::npos);
  // --adhesionless reads challenge/adhesionless/Q.csv of the same folder, and only that.
  x.adhesionless = true;
  EXPECT_NE(message(x).find("no stored adhesionless reference for quantity 'contact_area_vs_pressure' yet"),
            std::string::npos);
  fs::create_directories(d.path / "challenge" / "adhesionless");
  fs::copy_file(r, d.path / "challenge" / "adhesionless" / "contact_area_vs_pressure.csv");
  EXPECT_EQ(message(x), "(accepted)");
  EXPECT_EQ(run_check(x).reference_file, (d.path / "challenge" / "adhesionless" / "contact_area_vs_pressure.csv").string());
  x.quantity = "contact_area_vs_tabor";
  EXPECT_NE(message(x).find("the Tabor-parameter quantities have none"), std::string::npos);
  x = o;  // with an explicit reference file, --adhesionless would be ignored: refused instead
  x.adhesionless = true;
  EXPECT_NE(message(x).find("--adhesionless chooses the stored adhesionless reference"), std::string::npos);
  unsetenv("CMC_REFERENCE_DIR");
  // A reference that is not in the reference format.
  x = o;
  x.reference_file = good.string();
  EXPECT_NE(message(x).find("'# cmc-reference-csv: ...' is missing"), std::string::npos);
  // Generic comparison without a quantity needs a reference.
  x = o;
  x.quantity.clear();
  x.reference_file.clear();
  EXPECT_NE(message(x).find("--quantity"), std::string::npos);
}

// ------------------------------------------------------------------------ the command
// Runs the cmc program that sits beside this test binary; skips if there is none.
fs::path cmc_program() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const fs::path p = self.parent_path() / "cmc";
  return fs::exists(p) ? p : fs::path{};
}

int run(const std::string& cmd) {
  const int s = std::system((cmd + " >/dev/null 2>&1").c_str());
  return WIFEXITED(s) ? WEXITSTATUS(s) : -1;
}

TEST(CheckCommand, MalformedInputExitsTwoAndWritesNothing) {
  const fs::path cmc = cmc_program();
  if (cmc.empty()) GTEST_SKIP() << "no cmc program beside the test binary";
  TempDir d;
  const fs::path r = write_reference(d, "contact_area_vs_pressure");
  for (const auto& b : malformed()) {
    SCOPED_TRACE(b.what);
    const fs::path f = d.write("bad.csv", b.text);
    const fs::path out = d.path / "out";
    EXPECT_EQ(run(cmc.string() + " check " + f.string() + " --quantity contact_area_vs_pressure --reference " +
                  r.string() + " --out " + out.string()),
              2);
    EXPECT_FALSE(fs::exists(out)) << "something was written";
  }
  // Missing default reference: exit 2, nothing written.
  const fs::path good = d.write("good.csv", "pressure_Pa,contact_fraction\n1e4,0.001\n2e4,0.002\n");
  EXPECT_EQ(run("CMC_REFERENCE_DIR=" + d.path.string() + " " + cmc.string() + " check " + good.string() +
                " --quantity contact_area_vs_pressure --out " + (d.path / "out").string()),
            2);
  EXPECT_FALSE(fs::exists(d.path / "out"));
}

TEST(CheckCommand, WritesCheckJsonAndExitCodeFollowsVerdict) {
  const fs::path cmc = cmc_program();
  if (cmc.empty()) GTEST_SKIP() << "no cmc program beside the test binary";
  TempDir d;
  const fs::path r = write_reference(d, "contact_area_vs_pressure");
  const Synthetic s = synthetic();
  std::string ok = "pressure_Pa,contact_fraction\n", bad = ok;
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    ok += num(s.p[i]) + "," + num(s.ar[i] * 1.01) + "\n";
    bad += num(s.p[i]) + "," + num(s.ar[i] * 1.2) + "\n";
  }
  const std::string base = " check --quantity contact_area_vs_pressure --reference " + r.string() + " ";
  // Without python: the comparison still succeeds and check.json is written.
  EXPECT_EQ(run("CMC_PYTHON=/nonexistent/python3 " + cmc.string() + base + d.write("ok.csv", ok).string() + " --out " +
                (d.path / "a").string()),
            0);
  EXPECT_TRUE(fs::exists(d.path / "a" / "check.json"));
  EXPECT_FALSE(fs::exists(d.path / "a" / "check.png"));
  EXPECT_EQ(run("CMC_PYTHON=/nonexistent/python3 " + cmc.string() + base + d.write("bad.csv", bad).string() +
                " --out " + (d.path / "b").string()),
            5);
  EXPECT_TRUE(fs::exists(d.path / "b" / "check.json"));
  // With /usr/bin/python3 and matplotlib: the figure too.
  if (run("/usr/bin/python3 -c 'import matplotlib, numpy'") == 0) {
    EXPECT_EQ(run(cmc.string() + base + (d.path / "ok.csv").string() + " --out " + (d.path / "c").string()), 0);
    EXPECT_TRUE(fs::exists(d.path / "c" / "check.png"));
  }
}

}  // namespace
