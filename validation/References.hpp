// Reference curves: the one CSV format cmc stores curves in (reference/*.csv), its
// reader and writer, and the generators of the analytic curves.
//
// The format (documented for users in reference/README.md):
//
//   # cmc-reference-csv: 1
//   # name: hertz_penetration_force          <- file stem, [a-z0-9_.-]
//   # quantity: ...                          <- what the curve is (a `cmc check` quantity
//   #                                           for challenge curves)
//   # title: ...                             <- one line for humans
//   # source: analytic: <formula, citation>  |  cmc run: <how>
//   # ... further "# key: value" lines (parameters, cmc_version, case_file, grid, date)
//   # unit.<column>: <unit> (<meaning>)     <- one per column
//   # columns: c1,c2,...
//   # x: c1                                  <- default abscissa / ordinate
//   # y: c2
//   # representation: log-log               <- x-y axis scales: lin-lin, log-lin, lin-log, log-log
//   # estimated_error: ...
//   # tolerance: 1e-3                        <- acceptance for a comparison with this curve
//   # tolerance_metric: max_rel              <- max_abs | rms_abs | max_rel | rms_rel (see Check.hpp)
//   c1,c2,...                                <- header row
//   1.000000000000e-04,2.000000000000e-03    <- data, "%.12e", one row per point
//
// Analytic curves contain no date and no version, so regenerating them reproduces the
// stored file byte for byte (tests/test_references.cpp enforces it).
#pragma once

#include <fstream>
#include <istream>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace cmc::reference {

// A malformed file or argument: the message names the file, the line and column, and
// what was expected. `cmc` maps it to exit code 2.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

using Meta = std::vector<std::pair<std::string, std::string>>;

// A parsed CSV table: "# key: value" metadata, the header row and the numbers (one vector
// per column). Also used for predictions handed to `cmc check` (metadata optional there).
struct Table {
  std::string file;                   // for messages
  Meta meta;                          // in file order
  std::vector<std::string> comments;  // '#' lines that are not "key: value"
  std::vector<std::string> columns;
  std::vector<std::vector<double>> data;  // data[column][row]
  std::vector<int> row_line;              // 1-based file line of each row
  int header_line = 0;

  std::size_t rows() const { return data.empty() ? 0 : data.front().size(); }
  std::optional<std::string> get(const std::string& key) const;
  std::string require(const std::string& key) const;  // throws InputError naming the file
  void set(const std::string& key, const std::string& value);  // replaces or appends
  int column_index(const std::string& name) const;             // -1 if absent
  const std::vector<double>& column(const std::string& name) const;  // throws InputError
};

// Parse CSV text. Rules: '#' lines are comments ("# key: value" ones are metadata);
// blank lines are skipped; the first other line is the header row (comma-separated,
// non-empty, distinct names); every data row has as many fields as the header, each a
// finite number (strtod, whole field). At least `min_rows` data rows. Errors throw
// InputError("FILE:LINE: column K ('name'): ...").
Table parse_csv(const std::string& text, const std::string& file, std::size_t min_rows = 1);
Table read_csv(const std::string& path, std::size_t min_rows = 1);  // file missing: InputError

// The same rules, one row at a time, for files too large to hold (`cmc check` streams a
// prediction through it): the constructor reads up to and including the header row,
// next() the following data rows. Lines longer than kMaxLineBytes are an error.
//
// A prediction (`cmc check`) may use the layouts that the challenge's participants
// submitted (Layout::submissions): values separated by commas, semicolons, tabs or spaces
// (the header row decides, and data rows follow it), and a file without a header row
// (its first non-comment line is all numbers) when `columns` names its columns.
struct Layout {
  bool any_separator = false;        // else commas only (cmc's own CSV files)
  std::vector<std::string> columns;  // names for a file without a header row; given with
                                     // a header row, they must match its column count and replace it
  static Layout submissions(std::vector<std::string> columns = {}) { return {true, std::move(columns)}; }
};

