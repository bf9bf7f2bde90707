// The prediction checker (see Check.hpp and reference/README.md): the check of one
// prediction and its report (check.json, the printed summary).
#include "CheckParts.hpp"

#include "cmc/output/Writer.hpp"

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <tuple>

#include <toml++/toml.h>

namespace cmc::check {

using namespace parts;

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

void stored_reference(const Options& o, Report& r);

// The options' consistency and the reference file: --reference, else the stored one of a
// challenge quantity (--quantity), which must exist.
void resolve_reference(const Options& o, bool challenge, Report& r) {
  if (o.prediction.empty()) throw InputError("no prediction file given");
  if (!challenge && o.reference_file.empty())
    throw InputError("give --quantity Q (a challenge quantity) or --reference FILE (compare with a stored curve)");
  if (challenge) r.spec = quantity(o.quantity);
  r.prediction_file = o.prediction;
  r.reference_file = o.reference_file;
  if (o.adhesionless && !(challenge && r.reference_file.empty()))
    throw InputError("--adhesionless chooses the stored adhesionless reference of a challenge quantity: give it with "
                     "--quantity Q and without --reference");
  if (!o.against.empty() && !(challenge && r.reference_file.empty()))
    throw InputError("--against chooses which stored reference of a challenge quantity to score against: give it "
                     "with --quantity Q and without --reference");
  if (!o.against.empty() && o.against != "surface" && o.against != "ensemble" && o.against != "realisation")
    throw InputError("--against " + o.against + ": expected surface, ensemble or realisation");
  if (challenge && r.reference_file.empty()) stored_reference(o, r);
}

// The stored reference of a challenge quantity for the question asked (--against), or for a
// prediction whose surface is not stated: the realisation reference where it exists, else
// cmc's own surface, with a note.
void stored_reference(const Options& o, Report& r) {
  std::error_code ec;
  r.against = o.against.empty() ? "realisation" : o.against;
  r.reference_file = default_reference_path(o.quantity, o.adhesionless, r.against);
  if (o.against.empty() && !std::filesystem::exists(r.reference_file, ec)) {
    r.against = "surface";
    r.reference_file = default_reference_path(o.quantity, o.adhesionless, r.against);
    r.notes.push_back("no realisation reference is stored for this quantity: scored against cmc's own surface "
                      "(--against surface), whose band is numerical only");
  }
  if (!std::filesystem::exists(r.reference_file, ec))
    throw InputError("no stored " + std::string(o.adhesionless ? "adhesionless " : "") +
                     (r.against == "surface" ? "" : r.against + " ") + "reference for quantity '" + o.quantity +
                     "' yet (" + r.reference_file + " does not exist" +
                     (o.adhesionless ? "; the Tabor-parameter quantities have none, the Tabor parameter being one "
                                       "of adhesion"
                                     : "; challenge reference curves come from cmc runs") +
                     reference::reference_dir_note() + "): pass --reference FILE" +
                     (r.against == "surface" ? "" : " or another --against"));
}

// The quantity the reference curve holds: the challenge quantity asked for, or a generic
// one from the reference's header (its columns, or --x/--y).
void reference_spec(const Options& o, bool challenge, const Table& ref_table, const reference::Curve& ref_curve,
                    Report& r) {
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
}

// The coverage the prediction must reach, from the command line, else the reference, and
// where it comes from.
std::pair<double, std::string> coverage_rule(const Options& o, bool challenge, const Table& ref_table,
                                             const Report& r) {
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
  return {min_coverage, coverage_source};
}

// The verdict on the metric and tolerance that decide: the reference's error band, else
// --tolerance, else the reference file's, else the quantity's default.
Verdict tolerance_verdict(const Options& o, bool challenge, const reference::Curve& ref_curve, const Report& r) {
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
  return verdict(r.metrics, tol, metric, source);
}

// What the report says besides the numbers: columns not used, points left out, echoes.
void add_notes(Report& r) {
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
}

}  // namespace

