// The prediction checker (see Check.hpp and reference/README.md).
#include "Check.hpp"

#include "cmc/output/Writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <toml++/toml.h>

namespace cmc::check {

namespace {

std::string fmt(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

std::string col_ref(const Table& t, int k) {
  return "column " + std::to_string(k + 1) + " ('" + t.columns[std::size_t(k)] + "')";
}

// Accepted header names for an axis, for messages: "pressure_Pa, pressure_kPa, ...".
std::string accepted_names(const AxisSpec& a, bool all_bases) {
  std::string s;
  const std::size_t nb = all_bases ? a.bases.size() : 1;
  for (std::size_t b = 0; b < nb; ++b)
    for (const auto& u : units(a.dim)) s += (s.empty() ? "" : ", ") + a.bases[b] + (u.suffix.empty() ? "" : "_" + u.suffix);
  return s;
}

struct Match {
  int column = -1;
  const UnitChoice* unit = nullptr;
};

// Does column name `name` give axis `a`? Returns the unit, or sets near_miss when the
// name starts with a base but the unit suffix is unknown.
const UnitChoice* match_name(const std::string& name, const AxisSpec& a, std::string* near_miss) {
  for (const auto& base : a.bases) {
    for (const auto& u : units(a.dim)) {
      const std::string full = u.suffix.empty() ? base : base + "_" + u.suffix;
      if (name == full) return &u;
    }
  }
  for (const auto& base : a.bases)
    if (name.size() > base.size() + 1 && name.compare(0, base.size() + 1, base + "_") == 0 && near_miss &&
        near_miss->empty())
      *near_miss = name.substr(base.size() + 1);
  return nullptr;
}

Match find_axis(const Table& t, const AxisSpec& a, int exclude) {
  Match m;
  for (int k = 0; k < int(t.columns.size()); ++k) {
    if (k == exclude) continue;
    std::string miss;
    const UnitChoice* u = match_name(t.columns[std::size_t(k)], a, &miss);
    if (u) {
      if (m.column >= 0)
        throw InputError(t.file + ":" + std::to_string(t.header_line) + ": " + col_ref(t, m.column) + " and " +
                         col_ref(t, k) + " both give the " + a.label + "; keep one");
      m = {k, u};
    }
  }
  if (m.column >= 0) return m;
  // Not found: name the closest problem.
  for (int k = 0; k < int(t.columns.size()); ++k) {
    if (k == exclude) continue;
    std::string miss;
    match_name(t.columns[std::size_t(k)], a, &miss);
    if (!miss.empty())
      throw InputError(t.file + ":" + std::to_string(t.header_line) + ": " + col_ref(t, k) + ": unknown unit '" +
                       miss + "' for the " + a.label + " (SI unit " + si_unit(a.dim) + "); accepted column names: " +
                       accepted_names(a, false) + " (stems: " + [&] {
                         std::string s;
                         for (const auto& b : a.bases) s += (s.empty() ? "" : ", ") + b;
                         return s;
                       }() + ")");
  }
  std::string have;
  for (const auto& c : t.columns) have += (have.empty() ? "" : ", ") + c;
  throw InputError(t.file + ":" + std::to_string(t.header_line) + ": no column for the " + a.label +
                   "; expected one of: " + accepted_names(a, true) + " (the header row has: " + have + ")");
}

}  // namespace

// ============================================================================ units
const std::vector<UnitChoice>& units(Dim d) {
  static const std::vector<UnitChoice> none = {{"", 1.0, "dimensionless"}};
  static const std::vector<UnitChoice> fraction = {{"", 1.0, "fraction (0..1)"}, {"percent", 0.01, "percent"}};
  static const std::vector<UnitChoice> pressure = {
      {"Pa", 1.0, "Pa"}, {"kPa", 1e3, "kPa"}, {"MPa", 1e6, "MPa"}, {"GPa", 1e9, "GPa"},
      {"over_Estar", kChallengeEstar, "reduced: p/(E* g), E* g = 25 MPa"}};
  static const std::vector<UnitChoice> length = {{"m", 1.0, "m"},     {"mm", 1e-3, "mm"}, {"um", 1e-6, "micrometre"},
                                                 {"nm", 1e-9, "nm"},  {"over_L", kChallengeL, "reduced: in L = 0.1 mm"}};
  static const std::vector<UnitChoice> area = {{"m2", 1.0, "m^2"},      {"mm2", 1e-6, "mm^2"},
                                               {"um2", 1e-12, "um^2"},  {"nm2", 1e-18, "nm^2"},
                                               {"over_L2", kChallengeL * kChallengeL, "reduced: in L^2"}};
  static const std::vector<UnitChoice> inv_length = {{"per_m", 1.0, "1/m"},      {"per_mm", 1e3, "1/mm"},
                                                     {"per_um", 1e6, "1/um"},    {"per_nm", 1e9, "1/nm"},
                                                     {"times_L", 1 / kChallengeL, "reduced: times L"}};
  static const std::vector<UnitChoice> inv_pressure = {{"per_Pa", 1.0, "1/Pa"},
                                                       {"per_kPa", 1e-3, "1/kPa"},
                                                       {"per_MPa", 1e-6, "1/MPa"},
                                                       {"times_Estar", 1 / kChallengeEstar, "reduced: times E* g"}};
  static const std::vector<UnitChoice> inv_area = {{"per_m2", 1.0, "1/m^2"},
                                                   {"per_um2", 1e12, "1/um^2"},
                                                   {"per_nm2", 1e18, "1/nm^2"},
                                                   {"times_L2", 1 / (kChallengeL * kChallengeL), "reduced: times L^2"}};
  static const std::vector<UnitChoice> spectrum = {
      {"Pa2m2", 1.0, "Pa^2 m^2"},
      {"MPa2um2", 1.0, "MPa^2 um^2 (= Pa^2 m^2)"},
      {"over_Estar2L2", kChallengeEstar * kChallengeEstar * kChallengeL * kChallengeL, "reduced: in (E* g)^2 L^2"}};
  switch (d) {
    case Dim::None: return none;
    case Dim::Fraction: return fraction;
    case Dim::Pressure: return pressure;
    case Dim::Length: return length;
    case Dim::Area: return area;
    case Dim::InvLength: return inv_length;
    case Dim::InvPressure: return inv_pressure;
    case Dim::InvArea: return inv_area;
    case Dim::StressSpectrum: return spectrum;
  }
  return none;
}

std::string si_unit(Dim d) {
  switch (d) {
    case Dim::None: return "1";
    case Dim::Fraction: return "1";
    case Dim::Pressure: return "Pa";
    case Dim::Length: return "m";
    case Dim::Area: return "m^2";
    case Dim::InvLength: return "1/m";
    case Dim::InvPressure: return "1/Pa";
    case Dim::InvArea: return "1/m^2";
    case Dim::StressSpectrum: return "Pa^2 m^2";
  }
  return "1";
}

std::string representation_name(Representation r) {
  return std::string(r.log_x ? "log" : "lin") + "-" + (r.log_y ? "log" : "lin");
}

// ============================================================================ quantities
const std::vector<QuantitySpec>& quantities() {
  const AxisSpec pressure{"mean pressure", {"mean_pressure", "pressure", "p"}, Dim::Pressure};
  const AxisSpec fraction{"relative contact area", {"contact_fraction", "relative_contact_area", "a_r", "ar"},
                          Dim::Fraction};
  const AxisSpec mean_gap{"mean gap", {"mean_gap", "gap", "mean_separation", "u"}, Dim::Length};
  const AxisSpec tabor{"Tabor coefficient", {"tabor", "mu_T", "mu_t", "tabor_coefficient"}, Dim::None};
  const std::vector<std::string> density = {"density", "probability_density", "pdf", "P"};
  static const std::vector<QuantitySpec> q = {
      {"patch_size_distribution", "Distribution of contact patch size", 1,
       {"patch area", {"patch_area", "area", "A"}, Dim::Area},
       {"probability density of patch area", density, Dim::InvArea},
       {true, true}, 0.15, "rms_abs"},
      {"contact_area_vs_pressure", "Contact area as a function of pressure", 2, pressure, fraction, {true, true}, 0.05,
       "max_rel"},
      {"gap_distribution", "Gap distribution function", 3, {"gap", {"gap", "g", "separation"}, Dim::Length},
       {"probability density of the gap", density, Dim::InvLength}, {true, true}, 0.1, "rms_abs"},
      {"stress_distribution", "Interfacial stress distribution function", 4,
       {"interfacial stress", {"stress", "pressure", "p", "sigma"}, Dim::Pressure},
       {"probability density of the stress", density, Dim::InvPressure}, {false, true}, 0.1, "rms_abs"},
      {"stress_spectrum", "Interfacial stress spectrum", 5, {"wavenumber", {"q", "wavenumber"}, Dim::InvLength},
       {"stress spectrum", {"C", "spectrum", "psd", "C_stress"}, Dim::StressSpectrum}, {true, true}, 0.1, "rms_abs"},
      {"contact_area_vs_tabor", "Contact area as a function of the Tabor coefficient", 6, tabor, fraction,
       {true, false}, 0.05, "max_rel"},
      {"mean_gap_vs_tabor", "Mean gap as a function of the Tabor coefficient", 7, tabor, mean_gap, {true, false}, 0.05,
       "max_rel"},
      {"mean_gap_vs_pressure", "Mean gap as a function of pressure", 8, pressure, mean_gap, {true, false}, 0.05,
       "max_rel"},
      {"cross_section_gap", "Gap along the cross section x = 50 um", 9,
       {"position y along the cross section", {"y", "position", "s"}, Dim::Length},
       {"gap", {"gap", "g"}, Dim::Length}, {false, false}, 0.05, "rms_rel"},
      {"cross_section_pressure", "Stress along the cross section x = 50 um", 9,
       {"position y along the cross section", {"y", "position", "s"}, Dim::Length},
       {"interfacial stress", {"pressure", "stress", "p", "sigma"}, Dim::Pressure}, {false, false}, 0.1, "rms_rel"},
  };
  return q;
}

const QuantitySpec& quantity(const std::string& id) {
  for (const auto& q : quantities())
    if (q.id == id) return q;
  std::string known;
  for (const auto& q : quantities()) known += (known.empty() ? "" : ", ") + q.id;
  throw InputError("unknown quantity '" + id + "' (known: " + known + ")");
}

QuantitySpec generic_spec(const std::string& quantity, const std::string& x, const std::string& y, Representation rep,
                          double tolerance, const std::string& metric) {
  QuantitySpec s;
  s.id = quantity;
  s.title = quantity;
  s.x = {x, {x}, Dim::None};
  s.y = {y, {y}, Dim::None};
  s.rep = rep;
  s.tolerance = tolerance;
  s.metric = metric;
  return s;
}

std::string default_reference_path(const std::string& quantity) {
  return reference::default_reference_dir() + "/challenge/" + quantity + ".csv";
}

// ============================================================================ extraction
XY extract(const Table& t, const QuantitySpec& spec) {
  const Match mx = find_axis(t, spec.x, -1);
  const Match my = find_axis(t, spec.y, mx.column);
  XY c;
  c.file = t.file;
  c.x_column = t.columns[std::size_t(mx.column)];
  c.y_column = t.columns[std::size_t(my.column)];
  c.x_to_si = mx.unit->to_si;
  c.y_to_si = my.unit->to_si;
  for (int k = 0; k < int(t.columns.size()); ++k)
    if (k != mx.column && k != my.column) c.ignored_columns.push_back(t.columns[std::size_t(k)]);
  const auto& xs = t.data[std::size_t(mx.column)];
  const auto& ys = t.data[std::size_t(my.column)];
  if (xs.size() < 2)
    throw InputError(t.file + ": " + std::to_string(xs.size()) + " data row(s); a curve needs at least 2");
  // Direction from the ends, so a repeated or misplaced first value is named as such.
  const bool increasing = xs.back() >= xs.front();
  for (std::size_t i = 1; i < xs.size(); ++i) {
    const std::string here = t.file + ":" + std::to_string(t.row_line[i]) + ": " + col_ref(t, mx.column) + ": ";
    if (xs[i] == xs[i - 1])
      throw InputError(here + fmt(xs[i]) + " repeats the value of line " + std::to_string(t.row_line[i - 1]) +
                       ": duplicate " + spec.x.label + " (the abscissa must be strictly monotonic: one value of the " +
                       spec.y.label + " per abscissa)");
    const bool ok = increasing ? xs[i] > xs[i - 1] : xs[i] < xs[i - 1];
    if (!ok)
      throw InputError(here + fmt(xs[i]) + " after " + fmt(xs[i - 1]) + " (line " + std::to_string(t.row_line[i - 1]) +
                       "): the " + spec.x.label + " must be strictly " + (increasing ? "increasing" : "decreasing") +
                       " (non-monotonic abscissa; sort the rows)");
  }
  for (std::size_t i = 0; i < xs.size(); ++i) {
    c.x.push_back(xs[i] * c.x_to_si);
    c.y.push_back(ys[i] * c.y_to_si);
    c.line.push_back(t.row_line[i]);
    // A value finite in its unit can overflow in SI (1e300 per nm^2 is 1e318 per m^2).
    for (const auto& [v, k] : {std::pair{c.x.back(), mx.column}, std::pair{c.y.back(), my.column}})
      if (!std::isfinite(v))
        throw InputError(t.file + ":" + std::to_string(t.row_line[i]) + ": " + col_ref(t, k) + ": " +
                         fmt(t.data[std::size_t(k)][i]) + " is too large to convert to SI units (" +
                         si_unit(k == mx.column ? spec.x.dim : spec.y.dim) + ")");
  }
  if (!increasing) {
    std::reverse(c.x.begin(), c.x.end());
    std::reverse(c.y.begin(), c.y.end());
    std::reverse(c.line.begin(), c.line.end());
  }
  return c;
}

// ============================================================================ metrics
double Metrics::get(const std::string& metric) const {
  if (metric == "max_abs") return max_abs;
  if (metric == "rms_abs") return rms_abs;
  if (metric == "max_rel") return max_rel;
  if (metric == "rms_rel") return rms_rel;
  throw InputError("unknown metric '" + metric + "' (expected max_abs, rms_abs, max_rel or rms_rel)");
}

namespace {
struct Transformed {
  std::vector<double> X, Y;
  std::size_t excluded = 0;
};
Transformed transform(const XY& c, Representation rep, const std::string& what) {
  Transformed t;
  for (std::size_t i = 0; i < c.x.size(); ++i) {
    if ((rep.log_x && !(c.x[i] > 0)) || (rep.log_y && !(c.y[i] > 0))) {
      ++t.excluded;
      continue;
    }
    t.X.push_back(rep.log_x ? std::log10(c.x[i]) : c.x[i]);
    t.Y.push_back(rep.log_y ? std::log10(c.y[i]) : c.y[i]);
  }
  if (t.X.size() < 2)
    throw InputError(c.file + ": only " + std::to_string(t.X.size()) + " point(s) of the " + what +
                     " are positive on the log axes of the " + representation_name(rep) +
                     " representation; at least 2 are needed");
  return t;
}
// Piecewise-linear interpolation of (X, Y) at x, X strictly increasing, x inside.
double interp(const std::vector<double>& X, const std::vector<double>& Y, double x) {
  auto it = std::upper_bound(X.begin(), X.end(), x);
  if (it == X.begin()) return Y.front();
  if (it == X.end()) return Y.back();
  const std::size_t j = std::size_t(it - X.begin());
  const double t = (x - X[j - 1]) / (X[j] - X[j - 1]);
  return Y[j - 1] + t * (Y[j] - Y[j - 1]);
}
double from_rep(double v, bool log) { return log ? std::pow(10.0, v) : v; }
}  // namespace

Metrics compare(const XY& pred, const XY& ref, Representation rep) {
  const Transformed p = transform(pred, rep, "prediction"), r = transform(ref, rep, "reference");
  Metrics m;
  m.excluded_prediction = p.excluded;
  m.excluded_reference = r.excluded;
  const double lo = std::max(p.X.front(), r.X.front()), hi = std::min(p.X.back(), r.X.back());
  if (!(hi > lo)) {
    auto range = [&](const Transformed& t) {
      return "[" + fmt(from_rep(t.X.front(), rep.log_x)) + ", " + fmt(from_rep(t.X.back(), rep.log_x)) + "]";
    };
    throw InputError(pred.file + ": no overlap with the reference " + ref.file + ": the prediction covers " +
                     pred.x_column + " in " + range(p) + " (SI), the reference " + range(r) +
                     " (SI); the curves must share a range of the abscissa");
  }
  std::vector<double> X = {lo, hi};
  for (double x : p.X)
    if (x > lo && x < hi) X.push_back(x);
  for (double x : r.X)
    if (x > lo && x < hi) X.push_back(x);
  std::sort(X.begin(), X.end());
  X.erase(std::unique(X.begin(), X.end()), X.end());
  std::vector<double> d(X.size()), yr(X.size()), yp(X.size());
  double scale = 0;
  for (std::size_t i = 0; i < X.size(); ++i) {
    yp[i] = interp(p.X, p.Y, X[i]);
    yr[i] = interp(r.X, r.Y, X[i]);
    d[i] = yp[i] - yr[i];
    scale = std::max(scale, std::abs(yr[i]));
  }
  if (!rep.log_y && !(scale > 0))
    throw InputError(ref.file + ": the reference is zero over the common range: relative errors are undefined");
  m.rel_scale = rep.log_y ? 0.0 : scale;
  std::vector<double> ea(X.size()), er(X.size());
  for (std::size_t i = 0; i < X.size(); ++i) {
    ea[i] = std::abs(d[i]);
    er[i] = rep.log_y ? std::abs(std::pow(10.0, d[i]) - 1) : ea[i] / scale;
    if (ea[i] > m.max_abs || i == 0) {
      m.max_abs = ea[i];
      m.x_at_max_abs = from_rep(X[i], rep.log_x);
    }
    m.max_rel = std::max(m.max_rel, er[i]);
  }
  double sa = 0, sr = 0;
  for (std::size_t i = 1; i < X.size(); ++i) {
    const double h = X[i] - X[i - 1];
    sa += 0.5 * h * (ea[i] * ea[i] + ea[i - 1] * ea[i - 1]);
    sr += 0.5 * h * (er[i] * er[i] + er[i - 1] * er[i - 1]);
  }
  m.rms_abs = std::sqrt(sa / (hi - lo));
  m.rms_rel = std::sqrt(sr / (hi - lo));
  // Values near the largest double make differences (or relative errors) overflow; a
  // verdict on NaN or infinity would be meaningless, and check.json could not hold it.
  for (double v : {m.max_abs, m.rms_abs, m.max_rel, m.rms_rel})
    if (!std::isfinite(v))
      throw InputError(pred.file + ": the errors against " + ref.file + " overflow a double (values or differences "
                       "beyond 1e308, or a relative error beyond that on a log axis): nothing to score");
  m.x_lo = from_rep(lo, rep.log_x);
  m.x_hi = from_rep(hi, rep.log_x);
  m.coverage = (hi - lo) / (r.X.back() - r.X.front());
  m.points = X.size();
  for (std::size_t i = 0; i < X.size(); ++i) {
    m.eval_x.push_back(from_rep(X[i], rep.log_x));
    m.eval_pred.push_back(from_rep(yp[i], rep.log_y));
    m.eval_ref.push_back(from_rep(yr[i], rep.log_y));
  }
  return m;
}

Verdict verdict(const Metrics& m, double tolerance, const std::string& metric, const std::string& source) {
  if (!(tolerance > 0) || !std::isfinite(tolerance))
    throw InputError("tolerance " + fmt(tolerance) + ": expected a positive number");
  Verdict v;
  v.tolerance = tolerance;
  v.metric = metric;
  v.source = source;
  v.value = m.get(metric);
  v.pass = v.value <= tolerance;
  return v;
}

// ============================================================================ the check
Report run_check(const Options& o) {
  Report r;
  if (o.prediction.empty()) throw InputError("no prediction file given");
  const bool challenge = !o.quantity.empty();
  if (!challenge && o.reference_file.empty())
    throw InputError("give --quantity Q (a challenge quantity) or --reference FILE (compare with a stored curve)");
  if (challenge) r.spec = quantity(o.quantity);
  r.prediction_file = o.prediction;
  r.reference_file = o.reference_file;
  if (challenge && r.reference_file.empty()) {
    r.reference_file = default_reference_path(o.quantity);
    std::error_code ec;
    if (!std::filesystem::exists(r.reference_file, ec))
      throw InputError("no stored reference for quantity '" + o.quantity + "' yet (" + r.reference_file +
                       " does not exist; challenge reference curves come from cmc runs): pass --reference FILE");
  }
  if (!o.metric.empty()) Metrics{}.get(o.metric);  // validates the name
  // Read both files before anything else, so every input error surfaces here.
  const Table ref_table = reference::read_csv(r.reference_file, 2);
  const reference::Curve ref_curve = reference::curve_from_table(ref_table);
  r.reference_name = ref_curve.name;
  r.reference_source = ref_curve.source;
  if (challenge && ref_curve.quantity != o.quantity)
    throw InputError(r.reference_file + ": the reference is for quantity '" + ref_curve.quantity + "', not '" +
                     o.quantity + "'");
  if (!challenge) {
    const std::string x = o.x.empty() ? ref_curve.x : o.x, y = o.y.empty() ? ref_curve.y : o.y;
    ref_table.column(x);
    ref_table.column(y);
    r.spec = generic_spec(ref_curve.quantity, x, y, reference::parse_representation(ref_curve.representation),
                          ref_curve.tolerance.value_or(0.0), ref_curve.tolerance_metric);
    r.spec.title = ref_curve.title.empty() ? ref_curve.name : ref_curve.title;
  } else if (!o.x.empty() || !o.y.empty()) {
    throw InputError("--x/--y select columns only without --quantity (a challenge quantity names its columns)");
  }
  const Table pred_table = reference::read_csv(o.prediction, 2);
  r.prediction = extract(pred_table, r.spec);
  r.ref = extract(ref_table, r.spec);
  r.metrics = compare(r.prediction, r.ref, r.spec.rep);

  std::string metric = o.metric, source;
  double tol = 0;
  if (o.tolerance) {
    tol = *o.tolerance;
    source = "--tolerance";
  } else if (ref_curve.tolerance) {
    tol = *ref_curve.tolerance;
    source = "reference file " + r.reference_file;
    if (metric.empty()) metric = ref_curve.tolerance_metric;
  } else if (challenge) {
    tol = r.spec.tolerance;
    source = "default for " + r.spec.id;
    if (metric.empty()) metric = r.spec.metric;
  } else {
    throw InputError(r.reference_file + ": has no '# tolerance:' line: pass --tolerance T");
  }
  if (metric.empty()) metric = challenge ? r.spec.metric : ref_curve.tolerance_metric;
  r.verdict = verdict(r.metrics, tol, metric, source);

  if (!r.prediction.ignored_columns.empty()) {
    std::string s;
    for (const auto& c : r.prediction.ignored_columns) s += (s.empty() ? "" : ", ") + c;
    r.notes.push_back("columns not used: " + s);
  }
  if (r.metrics.excluded_prediction)
    r.notes.push_back(std::to_string(r.metrics.excluded_prediction) +
                      " prediction point(s) left out: not positive on a log axis");
  if (r.metrics.excluded_reference)
    r.notes.push_back(std::to_string(r.metrics.excluded_reference) +
                      " reference point(s) left out: not positive on a log axis");
  if (r.metrics.coverage < 0.5)
    r.notes.push_back("the prediction covers only " + fmt(100 * r.metrics.coverage) +
                      "% of the reference's range (in the " + representation_name(r.spec.rep) + " representation)");
  return r;
}

// ============================================================================ output
namespace {
toml::array arr(const std::vector<double>& v) {
  toml::array a;
  for (double x : v) a.push_back(x);
  return a;
}
std::string axis_unit(const QuantitySpec& s, bool x) {
  const Dim d = x ? s.x.dim : s.y.dim;
  return d == Dim::None ? std::string("as in the files") : si_unit(d);
}
}  // namespace

std::string report_json(const Report& r) {
  const Metrics& m = r.metrics;
  toml::table axes{{"x", toml::table{{"label", r.spec.x.label}, {"unit", axis_unit(r.spec, true)},
                                     {"log", r.spec.rep.log_x}, {"prediction_column", r.prediction.x_column},
                                     {"reference_column", r.ref.x_column}}},
                   {"y", toml::table{{"label", r.spec.y.label}, {"unit", axis_unit(r.spec, false)},
                                     {"log", r.spec.rep.log_y}, {"prediction_column", r.prediction.y_column},
                                     {"reference_column", r.ref.y_column}}}};
  toml::array notes;
  for (const auto& n : r.notes) notes.push_back(n);
  toml::table t{
      {"cmc_version", CMC_VERSION},
      {"quantity", r.spec.id},
      {"title", r.spec.title},
      {"challenge_item", r.spec.item},
      {"prediction_file", r.prediction_file},
      {"reference_file", r.reference_file},
      {"reference_name", r.reference_name},
      {"reference_source", r.reference_source},
      {"representation", representation_name(r.spec.rep)},
      {"axes", axes},
      {"common_range", toml::array{m.x_lo, m.x_hi}},
      {"coverage_of_reference", m.coverage},
      {"evaluation_points", (long long)m.points},
      {"excluded_points", toml::table{{"prediction", (long long)m.excluded_prediction},
                                      {"reference", (long long)m.excluded_reference}}},
      {"metrics", toml::table{{"max_abs", m.max_abs},
                              {"rms_abs", m.rms_abs},
                              {"max_rel", m.max_rel},
                              {"rms_rel", m.rms_rel},
                              {"x_at_max_abs", m.x_at_max_abs},
                              {"abs_unit", r.spec.rep.log_y ? std::string("decades (log10)") : axis_unit(r.spec, false)},
                              {"rel_definition",
                               r.spec.rep.log_y ? std::string("|y_pred/y_ref - 1|")
                                                : std::string("|y_pred - y_ref| / max|y_ref| over the common range")},
                              {"rel_scale", m.rel_scale}}},
      {"verdict", toml::table{{"pass", r.verdict.pass},
                              {"metric", r.verdict.metric},
                              {"value", r.verdict.value},
                              {"tolerance", r.verdict.tolerance},
                              {"tolerance_source", r.verdict.source}}},
      {"notes", notes},
      {"prediction", toml::table{{"x", arr(r.prediction.x)}, {"y", arr(r.prediction.y)}}},
      {"reference", toml::table{{"x", arr(r.ref.x)}, {"y", arr(r.ref.y)}}},
      {"evaluation", toml::table{{"x", arr(m.eval_x)}, {"prediction", arr(m.eval_pred)}, {"reference", arr(m.eval_ref)}}},
  };
  return cmc::to_json(t);
}

std::string report_text(const Report& r) {
  const Metrics& m = r.metrics;
  std::ostringstream s;
  const std::string absu = r.spec.rep.log_y ? "decades" : axis_unit(r.spec, false);
  s << "quantity        " << r.spec.id << (r.spec.item ? " (challenge item " + std::to_string(r.spec.item) + ")" : "")
    << "\n";
  s << "prediction      " << r.prediction_file << "  [" << r.prediction.x_column << ", " << r.prediction.y_column
    << "]\n";
  s << "reference       " << r.reference_file << "  [" << r.ref.x_column << ", " << r.ref.y_column << "]\n";
  s << "representation  " << representation_name(r.spec.rep) << "; common range " << r.spec.x.label << " "
    << fmt(m.x_lo) << " .. " << fmt(m.x_hi) << " " << axis_unit(r.spec, true) << " (" << fmt(100 * m.coverage)
    << "% of the reference), " << m.points << " points\n";
  s << "max abs error   " << fmt(m.max_abs) << " " << absu << " (at " << fmt(m.x_at_max_abs) << ")\n";
  s << "rms abs error   " << fmt(m.rms_abs) << " " << absu << "\n";
  s << "max rel error   " << fmt(m.max_rel) << "\n";
  s << "rms rel error   " << fmt(m.rms_rel) << "\n";
  for (const auto& n : r.notes) s << "note            " << n << "\n";
  s << "verdict         " << (r.verdict.pass ? "PASS" : "FAIL") << ": " << r.verdict.metric << " = "
    << fmt(r.verdict.value) << (r.verdict.pass ? " <= " : " > ") << "tolerance " << fmt(r.verdict.tolerance) << " ("
    << r.verdict.source << ")\n";
  return s.str();
}

}  // namespace cmc::check
