// Reference curves as CSV files: the header (Table) and the reader of curves and of
// submitted predictions (CsvReader), see References.hpp and reference/README.md.
#include "ReferenceParts.hpp"

#include "cmc/grid/FilePaths.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace cmc::reference {

using namespace parts;

namespace {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == sep) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

std::string where(const std::string& file, int line) { return file + ":" + std::to_string(line) + ": "; }

}  // namespace

std::optional<std::string> Table::get(const std::string& key) const {
  for (const auto& [k, v] : meta)
    if (k == key) return v;
  return std::nullopt;
}

std::string Table::require(const std::string& key) const {
  auto v = get(key);
  if (!v || v->empty())
    throw InputError(file + ": the metadata line '# " + key + ": ...' is missing (see reference/README.md)");
  return *v;
}

void Table::set(const std::string& key, const std::string& value) {
  for (auto& [k, v] : meta)
    if (k == key) {
      v = value;
      return;
    }
  meta.emplace_back(key, value);
}

int Table::column_index(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return int(i);
  return -1;
}

const std::vector<double>& Table::column(const std::string& name) const {
  const int i = column_index(name);
  if (i < 0) {
    std::string have;
    for (const auto& c : columns) have += (have.empty() ? "" : ", ") + c;
    throw InputError(file + ":" + std::to_string(header_line) + ": no column '" + name + "' (the header has: " +
                     have + ")");
  }
  return data[std::size_t(i)];
}

namespace {
// A whole field that strtod reads as a number.
bool is_number(const std::string& f) {
  char* end = nullptr;
  std::strtod(f.c_str(), &end);
  return !f.empty() && end && *end == '\0';
}
const char* separator_name(char sep) {
  return sep == ',' ? "comma" : sep == ';' ? "semicolon" : "whitespace";
}
}  // namespace

std::vector<std::string> CsvReader::fields(const std::string& s) const {
  if (sep_ != ' ') return split(s, sep_);
  std::vector<std::string> out;
  std::size_t b = s.find_first_not_of(" \t");
  while (b != std::string::npos) {
    const std::size_t e = s.find_first_of(" \t", b);
    out.push_back(s.substr(b, e == std::string::npos ? std::string::npos : e - b));
    b = e == std::string::npos ? e : s.find_first_not_of(" \t", e);
  }
  return out;
}

CsvReader::CsvReader(std::istream& in, std::string file, bool keep_comments, Layout layout)
    : in_(in), keep_comments_(keep_comments), layout_(std::move(layout)) {
  t_.file = std::move(file);
  std::string raw;
  while (read_line(raw)) {
    if (line_ == 1 && raw.size() >= 3 && raw.compare(0, 3, "\xEF\xBB\xBF") == 0) raw.erase(0, 3);  // UTF-8 BOM
    const std::string s = trim(raw);
    if (s.empty()) continue;
    if (s[0] == '#') {
      const std::string body = trim(s.substr(1));
      const auto colon = body.find(':');
      if (colon != std::string::npos && valid_key(trim(body.substr(0, colon))))
        t_.set(trim(body.substr(0, colon)), trim(body.substr(colon + 1)));
      else
        t_.comments.push_back(body);
      continue;
    }
    if (layout_.any_separator)
      sep_ = s.find(',') != std::string::npos ? ',' : s.find(';') != std::string::npos ? ';' : ' ';
    auto fields = this->fields(s);
    have_header_ = true;
    t_.header_line = line_;
    bool numbers = layout_.any_separator;
    for (const auto& f : fields) numbers = numbers && is_number(trim(f));
    if (numbers) {  // no header row: this line is the first data row
      if (layout_.columns.empty())
        throw InputError(where(t_.file, line_) + "the file has no header row (this line is " +
                         std::to_string(fields.size()) + " numbers); name its columns with --columns, e.g. "
                         "--columns pressure_Pa,contact_fraction (cmc check --list gives the names)");
      if (layout_.columns.size() != fields.size())
        throw InputError(where(t_.file, line_) + "--columns names " + std::to_string(layout_.columns.size()) +
                         " columns, the file's rows have " + std::to_string(fields.size()) + " " +
                         separator_name(sep_) + "-separated values");
      pending_ = s, pending_line_ = line_;
      fields = layout_.columns;
    } else if (!layout_.columns.empty()) {
      if (layout_.columns.size() != fields.size())
        throw InputError(where(t_.file, line_) + "--columns names " + std::to_string(layout_.columns.size()) +
                         " columns, the header row has " + std::to_string(fields.size()));
      fields = layout_.columns;
    }
    for (std::size_t k = 0; k < fields.size(); ++k) {
      const std::string name = trim(fields[k]);
      if (name.empty())
        throw InputError(where(t_.file, line_) + "header row: column " + std::to_string(k + 1) +
                         " has no name (expected comma-separated column names, e.g. "
                         "'pressure_Pa,contact_fraction')");
      if (is_number(name))
        throw InputError(where(t_.file, line_) + "header row: column " + std::to_string(k + 1) + " is the number '" +
                         name + "', expected a column name: the file needs a header row naming its columns, "
                         "e.g. 'pressure_Pa,contact_fraction'");
      if (std::find(t_.columns.begin(), t_.columns.end(), name) != t_.columns.end())
        throw InputError(where(t_.file, line_) + "header row: column name '" + name + "' appears twice");
      t_.columns.push_back(name);
    }
    if (t_.columns.size() < 2) {
      const bool other_sep = s.find_first_of("\t;") != std::string::npos || s.find(' ') != std::string::npos;
      throw InputError(where(t_.file, line_) + "header row '" + s + "' names one column; expected at least two, "
                       "separated by commas" + (layout_.any_separator ? ", semicolons, tabs or spaces"
                                                : other_sep ? " (tabs, spaces and semicolons are not separators)" : ""));
    }
    t_.data.assign(t_.columns.size(), {});
    return;
  }
}

