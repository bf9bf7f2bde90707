// The prediction checker's pieces shared by its files (Check.cpp: the check and its
// report; CheckColumns.cpp: quantities, units and column names; CheckScore.cpp: the
// scoring). Internal to the checker.
#pragma once

#include "Check.hpp"

#include <string>
#include <utility>
#include <vector>

namespace cmc::check::parts {

// A number as messages and reports write it (6 significant digits).
std::string fmt(double v);
// The SI unit of an axis of `s` ("as in the files" for a generic curve).
std::string axis_unit(const QuantitySpec& s, bool x);
// "column 2 ('pressure_Pa')"
std::string col_ref(const Table& t, int k);
// A non-monotonic or repeated abscissa at `line` (x after xprev of line_prev).
[[noreturn]] void fail_monotonic(const Table& t, const QuantitySpec& spec, int column, double x, double xprev,
                                 int line, int line_prev, bool increasing);
// The curve's columns and units: the axes of `spec` in the header of `t`.
XY axes_of(const Table& t, const QuantitySpec& spec, int& xcol, int& ycol);
// The prediction file, streamed row by row through the scorer: the same checks and
// messages as extract() + compare() on the whole table, with memory bounded by the
// reference and kMaxEchoedRows. Returns the sampled curve and the metrics.
std::pair<XY, Metrics> score_prediction(const std::string& path, const std::vector<std::string>& columns,
                                        const QuantitySpec& spec, const XY& ref);

}  // namespace cmc::check::parts
