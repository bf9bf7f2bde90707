// Predictions scored against reference curves from Python: `cmc check` (validation/Check.hpp),
// its report as the data check.json holds.
#include "bindings.hpp"

#include "Check.hpp"

#include <pybind11/stl.h>

#include <optional>
#include <string>

namespace cmcpy {

namespace py = pybind11;
namespace ck = cmc::check;

namespace {

// The column name a prediction in SI units takes for an axis: its first name, with the
// suffix of the SI unit ("mean_pressure_Pa", "contact_fraction").
std::string si_column(const ck::AxisSpec& a) {
  for (const ck::UnitChoice& u : ck::units(a.dim))
    if (u.to_si == 1.0) return a.bases.front() + (u.suffix.empty() ? "" : "_" + u.suffix);
  return a.bases.front();
}

// The whole check, as `cmc check PREDICTION --quantity Q [--reference FILE] ...` runs it,
// without writing anything: check.json's content as JSON text, and the printed summary.
py::tuple check(const std::string& prediction, const std::string& quantity, const std::string& reference,
                std::optional<double> tolerance, const std::string& metric, std::optional<double> min_coverage,
                bool adhesionless, const std::string& against) {
  const ck::Options o{.prediction = prediction, .quantity = quantity, .reference_file = reference, .x = {}, .y = {},
                      .metric = metric, .tolerance = tolerance, .min_coverage = min_coverage, .columns = {},
                      .adhesionless = adhesionless, .against = against};
  ck::Report r;
  {
    py::gil_scoped_release free;
    r = ck::run_check(o);
  }
  return py::make_tuple(ck::report_json(r), ck::report_text(r));
}

}  // namespace

void bind_check(py::module_& m) {
  m.def("check", &check, py::arg("prediction"), py::arg("quantity"), py::arg("reference"), py::arg("tolerance"),
        py::arg("metric"), py::arg("min_coverage"), py::arg("adhesionless"), py::arg("against"),
        "Score a prediction file: (check.json as JSON text, the summary `cmc check` prints).");
  m.def(
      "check_columns",
      [](const std::string& quantity) {
        const ck::QuantitySpec& q = ck::quantity(quantity);
        return py::make_tuple(si_column(q.x), si_column(q.y));
      },
      py::arg("quantity"), "The column names of a challenge quantity's axes in SI units.");
  m.def("check_quantities", [] {
    py::list ids;
    for (const auto& q : ck::quantities()) ids.append(q.id);
    return ids;
  });
}

}  // namespace cmcpy