bool CsvReader::read_line(std::string& raw) {
  raw.clear();
  std::streambuf* sb = in_.rdbuf();
  bool any = false;
  for (int ch = sb->sbumpc(); ch != std::char_traits<char>::eof(); ch = sb->sbumpc()) {
    any = true;
    if (ch == '\n') break;
    if (raw.size() >= kMaxLineBytes)
      throw InputError(where(t_.file, line_ + 1) + "line longer than " + std::to_string(kMaxLineBytes) +
                       " bytes (not a CSV file of numbers?)");
    raw.push_back(char(ch));
  }
  if (!any) return false;
  ++line_;
  return true;
}

bool CsvReader::next(std::vector<double>& values, int& line) {
  std::string raw;
  while (!pending_.empty() || read_line(raw)) {
    int at = line_;
    if (!pending_.empty()) raw = std::move(pending_), pending_.clear(), at = pending_line_;
    const std::string s = trim(raw);
    if (s.empty()) continue;
    if (s[0] == '#') {
      if (keep_comments_) t_.comments.push_back(trim(s.substr(1)));
      continue;
    }
    const auto fields = this->fields(s);
    if (fields.size() != t_.columns.size())
      throw InputError(where(t_.file, at) + "expected " + std::to_string(t_.columns.size()) + " " +
                       separator_name(sep_) + "-separated values (as in the header row, line " +
                       std::to_string(t_.header_line) + "), found " + std::to_string(fields.size()));
    values.resize(fields.size());
    for (std::size_t k = 0; k < fields.size(); ++k) {
      const std::string f = trim(fields[k]);
      const std::string col = "column " + std::to_string(k + 1) + " ('" + t_.columns[k] + "'): ";
      if (f.empty()) throw InputError(where(t_.file, at) + col + "empty field, expected a number");
      errno = 0;
      char* end = nullptr;
      const double v = std::strtod(f.c_str(), &end);
      if (end == f.c_str() || *end != '\0')
        throw InputError(where(t_.file, at) + col + "'" + f + "' is not a number");
      if (!std::isfinite(v) || (errno == ERANGE && std::abs(v) > 1))
        throw InputError(where(t_.file, at) + col + "'" + f +
                         "' is not a finite number (NaN and infinity are not allowed)");
      values[k] = v;
    }
    line = at;
    return true;
  }
  return false;
}

void CsvReader::fail_no_header() const {
  throw InputError(t_.file + ": " + (line_ == 0 ? "the file is empty" : "the file has no header row and no data") +
                   " (expected a header row naming the columns, then one row of numbers per point)");
}

void CsvReader::fail_rows(std::size_t rows, std::size_t min_rows) const {
  throw InputError(t_.file + ": " + std::to_string(rows) + " data row" + (rows == 1 ? "" : "s") +
                   " after the header row (line " + std::to_string(t_.header_line) + "); expected at least " +
                   std::to_string(min_rows));
}

Table parse_csv(const std::string& text, const std::string& file, std::size_t min_rows) {
  std::istringstream in(text);
  CsvReader reader(in, file);
  if (!reader.has_header()) reader.fail_no_header();
  Table t = reader.header();
  std::vector<double> row;
  int line = 0;
  while (reader.next(row, line)) {
    for (std::size_t k = 0; k < row.size(); ++k) t.data[k].push_back(row[k]);
    t.row_line.push_back(line);
  }
  t.comments = reader.header().comments;  // including those after the header
  if (t.rows() < min_rows) reader.fail_rows(t.rows(), min_rows);
  return t;
}

std::ifstream open_csv(const std::string& path) {
  if (const std::string why = input_file_problem(path); !why.empty()) throw InputError(path + ": " + why);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot be read");
  return in;
}

Table read_csv(const std::string& path, std::size_t min_rows) {
  std::ifstream in = open_csv(path);
  std::ostringstream s;
  s << in.rdbuf();
  return parse_csv(s.str(), path, min_rows);
}

}  // namespace cmc::reference
