// The prediction checker behind `cmc check`: which challenge quantities can be checked,
// which column names and units a submitted CSV may use, and how a curve is scored
// against a reference curve.
//
// Scoring (documented for users in reference/README.md):
//   1. Both curves are converted to SI and transformed into the representation the
//      challenge asks for: X = log10(x) on a log axis, else x; likewise Y.
//      Points that are <= 0 on a log axis are left out (and counted). A prediction row
//      with y <= 0 on a log y axis inside the reference's range is a wrong prediction:
//      the verdict is a fail naming its lines (a row with x <= 0 on a log x axis lies
//      outside every reference's range and is only left out).
//   2. Common range: [max(first X), min(last X)] of the two curves (error if empty).
//   3. Evaluation points: every abscissa of either curve inside the common range, plus
//      its ends; both curves are interpolated piecewise-linearly in (X, Y).
//   4. d = Y_pred - Y_ref at each point.
//        abs error: |d|, in decades on a log y axis, in the SI unit on a linear one;
//        rel error: |10^d - 1| = |y_pred/y_ref - 1| on a log y axis;
//                   |d| / max|y_ref| (over the evaluation points) on a linear one.
//      max_* is the largest over the points; rms_* is sqrt(integral of e^2 dX / range),
//      trapezoidal in X, so it does not depend on how densely either curve is sampled.
//   5. Verdict: pass when the chosen metric (max_abs, rms_abs, max_rel, rms_rel) is at
//      most the tolerance. Tolerance from --tolerance, else the reference file's
//      "# tolerance:" line, else the quantity's default below.
//      A reference with an error band ("# band: <column>", the half-width e of y at
//      each point) is scored against it instead, unless --tolerance or --metric is
//      given: at each evaluation point the band is interpolated like y (in the
//      representation: on a log y axis it spans log10(y - e) .. log10(y + e)), and
//      max_band = the largest |d| over the band's half-width on d's side. Pass when
//      max_band <= 1 (inside the band); otherwise it says by how much, in bands.
//   6. Coverage: the common range must be at least min_coverage of the reference's range
//      on the abscissa, in the representation (from --min-coverage, else the reference
//      file's "# min_coverage:" line, else kDefaultMinCoverage); otherwise the verdict is
//      a fail whatever the errors, saying what the prediction covers and what is needed.
//
// The prediction is streamed (row by row; memory bounded by the reference, not by the
// submission) and check.json echoes at most kMaxEchoedRows of its rows and of the
// evaluation points, evenly sampled, saying so; the metrics use every one.
#pragma once

#include "References.hpp"

#include <optional>
#include <string>
#include <vector>

