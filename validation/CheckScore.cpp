// Scoring a prediction against a reference curve (Check.hpp, "Scoring"): the errors in the
// representation the challenge asks for, streamed over the prediction's rows.
#include "CheckParts.hpp"
#include "Sampler.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

namespace cmc::check {

using namespace parts;

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

namespace parts {

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

}  // namespace parts

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


}  // namespace cmc::check