class CsvReader {
 public:
  static constexpr std::size_t kMaxLineBytes = 1 << 20;
  // keep_comments: also keep '#' lines after the header in header().comments (a
  // streaming reader passes false, so that its memory does not grow with the file).
  CsvReader(std::istream& in, std::string file, bool keep_comments = true, Layout layout = {});
  // Metadata, comments before the header, the columns and the header's line; no data.
  const Table& header() const { return t_; }
  bool has_header() const { return have_header_; }
  // The next data row (one value per column) and its 1-based line; false at the end.
  bool next(std::vector<double>& values, int& line);
  int lines() const { return line_; }  // lines read so far
  // The error of a file without a header row ("the file is empty" ...).
  [[noreturn]] void fail_no_header() const;
  // The error of a file with fewer than min_rows data rows after its header.
  [[noreturn]] void fail_rows(std::size_t rows, std::size_t min_rows) const;

 private:
  bool read_line(std::string& raw);
  std::vector<std::string> fields(const std::string& s) const;  // split at the separator
  std::istream& in_;
  Table t_;
  int line_ = 0;
  bool have_header_ = false, keep_comments_ = true;
  Layout layout_;
  char sep_ = ',';  // ' ' means runs of spaces and tabs
  std::string pending_;  // a headerless file's first data row
  int pending_line_ = 0;
};
// Opens `path` for a CsvReader: a regular file, else InputError.
std::ifstream open_csv(const std::string& path);

// ---- curves with metadata ------------------------------------------------------------
struct Column {
  std::string name, unit, meaning;
  std::vector<double> values;
};

struct Curve {
  std::string name, quantity, title, source;
  Meta extra;  // written after `source`, in this order (parameters, case_file, grid, date, ...)
  std::vector<Column> columns;
  std::string x, y;               // default abscissa and ordinate (column names)
  std::string representation;     // lin-lin | log-lin | lin-log | log-log (x-y)
  std::string estimated_error;    // free text with a number and what it bounds
  std::optional<double> tolerance;
  std::string tolerance_metric = "max_rel";
  // The column holding the reference's own uncertainty of y ("# band: <column>"): a
  // half-width > 0 in y's unit at every row (y ± band). Empty: no band. `cmc check`
  // scores a prediction in units of it where it is given.
  std::string band;
};

// The file text of a curve (deterministic: fixed key order, "%.12e", no trailing spaces).
// Throws std::invalid_argument for missing metadata, unequal column lengths, a name
// with a comma or newline, or a non-finite value.
std::string format_curve(const Curve& c);
void write_curve(const std::string& path, const Curve& c);  // atomically
// The inverse of format_curve for files in the format (metadata checked).
Curve curve_from_table(const Table& t);
Curve read_curve(const std::string& path);

// Axis scales of a representation string ("log-log" -> {true, true}); throws InputError.
struct Representation {
  bool log_x = false, log_y = false;
};
Representation parse_representation(const std::string& s);

// ---- curves from cmc runs (challenge references) -------------------------------------
// A curve produced by a cmc run: source "cmc run", with the version, case file, grid,
// solver tolerance, date (UTC, ISO 8601) and the estimated discretisation error.
struct RunProvenance {
  std::string cmc_version;  // empty: this build's CMC_VERSION
  std::string case_file;
  std::string grid;         // e.g. "4096x4096, dx = 24.4 nm (lambda_s/4.1)"
  std::string solver_tolerance;
  std::string date;         // empty: now
  std::string command;      // how it was produced, e.g. "cmc run cases/challenge/... --out ..."
};
Curve make_run_curve(const std::string& name, const std::string& quantity, const std::string& title,
                     const RunProvenance& how, std::vector<Column> columns, const std::string& x,
                     const std::string& y, const std::string& representation,
                     const std::string& estimated_error, std::optional<double> tolerance,
                     const std::string& tolerance_metric = "max_rel");

// ---- analytic curves -----------------------------------------------------------------
// Every analytic curve, in a fixed order; `generate` builds one by name (throws
// std::invalid_argument for an unknown name).
std::vector<std::string> analytic_curve_names();
std::string analytic_curve_title(const std::string& name);
Curve generate(const std::string& name);

// The folder holding the stored curves: $CMC_REFERENCE_DIR, else reference/ in cmc's data
// folder (input/DataDir.hpp: the source checkout, or PREFIX/share/cmc once installed).
std::string default_reference_dir();

// "" when default_reference_dir() is set or found, else "; ..." saying where it was looked for.
std::string reference_dir_note();

}  // namespace cmc::reference
