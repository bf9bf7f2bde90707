// The challenge quantities the checker knows, the units and column names a prediction
// may use, and a reference curve read into SI units (Check.hpp).
#include "CheckParts.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace cmc::check {

namespace parts {

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

void fail_monotonic(const Table& t, const QuantitySpec& spec, int column, double x, double xprev,
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

}  // namespace parts

using namespace parts;

namespace {

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

XY parts::axes_of(const Table& t, const QuantitySpec& spec, int& xcol, int& ycol) {
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

std::string default_reference_path(const std::string& quantity, bool adhesionless, const std::string& against) {
  const std::string question = against.empty() || against == "surface" ? "" : against + "/";
  return reference::default_reference_dir() + "/challenge/" + question + (adhesionless ? "adhesionless/" : "") +
         quantity + ".csv";
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


}  // namespace cmc::check
