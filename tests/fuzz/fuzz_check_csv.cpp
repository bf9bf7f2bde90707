// libFuzzer target: the reader and scorer behind `cmc check` (validation/Check, with the
// CSV reader of validation/References), on any bytes taken as a prediction CSV.
//
// Per input: the table is read (reference::parse_csv, as cmc check reads a prediction),
// then scored as a prediction of every challenge quantity against its stored reference
// curve (reference/challenge/*.csv, read once; a fixed synthetic curve for quantities
// without one): column choice and units (extract), comparison (compare), verdict and both
// reports. The same bytes are also streamed as `cmc check` reads a prediction (any
// separator, with or without a header: run_check for each quantity with a stored
// reference), and taken as a reference file in cmc's format (the generic `cmc check FILE
// --reference FILE` path, through run_check; a '# band:' column included).
//
// Bad input must end in an InputError (the documented error, exit code 2); anything else
// thrown is a finding. A comparison that succeeds must keep compare()'s promises:
// at least two evaluation points inside a non-empty common range, finite non-negative
// errors.
#include "FuzzInput.hpp"

#include "Check.hpp"

#include <cmath>
#include <exception>
#include <filesystem>
#include <map>
#include <string>

namespace {

using namespace cmc;
using cmc::fuzz::require;

// The reference curve of each quantity, in SI, read once.
const std::map<std::string, check::XY>& references() {
  static const std::map<std::string, check::XY> refs = [] {
    std::map<std::string, check::XY> r;
    for (const auto& q : check::quantities()) {
      const std::string path = check::default_reference_path(q.id);
      std::error_code ec;
      if (std::filesystem::exists(path, ec)) {
        r[q.id] = check::extract(reference::read_csv(path, 2), q);
        continue;
      }
      // No stored curve: a positive curve over a wide range of SI values, so that most
      // predictions overlap it on either axis scale.
      check::XY xy;
      xy.file = "synthetic reference for " + q.id;
      xy.x_column = q.x.bases.front();
      xy.y_column = q.y.bases.front();
      for (int i = 0; i < 60; ++i) {
        xy.x.push_back(std::pow(10.0, -15.0 + 0.5 * i));
        xy.y.push_back(std::pow(10.0, std::sin(0.3 * i)));
        xy.line.push_back(i + 1);
      }
      r[q.id] = xy;
    }
    return r;
  }();
  return refs;
}

void check_metrics(const check::Metrics& m, const std::string& what) {
  require(m.points >= 2, what + ": fewer than two evaluation points");
  require(m.x_lo <= m.x_hi, what + ": empty common range");
  for (double v : {m.max_abs, m.rms_abs, m.max_rel, m.rms_rel})
    require(std::isfinite(v) && v >= 0, what + ": error measure not finite and non-negative");
  // Every point, or (a streamed prediction, run_check) an even sample of at most
  // kMaxEchoedRows and the last one.
  const std::size_t n = m.eval_echo_stride == 1 ? m.points : m.eval_x.size();
  require(n <= m.points && (m.eval_echo_stride == 1 || n <= check::kMaxEchoedRows + 1),
          what + ": evaluation sample larger than the points or the cap");
  require(m.eval_x.size() == n && m.eval_pred.size() == n && m.eval_ref.size() == n,
          what + ": evaluation arrays of the wrong length");
  require(!m.has_band || (m.eval_lo.size() == n && m.eval_hi.size() == n && std::isfinite(m.max_band) && m.max_band >= 0),
          what + ": band arrays of the wrong length, or max_band not finite and non-negative");
}

template <class F>
void expect_input_error_or_ok(const std::string& what, F&& f) {
  try {
    f();
  } catch (const check::InputError&) {
    // bad input, reported as such
  } catch (const std::exception& e) {
    cmc::fuzz::fail(what + " threw something other than InputError: " + e.what());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static cmc::fuzz::TempFile file("reference.csv");
  const std::string text(cmc::fuzz::as_text(data, size));
  const auto& refs = references();
  expect_input_error_or_ok("parse_csv", [&] {
    const reference::Table t = reference::parse_csv(text, "prediction.csv", 2);
    for (const auto& q : check::quantities()) {
      expect_input_error_or_ok("scoring as " + q.id, [&] {
        check::Report r;
        r.spec = q;
        r.prediction_file = t.file;
        r.prediction = check::extract(t, q);
        r.ref = refs.at(q.id);
        r.metrics = check::compare(r.prediction, r.ref, q.rep);
        check_metrics(r.metrics, q.id);
        r.verdict = check::verdict(r.metrics, q.tolerance, q.metric, "default for " + q.id);
        require(!check::report_json(r).empty() && !check::report_text(r).empty(), "empty report");
      });
    }
  });
  // The same bytes as a prediction the way cmc check streams it (the submissions'
  // layouts: any separator, with or without a header row), against two stored references
  // (log-log and lin-log; each run_check reads its reference file, so not all of them).
  file.write(text);
  for (const char* id : {"gap_distribution", "stress_distribution"}) {
    const check::QuantitySpec& q = check::quantity(id);
    std::error_code ec;
    if (!std::filesystem::exists(check::default_reference_path(q.id), ec)) continue;
    expect_input_error_or_ok("run_check as " + q.id, [&] {
      check::Options o;
      o.prediction = file.path();
      o.quantity = q.id;
      const check::Report r = check::run_check(o);
      check_metrics(r.metrics, "run_check as " + q.id);
    });
  }
  // The same bytes as a reference file (the generic path of cmc check).
  file.write(text);
  expect_input_error_or_ok("run_check with the input as reference", [&] {
    check::Options o;
    o.prediction = o.reference_file = file.path();
    o.tolerance = 0.1;
    const check::Report r = check::run_check(o);
    check_metrics(r.metrics, "generic check");
    require(r.metrics.max_abs == 0, "a curve compared with itself has errors");
    require(!r.metrics.has_band || r.metrics.max_band == 0, "a curve compared with itself lies outside its band");
    require(!check::report_json(r).empty() && !check::report_text(r).empty(), "empty report");
  });
  return 0;
}
