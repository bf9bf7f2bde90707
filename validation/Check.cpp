// The prediction checker (see Check.hpp and reference/README.md).
#include "Check.hpp"
#include "Sampler.hpp"

#include "cmc/output/Writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <tuple>

#include <toml++/toml.h>

namespace cmc::check {

namespace {

std::string fmt(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

std::string axis_unit(const QuantitySpec& s, bool x) {
  const Dim d = x ? s.x.dim : s.y.dim;
  return d == Dim::None ? std::string("as in the files") : si_unit(d);
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

// A non-monotonic or repeated abscissa at `line` (x after xprev of line_prev).
[[noreturn]] void fail_monotonic(const Table& t, const QuantitySpec& spec, int column, double x, double xprev,
                                 int line, int line_prev, bool increasing) {
  const std::string here = t.file + ":" + std::to_string(line) + ": " + col_ref(t, column) + ": ";
  if (x == xprev)
    throw InputError(here + fmt(x) + " repeats the value of line " + std::to_string(line_prev) + ": duplicate " +
                     spec.x.label + " (the abscissa must be strictly monotonic: one value of the " + spec.y.label +
                     " per abscissa)");
  throw InputError(here + fmt(x) + " after " + fmt(xprev) + " (line " + std::to_string(line_prev) + "): the " +
                   spec.x.label + " must be strictly " + (increasing ? "increasing" : "decreasing") +
                   " (non-monotonic abscissa; sort the rows)");
}

// The curve's columns and units: the axes of `spec` in the header of `t`.
XY axes_of(const Table& t, const QuantitySpec& spec, int& xcol, int& ycol) {
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
  xcol = mx.column, ycol = my.column;
  return c;
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

std::string default_reference_path(const std::string& quantity, bool adhesionless) {
  return reference::default_reference_dir() + (adhesionless ? "/challenge/adhesionless/" : "/challenge/") + quantity +
         ".csv";
}

// ============================================================================ extraction
XY extract(const Table& t, const QuantitySpec& spec, const std::string& band_column) {
  int xcol = -1, ycol = -1;
  XY c = axes_of(t, spec, xcol, ycol);
  const auto& xs = t.data[std::size_t(xcol)];
  const auto& ys = t.data[std::size_t(ycol)];
  if (!band_column.empty())
    for (double b : t.column(band_column)) c.band.push_back(b * c.y_to_si);
  if (xs.size() < 2)
    throw InputError(t.file + ": " + std::to_string(xs.size()) + " data row(s); a curve needs at least 2");
  // Direction from the ends, so a repeated or misplaced first value is named as such.
  const bool increasing = xs.back() >= xs.front();
  for (std::size_t i = 1; i < xs.size(); ++i) {
    const bool ok = increasing ? xs[i] > xs[i - 1] : xs[i] < xs[i - 1];
    if (!ok) fail_monotonic(t, spec, xcol, xs[i], xs[i - 1], t.row_line[i], t.row_line[i - 1], increasing);
  }
  for (std::size_t i = 0; i < xs.size(); ++i) {
    c.x.push_back(xs[i] * c.x_to_si);
    c.y.push_back(ys[i] * c.y_to_si);
    c.line.push_back(t.row_line[i]);
    // A value finite in its unit can overflow in SI (1e300 per nm^2 is 1e318 per m^2).
    for (const auto& [v, k] : {std::pair{c.x.back(), xcol}, std::pair{c.y.back(), ycol}})
      if (!std::isfinite(v))
        throw InputError(t.file + ":" + std::to_string(t.row_line[i]) + ": " + col_ref(t, k) + ": " +
                         fmt(t.data[std::size_t(k)][i]) + " is too large to convert to SI units (" +
                         si_unit(k == xcol ? spec.x.dim : spec.y.dim) + ")");
  }
  if (!increasing) {
    std::reverse(c.x.begin(), c.x.end());
    std::reverse(c.y.begin(), c.y.end());
    std::reverse(c.band.begin(), c.band.end());
    std::reverse(c.line.begin(), c.line.end());
  }
  c.rows = c.x.size();
  c.x_min = *std::min_element(c.x.begin(), c.x.end()), c.x_max = *std::max_element(c.x.begin(), c.x.end());
  c.y_min = *std::min_element(c.y.begin(), c.y.end()), c.y_max = *std::max_element(c.y.begin(), c.y.end());
  return c;
}

// ============================================================================ metrics
double Metrics::get(const std::string& metric) const {
  if (metric == "max_abs") return max_abs;
  if (metric == "rms_abs") return rms_abs;
  if (metric == "max_rel") return max_rel;
  if (metric == "rms_rel") return rms_rel;
  if (metric == "max_band" && has_band) return max_band;
  throw InputError("unknown metric '" + metric + "' (expected max_abs, rms_abs, max_rel or rms_rel" +
                   (has_band ? ", or max_band" : "") + ")");
}

namespace {
struct Transformed {
  std::vector<double> X, Y;
  std::vector<double> up, down;  // the band's half-widths above and below Y (in Y), if any
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
    if (c.band.empty()) continue;
    const double e = c.band[i], y = c.y[i];
    // On a log axis y ± e is log10(y + e) above and log10(y - e) below (no lower edge,
    // i.e. any smaller value is inside, when e >= y).
    t.up.push_back(rep.log_y ? std::log1p(e / y) / std::log(10.0) : e);
    t.down.push_back(rep.log_y ? (e < y ? -std::log1p(-e / y) / std::log(10.0) : INFINITY) : e);
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

// Scores a prediction against the reference one point at a time, in the prediction's
// order (increasing or decreasing): each segment between consecutive prediction points
// (in the representation) is clipped to the reference's range and evaluated at its
// ends and at every reference abscissa inside it, exactly the points and trapezoids of
// the whole-curve definition (Check.hpp), so memory does not grow with the prediction.
class Scorer {
 public:
  Scorer(const Transformed& ref, Representation rep, std::size_t cap) : R_(ref), rep_(rep), eval_(cap) {}

  void add(double X, double Y) {
    xmin_ = std::min(xmin_, X), xmax_ = std::max(xmax_, X);
    if (have_prev_) segment(prev_, {X, Y});
    prev_ = {X, Y};
    have_prev_ = true;
    ++kept_;
  }
  std::size_t kept() const { return kept_; }

  // The metrics; throws InputError when the curves do not overlap or the reference is
  // zero over the common range (relative errors undefined on a linear axis).
  Metrics finish(const XY& pred, const XY& ref) const {
    const bool lx = rep_.log_x, ly = rep_.log_y;
    if (subsegments_ == 0) {
      auto range = [&](double a, double b) { return "[" + fmt(from_rep(a, lx)) + ", " + fmt(from_rep(b, lx)) + "]"; };
      throw InputError(pred.file + ": no overlap with the reference " + ref.file + ": the prediction covers " +
                       pred.x_column + " in " + range(xmin_, xmax_) + " (SI), the reference " +
                       range(R_.X.front(), R_.X.back()) + " (SI); the curves must share a range of the abscissa");
    }
    if (!ly && !(scale_ > 0))
      throw InputError(ref.file + ": the reference is zero over the common range: relative errors are undefined");
    Metrics m;
    const double span = hi_ - lo_;
    m.max_abs = max_abs_;
    m.x_at_max_abs = from_rep(x_at_max_, lx);
    m.rms_abs = std::sqrt(sa_ / span);
    m.rel_scale = ly ? 0.0 : scale_;
    m.max_rel = ly ? max_rel_log_ : max_abs_ / scale_;
    m.rms_rel = ly ? std::sqrt(sr_log_ / span) : m.rms_abs / scale_;
    // Values near the largest double make differences (or relative errors) overflow; a
    // verdict on NaN or infinity would be meaningless, and check.json could not hold it.
    for (double v : {m.max_abs, m.rms_abs, m.max_rel, m.rms_rel})
      if (!std::isfinite(v))
        throw InputError(pred.file + ": the errors against " + ref.file + " overflow a double (values or differences "
                         "beyond 1e308, or a relative error beyond that on a log axis): nothing to score");
    m.x_lo = from_rep(lo_, lx);
    m.x_hi = from_rep(hi_, lx);
    m.coverage = span / (R_.X.back() - R_.X.front());
    m.ref_lo = from_rep(R_.X.front(), lx);
    m.ref_hi = from_rep(R_.X.back(), lx);
    m.points = subsegments_ + 1;
    std::vector<Eval> ev = eval_.take();
    std::sort(ev.begin(), ev.end(), [](const Eval& a, const Eval& b) { return a.X < b.X; });
    ev.erase(std::unique(ev.begin(), ev.end(), [](const Eval& a, const Eval& b) { return a.X == b.X; }), ev.end());
    for (const Eval& e : ev) {
      m.eval_x.push_back(from_rep(e.X, lx));
      m.eval_pred.push_back(from_rep(e.yp, ly));
      m.eval_ref.push_back(from_rep(e.yr, ly));
      if (have_band_) {
        m.eval_lo.push_back(ly ? (std::isinf(e.down) ? 0.0 : from_rep(e.yr - e.down, ly)) : e.yr - e.down);
        m.eval_hi.push_back(from_rep(e.yr + e.up, ly));
      }
    }
    m.has_band = have_band_;
    m.max_band = max_band_;
    m.x_at_max_band = from_rep(x_at_max_band_, lx);
    m.eval_echo_stride = eval_.stride();
    return m;
  }

 private:
  struct Pt {
    double X = 0, Y = 0;
  };
  struct Eval {
    double X = 0, yp = 0, yr = 0, ea = 0, er = 0, up = 0, down = 0;
  };
  // The band's half-width at X, linear between the reference's points; an infinite lower
  // half-width (band reaching zero on a log axis) stays infinite between two such points
  // and takes the finite neighbour's value otherwise.
  double interp_band(const std::vector<double>& B, double X) const {
    auto it = std::upper_bound(R_.X.begin(), R_.X.end(), X);
    if (it == R_.X.begin()) return B.front();
    if (it == R_.X.end()) return B.back();
    const std::size_t j = std::size_t(it - R_.X.begin());
    const double a = B[j - 1], b = B[j], t = (X - R_.X[j - 1]) / (R_.X[j] - R_.X[j - 1]);
    if (std::isinf(a) || std::isinf(b)) return std::isinf(a) && std::isinf(b) ? INFINITY : std::isinf(a) ? b : a;
    return a + t * (b - a);
  }
  Eval at(double X, const Pt& l, const Pt& r) {
    Eval e;
    e.X = X;
    // The prediction on its segment [l, r] (exact at its ends), the reference by its own
    // interpolation.
    if (X == l.X) e.yp = l.Y;
    else if (X == r.X) e.yp = r.Y;
    else e.yp = l.Y + (X - l.X) / (r.X - l.X) * (r.Y - l.Y);
    e.yr = interp(R_.X, R_.Y, X);
    const double d = e.yp - e.yr;
    e.ea = std::abs(d);
    if (!R_.up.empty()) {
      e.up = interp_band(R_.up, X), e.down = interp_band(R_.down, X);
      const double half = d >= 0 ? e.up : e.down;
      const double b = d == 0 ? 0.0 : std::abs(d) / half;
      if (!std::isfinite(b))
        throw InputError("the reference's error band is too narrow to score against at " +
                         fmt(from_rep(X, rep_.log_x)) + " (its half-width " + fmt(half) + " in the " +
                         representation_name(rep_) + " representation, the difference " + fmt(d) + ")");
      if (!have_band_ || b > max_band_ || (b == max_band_ && X < x_at_max_band_)) max_band_ = b, x_at_max_band_ = X;
      have_band_ = true;
    }
    e.er = rep_.log_y ? std::abs(std::pow(10.0, d) - 1) : 0.0;
    // The largest error; among equal ones the smallest abscissa, as a sweep from the left.
    if (!have_max_ || e.ea > max_abs_ || (e.ea == max_abs_ && X < x_at_max_)) max_abs_ = e.ea, x_at_max_ = X;
    have_max_ = true;
    max_rel_log_ = std::max(max_rel_log_, e.er);
    scale_ = std::max(scale_, std::abs(e.yr));
    eval_.add(e);
    return e;
  }
  void trapezoid(const Eval& a, const Eval& b) {
    const double h = b.X - a.X;
    sa_ += 0.5 * h * (a.ea * a.ea + b.ea * b.ea);
    sr_log_ += 0.5 * h * (a.er * a.er + b.er * b.er);
    ++subsegments_;
  }
  void segment(Pt a, Pt b) {
    if (b.X < a.X) std::swap(a, b);
    if (!(b.X > a.X)) return;  // a repeated abscissa: the caller reports it
    const double lo = std::max(a.X, R_.X.front()), hi = std::min(b.X, R_.X.back());
    if (!(hi > lo)) return;
    Eval e0 = at(lo, a, b);
    for (auto it = std::upper_bound(R_.X.begin(), R_.X.end(), lo); it != R_.X.end() && *it < hi; ++it) {
      const Eval e1 = at(*it, a, b);
      trapezoid(e0, e1);
      e0 = e1;
    }
    trapezoid(e0, at(hi, a, b));
    lo_ = std::min(lo_, lo), hi_ = std::max(hi_, hi);
  }

  const Transformed& R_;
  Representation rep_;
  Sampler<Eval> eval_;
  Pt prev_;
  bool have_prev_ = false, have_max_ = false, have_band_ = false;
  double max_band_ = 0, x_at_max_band_ = 0;
  std::size_t kept_ = 0, subsegments_ = 0;
  double xmin_ = INFINITY, xmax_ = -INFINITY, lo_ = INFINITY, hi_ = -INFINITY;
  double max_abs_ = 0, x_at_max_ = 0, max_rel_log_ = 0, scale_ = 0, sa_ = 0, sr_log_ = 0;
};
}  // namespace

namespace {
// The prediction file, streamed row by row through the scorer: the same checks and
// messages as extract() + compare() on the whole table, with memory bounded by the
// reference and kMaxEchoedRows. Returns the sampled curve and the metrics.
std::pair<XY, Metrics> score_prediction(const std::string& path, const std::vector<std::string>& columns,
                                        const QuantitySpec& spec, const XY& ref) {
  std::ifstream in = reference::open_csv(path);
  reference::CsvReader reader(in, path, /*keep_comments=*/false, reference::Layout::submissions(columns));
  if (!reader.has_header()) reader.fail_no_header();
  const Table& t = reader.header();
  int xcol = -1, ycol = -1;
  XY c = axes_of(t, spec, xcol, ycol);
  const Representation rep = spec.rep;
  const Transformed r = transform(ref, rep, "reference");
  Scorer scorer(r, rep, kMaxEchoedRows);
  struct Row {
    double x = 0, y = 0;
    int line = 0;
  };
  Sampler<Row> rows(kMaxEchoedRows);
  // The first violation of either direction; which one counts is known at the end (the
  // direction comes from the ends, as in extract()).
  struct Violation {
    bool seen = false;
    double x = 0, xprev = 0;
    int line = 0, line_prev = 0;
  } up, down;
  std::vector<double> v;
  int line = 0, prev_line = 0;
  std::size_t n = 0, excluded = 0;
  NonPositive nonpositive;
  double first = 0, prev = 0;
  c.x_min = c.y_min = INFINITY, c.x_max = c.y_max = -INFINITY;
  while (reader.next(v, line)) {
    const double xf = v[std::size_t(xcol)], yf = v[std::size_t(ycol)];
    if (n == 0) first = xf;
    else {
      if (!up.seen && !(xf > prev)) up = {true, xf, prev, line, prev_line};
      if (!down.seen && !(xf < prev)) down = {true, xf, prev, line, prev_line};
    }
    prev = xf, prev_line = line, ++n;
    const double x = xf * c.x_to_si, y = yf * c.y_to_si;
    // A value finite in its unit can overflow in SI (1e300 per nm^2 is 1e318 per m^2).
    for (const auto& [si, k] : {std::pair{x, xcol}, std::pair{y, ycol}})
      if (!std::isfinite(si))
        throw InputError(path + ":" + std::to_string(line) + ": " + col_ref(t, k) + ": " + fmt(v[std::size_t(k)]) +
                         " is too large to convert to SI units (" + si_unit(k == xcol ? spec.x.dim : spec.y.dim) + ")");
    c.x_min = std::min(c.x_min, x), c.x_max = std::max(c.x_max, x);
    c.y_min = std::min(c.y_min, y), c.y_max = std::max(c.y_max, y);
    rows.add({x, y, line});
    const bool x_off = rep.log_x && !(x > 0), y_off = rep.log_y && !(y > 0);
    const double X = x_off ? -INFINITY : rep.log_x ? std::log10(x) : x;
    if (x_off || y_off) ++excluded;
    else scorer.add(X, rep.log_y ? std::log10(y) : y);
    // A value a log y axis cannot hold where the reference has one: a wrong prediction.
    if (y_off && !x_off && X >= r.X.front() && X <= r.X.back() && ++nonpositive.count <= 5)
      nonpositive.lines.push_back(line);
  }
  if (n < 2) reader.fail_rows(n, 2);
  const bool increasing = prev >= first;
  if (const Violation& bad = increasing ? up : down; bad.seen)
    fail_monotonic(t, spec, xcol, bad.x, bad.xprev, bad.line, bad.line_prev, increasing);
  if (scorer.kept() < 2)
    throw InputError(path + ": only " + std::to_string(scorer.kept()) + " point(s) of the prediction are positive on "
                     "the log axes of the " + representation_name(rep) + " representation; at least 2 are needed");
  Metrics m = scorer.finish(c, ref);
  m.excluded_prediction = excluded;
  m.excluded_reference = r.excluded;
  m.nonpositive = nonpositive;
  std::vector<Row> kept = rows.take();
  if (!increasing) std::reverse(kept.begin(), kept.end());
  for (const Row& k : kept) c.x.push_back(k.x), c.y.push_back(k.y), c.line.push_back(k.line);
  c.rows = n;
  c.echo_stride = rows.stride();
  return {std::move(c), std::move(m)};
}
}  // namespace

Metrics compare(const XY& pred, const XY& ref, Representation rep) {
  const Transformed p = transform(pred, rep, "prediction"), r = transform(ref, rep, "reference");
  Scorer sc(r, rep, std::numeric_limits<std::size_t>::max());
  for (std::size_t i = 0; i < p.X.size(); ++i) sc.add(p.X[i], p.Y[i]);
  Metrics m = sc.finish(pred, ref);
  m.excluded_prediction = p.excluded;
  m.excluded_reference = r.excluded;
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
namespace {
// Why rows with y <= 0 on a log y axis inside the reference's range fail the check ("": none).
std::string nonpositive_reason(const Report& r) {
  const NonPositive& np = r.metrics.nonpositive;
  if (!np.count) return "";
  std::string lines;
  for (int l : np.lines) lines.append(lines.empty() ? "" : ", ").append(std::to_string(l));
  return std::to_string(np.count) + " row(s) of the prediction give the " + r.spec.y.label +
         " <= 0 inside the reference's range, where the log y axis (and the reference) has only positive values: a "
         "wrong prediction (line" + (np.count > 1 ? "s " : " ") + lines + (np.count > 5 ? ", ..." : "") + " of " +
         r.prediction_file + ")";
}
// Why the prediction covers too little of the reference's range.
std::string coverage_reason(const Report& r) {
  const Verdict& v = r.verdict;
  return "the prediction covers " + fmt(100 * r.metrics.coverage) + "% of the reference's range of the " +
         r.spec.x.label + " (" + fmt(r.metrics.x_lo) + " .. " + fmt(r.metrics.x_hi) + " of " + fmt(r.metrics.ref_lo) +
         " .. " + fmt(r.metrics.ref_hi) + " " + axis_unit(r.spec, true) + ", in the " +
         representation_name(r.spec.rep) + " representation); at least " + fmt(100 * v.min_coverage) +
         "% is needed (" + v.coverage_source + ")";
}
}  // namespace

Report run_check(const Options& o) {
  Report r;
  if (o.prediction.empty()) throw InputError("no prediction file given");
  const bool challenge = !o.quantity.empty();
  if (!challenge && o.reference_file.empty())
    throw InputError("give --quantity Q (a challenge quantity) or --reference FILE (compare with a stored curve)");
  if (challenge) r.spec = quantity(o.quantity);
  r.prediction_file = o.prediction;
  r.reference_file = o.reference_file;
  if (o.adhesionless && !(challenge && r.reference_file.empty()))
    throw InputError("--adhesionless chooses the stored adhesionless reference of a challenge quantity: give it with "
                     "--quantity Q and without --reference");
  if (challenge && r.reference_file.empty()) {
    r.reference_file = default_reference_path(o.quantity, o.adhesionless);
    std::error_code ec;
    if (!std::filesystem::exists(r.reference_file, ec))
      throw InputError("no stored " + std::string(o.adhesionless ? "adhesionless " : "") + "reference for quantity '" +
                       o.quantity + "' yet (" + r.reference_file + " does not exist" +
                       (o.adhesionless ? "; the Tabor-parameter quantities have none, the Tabor parameter being one "
                                         "of adhesion"
                                       : "; challenge reference curves come from cmc runs") +
                       "): pass --reference FILE");
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
  // The coverage the prediction must reach, from the command line, else the reference.
  double min_coverage = r.spec.min_coverage;
  std::string coverage_source = challenge ? "default for " + r.spec.id : "default";
  if (o.min_coverage) {
    min_coverage = *o.min_coverage;
    coverage_source = "--min-coverage";
  } else if (const auto mc = ref_table.get("min_coverage")) {
    char* end = nullptr;
    min_coverage = std::strtod(mc->c_str(), &end);
    if (end == mc->c_str() || *end != '\0' || !(min_coverage >= 0.0 && min_coverage <= 1.0))
      throw InputError(r.reference_file + ": '# min_coverage: " + *mc + "': expected a fraction from 0 to 1");
    coverage_source = "reference file " + r.reference_file;
  }
  if (!(min_coverage >= 0.0 && min_coverage <= 1.0))
    throw InputError("--min-coverage " + fmt(min_coverage) + ": expected a fraction from 0 to 1");
  r.ref = extract(ref_table, r.spec, ref_curve.band);
  std::tie(r.prediction, r.metrics) = score_prediction(o.prediction, o.columns, r.spec, r.ref);

  std::string metric = o.metric, source;
  double tol = 0;
  if (r.metrics.has_band && !o.tolerance && (o.metric.empty() || o.metric == "max_band")) {
    // The reference's own uncertainty decides: inside its band passes.
    tol = 1.0;
    metric = "max_band";
    source = "the reference's error band, column '" + ref_curve.band + "' of " + r.reference_file;
  } else if (o.tolerance) {
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
  Verdict& v = r.verdict;
  v.min_coverage = min_coverage;
  v.coverage_source = coverage_source;
  v.covered = r.metrics.coverage >= min_coverage;
  v.reason = nonpositive_reason(r);
  v.pass = v.pass && v.reason.empty();
  if (!v.covered) v.pass = false, v.reason += (v.reason.empty() ? "" : "; and ") + coverage_reason(r);

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
  if (r.prediction.echo_stride > 1 || r.metrics.eval_echo_stride > 1)
    r.notes.push_back("check.json echoes " + std::to_string(r.prediction.x.size()) + " of the prediction's " +
                      std::to_string(r.prediction.rows) + " rows (one in " + std::to_string(r.prediction.echo_stride) +
                      ", and the last) and " + std::to_string(r.metrics.eval_x.size()) + " of the " +
                      std::to_string(r.metrics.points) + " evaluation points; the metrics use all of them");
  return r;
}

// ============================================================================ output
namespace {
toml::array arr(const std::vector<double>& v) {
  toml::array a;
  for (double x : v) a.push_back(x);
  return a;
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
                              {"rel_scale", m.rel_scale},
                              {"has_band", m.has_band},
                              {"max_band", m.max_band},
                              {"x_at_max_band", m.x_at_max_band}}},
      {"verdict", toml::table{{"pass", r.verdict.pass},
                              {"metric", r.verdict.metric},
                              {"value", r.verdict.value},
                              {"tolerance", r.verdict.tolerance},
                              {"tolerance_source", r.verdict.source},
                              {"covered", r.verdict.covered},
                              {"min_coverage", r.verdict.min_coverage},
                              {"min_coverage_source", r.verdict.coverage_source},
                              {"reason", r.verdict.reason}}},
      {"notes", notes},
      // At most kMaxEchoedRows rows of the prediction and evaluation points, evenly
      // sampled (echo_stride: one in that many, and the last); the ranges are over all.
      {"prediction", toml::table{{"rows", (long long)r.prediction.rows},
                                 {"echoed_rows", (long long)r.prediction.x.size()},
                                 {"echo_stride", (long long)r.prediction.echo_stride},
                                 {"x_range", toml::array{r.prediction.x_min, r.prediction.x_max}},
                                 {"y_range", toml::array{r.prediction.y_min, r.prediction.y_max}},
                                 {"x", arr(r.prediction.x)},
                                 {"y", arr(r.prediction.y)}}},
      {"reference", toml::table{{"x", arr(r.ref.x)}, {"y", arr(r.ref.y)}, {"band", arr(r.ref.band)}}},
      {"evaluation", toml::table{{"points", (long long)m.points},
                                 {"echoed_points", (long long)m.eval_x.size()},
                                 {"echo_stride", (long long)m.eval_echo_stride},
                                 {"x", arr(m.eval_x)},
                                 {"prediction", arr(m.eval_pred)},
                                 {"reference", arr(m.eval_ref)},
                                 {"reference_low", arr(m.eval_lo)},
                                 {"reference_high", arr(m.eval_hi)}}},
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
  if (m.has_band)
    s << "max deviation   " << fmt(m.max_band) << " x the reference's error band (at " << fmt(m.x_at_max_band)
      << "; <= 1 is inside it)\n";
  for (const auto& n : r.notes) s << "note            " << n << "\n";
  const Verdict& v = r.verdict;
  const bool within = v.value <= v.tolerance;
  if (v.metric == "max_band")
    s << "verdict         " << (v.pass ? "PASS" : "FAIL") << ": "
      << (within ? "inside the reference's error band (max_band = " + fmt(v.value) + " <= 1"
                 : "outside the reference's error band by up to " + fmt(v.value) + " times its half-width (at " +
                       fmt(m.x_at_max_band) + " " + axis_unit(r.spec, true))
      << "; " << v.source << ")\n";
  else
    s << "verdict         " << (v.pass ? "PASS" : "FAIL") << ": " << v.metric << " = " << fmt(v.value)
      << (within ? " <= " : " > ") << "tolerance " << fmt(v.tolerance) << " (" << v.source << ")\n";
  if (!v.reason.empty()) s << "                FAIL: " << v.reason << "\n";
  return s.str();
}

}  // namespace cmc::check
