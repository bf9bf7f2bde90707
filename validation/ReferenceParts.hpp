// Pieces of the reference-curve code shared by its files (CsvReader.cpp: the CSV reader;
// References.cpp: curves as files; AnalyticCurves.cpp: the analytic generators).
// Internal to the references.
#pragma once

#include "References.hpp"

#include <cctype>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace cmc::reference::parts {

inline std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

// Short form for metadata (numbers quoted in headers, not data).
inline std::string short_num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", v == 0 ? 0.0 : v);
  return buf;
}

// A header key: letters, digits, '_', '.' and '-'.
inline bool valid_key(const std::string& k) {
  if (k.empty()) return false;
  for (char c : k)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-')) return false;
  return true;
}

// The part every curve ends with: its columns, axes, representation, error statement
// and tolerance.
Curve with_axes(Curve c, std::vector<Column> columns, const std::string& x, const std::string& y,
                const std::string& representation, const std::string& estimated_error, std::optional<double> tolerance,
                const std::string& tolerance_metric);

}  // namespace cmc::reference::parts