namespace cmc::check {

using reference::InputError;
using reference::Representation;
using reference::Table;

// Physical dimension of an axis; each has a fixed list of unit suffixes (see units()).
enum class Dim { None, Fraction, Pressure, Length, Area, InvLength, InvPressure, InvArea, StressSpectrum };

struct UnitChoice {
  std::string suffix;  // appended to the base name with '_' ("" = no suffix)
  double to_si;        // SI value = file value * to_si
  std::string meaning;
};
const std::vector<UnitChoice>& units(Dim d);
std::string si_unit(Dim d);  // "Pa", "m", "1/m", ...

// Challenge units used by the reduced suffixes: E* g = 25 MPa (g = rms gradient = 1),
// L = 0.1 mm (problem definition, "Summary of default parameters").
inline constexpr double kChallengeEstar = 25e6;  // Pa
inline constexpr double kChallengeL = 1e-4;      // m

// What check.json echoes of a prediction and of the evaluation points, at most.
inline constexpr std::size_t kMaxEchoedRows = 1000;
// The fraction of the reference's range (on the abscissa, in the representation) a
// prediction must cover, unless the reference or --min-coverage says otherwise.
inline constexpr double kDefaultMinCoverage = 0.5;

struct AxisSpec {
  std::string label;               // "mean pressure"
  std::vector<std::string> bases;  // accepted column-name stems, first = preferred
  Dim dim = Dim::None;
};

struct QuantitySpec {
  std::string id;     // "contact_area_vs_pressure"
  std::string title;  // "Contact area vs pressure"
  int item = 0;       // number in the problem definition's list (0: not a challenge item)
  AxisSpec x, y;
  Representation rep;
  double tolerance = 0.05;
  std::string metric = "max_rel";
  double min_coverage = kDefaultMinCoverage;
};

const std::vector<QuantitySpec>& quantities();
// Throws InputError naming the known quantities.
const QuantitySpec& quantity(const std::string& id);
// "log-log" etc.
std::string representation_name(Representation r);

// A curve in SI units, strictly increasing in x.
struct XY {
  std::string file;
  std::string x_column, y_column;  // as in the file
  double x_to_si = 1, y_to_si = 1;
  std::vector<double> x, y;
  std::vector<double> band;  // the reference's uncertainty of y (half-width, SI), or empty
  std::vector<int> line;  // file line of each point
  std::vector<std::string> ignored_columns;
  // A streamed prediction holds a sample of its rows in x, y, line: every echo_stride-th
  // row and the last, of `rows` (x_range, y_range: over all rows, SI). Otherwise every row.
  std::size_t rows = 0, echo_stride = 1;
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;
};

// Picks the abscissa and ordinate columns of `spec` from a table (see QuantitySpec),
// converts them to SI, and checks that x is strictly monotonic (a decreasing x is
// reversed). Throws InputError naming the file, line/column and what was expected.
// band_column: also read that column as the uncertainty of y (same unit as y).
XY extract(const Table& t, const QuantitySpec& spec, const std::string& band_column = "");

// A spec for comparing two files column by column without unit conversion: the columns
// named x and y (exact names), in the given representation (generic `cmc check
// --reference FILE` without --quantity).
QuantitySpec generic_spec(const std::string& quantity, const std::string& x, const std::string& y,
                          Representation rep, double tolerance, const std::string& metric);

// Prediction rows whose y is <= 0 on a log y axis at an abscissa inside the reference's
// range: their number and the file lines of the first five. Any makes the verdict a fail.
struct NonPositive {
  std::size_t count = 0;
  std::vector<int> lines;
};

struct Metrics {
  double max_abs = 0, rms_abs = 0, max_rel = 0, rms_rel = 0;
  double x_lo = 0, x_hi = 0;     // common range, SI
  double x_at_max_abs = 0;       // where |d| is largest, SI
  double rel_scale = 0;          // max|y_ref| used for rel on a linear y axis (SI); 0 on a log one
  double coverage = 0;           // common range / reference range, in representation
  double ref_lo = 0, ref_hi = 0;  // the reference's range (its points on the log axes), SI
  std::size_t points = 0;        // evaluation points
  std::size_t excluded_prediction = 0, excluded_reference = 0;  // <= 0 on a log axis
  NonPositive nonpositive;  // prediction rows with y <= 0 on a log y axis inside the reference's range
  std::vector<double> eval_x, eval_pred, eval_ref;  // SI; a sample of the points when eval_echo_stride > 1
  std::vector<double> eval_lo, eval_hi;              // the reference's band there (SI), when it has one
  std::size_t eval_echo_stride = 1;
  // Against a reference with an error band: the largest |d| in units of the band's
  // half-width on d's side (in the representation), and where. <= 1: inside the band.
  bool has_band = false;
  double max_band = 0, x_at_max_band = 0;
  double get(const std::string& metric) const;  // throws InputError for an unknown name
};

// Throws InputError when fewer than two points of a curve remain on the log axes or the
// curves do not overlap. Keeps every evaluation point.
Metrics compare(const XY& prediction, const XY& ref, Representation rep);

struct Verdict {
  double tolerance = 0;
  std::string metric, source;  // source: "--tolerance", "reference file", "default for <quantity>"
  double value = 0;
  bool pass = false;  // the metric within the tolerance, the range covered, no y <= 0 on a log y axis
  // Coverage: the fraction of the reference's range required, where that came from,
  // and whether the prediction covers it (a fail otherwise, with `reason`).
  double min_coverage = 0;
  std::string coverage_source, reason;  // reason: why it fails besides the metric (coverage, y <= 0)
  bool covered = true;
};
Verdict verdict(const Metrics& m, double tolerance, const std::string& metric, const std::string& source);

// Everything `cmc check` reports, as JSON (check.json; read by reports/plot_check.py).
struct Report {
  QuantitySpec spec;
  std::string prediction_file, reference_file, reference_name, reference_source;
  std::string against;  // which question the stored reference answers (surface, ensemble, realisation); "" for --reference
  std::string band_words;  // how the reference's band was made (its estimated_error), for the verdict
  XY prediction, ref;
  Metrics metrics;
  Verdict verdict;
  std::vector<std::string> notes;
};
std::string report_json(const Report& r);
// The human-readable summary printed by `cmc check`.
std::string report_text(const Report& r);

// Runs the whole check without writing anything (the command writes check.json and the
// figure afterwards). `reference_file` empty: the stored challenge reference for the
// quantity (reference/challenge/<quantity>.csv), an InputError if it does not exist.
struct Options {
  std::string prediction, quantity, reference_file, x, y, metric;
  std::optional<double> tolerance, min_coverage;  // min_coverage in [0, 1]
  std::vector<std::string> columns;  // names for the prediction's columns (--columns)
  bool adhesionless = false;  // --adhesionless: the stored adhesionless reference of the quantity
  // --against: which stored reference of a challenge quantity: "surface" (cmc's own surface,
  // reference/challenge/), "ensemble" (the mean over surfaces of the spectrum, .../ensemble/) or
  // "realisation" (any one surface of it, .../realisation/); "" is "realisation" where that
  // reference exists, else "surface".
  std::string against;
};
Report run_check(const Options& o);

// Path of the stored reference for a challenge quantity.
// adhesionless: the challenge's surface under the hard wall alone (reference/challenge/adhesionless/).
// against: "surface" (or ""), "ensemble" or "realisation" (Options::against).
std::string default_reference_path(const std::string& quantity, bool adhesionless = false,
                                   const std::string& against = "surface");

}  // namespace cmc::check