Report run_check(const Options& o) {
  Report r;
  const bool challenge = !o.quantity.empty();
  resolve_reference(o, challenge, r);
  if (!o.metric.empty()) Metrics{}.get(o.metric);  // validates the name
  // Read both files before anything else, so every input error surfaces here.
  const Table ref_table = reference::read_csv(r.reference_file, 2);
  const reference::Curve ref_curve = reference::curve_from_table(ref_table);
  reference_spec(o, challenge, ref_table, ref_curve, r);
  const auto [min_coverage, coverage_source] = coverage_rule(o, challenge, ref_table, r);
  r.ref = extract(ref_table, r.spec, ref_curve.band);
  if (!ref_curve.band.empty()) r.band_words = ref_curve.estimated_error;
  std::tie(r.prediction, r.metrics) = score_prediction(o.prediction, o.columns, r.spec, r.ref);

  r.verdict = tolerance_verdict(o, challenge, ref_curve, r);
  Verdict& v = r.verdict;
  v.min_coverage = min_coverage;
  v.coverage_source = coverage_source;
  v.covered = r.metrics.coverage >= min_coverage;
  v.reason = nonpositive_reason(r);
  v.pass = v.pass && v.reason.empty();
  if (!v.covered) v.pass = false, v.reason += (v.reason.empty() ? "" : "; and ") + coverage_reason(r);
  add_notes(r);
  return r;
}

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
      {"against", r.against},
      {"band_words", r.band_words},
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

namespace {
// What each stored reference answers (--against), for the report.
std::string question_words(const std::string& against) {
  if (against == "ensemble") return "ensemble: the mean over all surfaces of the spectrum (for a theory)";
  if (against == "realisation")
    return "realisation: any one surface of the spectrum, e.g. the organisers' (for a run on a surface of its own)";
  return "surface: cmc's own realisation of the spectrum (for a run on the surface cmc surface --write gives)";
}

std::string shortened(const std::string& s, std::size_t n) { return s.size() <= n ? s : s.substr(0, n) + " ..."; }
}  // namespace

std::string report_text(const Report& r) {
  const Metrics& m = r.metrics;
  std::ostringstream s;
  const std::string absu = r.spec.rep.log_y ? "decades" : axis_unit(r.spec, false);
  s << "quantity        " << r.spec.id << (r.spec.item ? " (challenge item " + std::to_string(r.spec.item) + ")" : "")
    << "\n";
  s << "prediction      " << r.prediction_file << "  [" << r.prediction.x_column << ", " << r.prediction.y_column
    << "]\n";
  s << "reference       " << r.reference_file << "  [" << r.ref.x_column << ", " << r.ref.y_column << "]\n";
  if (!r.against.empty()) s << "against         " << question_words(r.against) << "\n";
  if (!r.band_words.empty()) s << "its band        " << shortened(r.band_words, 400) << "\n";
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
  const std::string measured =
      v.metric == "max_band"
          ? (within ? "inside the reference's error band (max_band = " + fmt(v.value) + " <= 1"
                    : "outside the reference's error band by up to " + fmt(v.value) + " times its half-width (at " +
                          fmt(m.x_at_max_band) + " " + axis_unit(r.spec, true)) +
                "; " + v.source + ")"
          : v.metric + " = " + fmt(v.value) + (within ? " <= " : " > ") + "tolerance " + fmt(v.tolerance) + " (" +
                v.source + ")";
  if (!v.pass && within && !v.reason.empty()) {
    // The error is within the tolerance: the reason for the FAIL comes first, the error after.
    s << "verdict         FAIL: " << v.reason << "\n";
    s << "                though " << measured << "\n";
  } else {
    s << "verdict         " << (v.pass ? "PASS" : "FAIL") << ": " << measured << "\n";
    if (!v.reason.empty()) s << "                FAIL: " << v.reason << "\n";
  }
  return s.str();
}

}  // namespace cmc::check
