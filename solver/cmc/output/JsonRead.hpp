// Reading back the JSON cmc writes (summary.json, written by to_json, Writer.hpp): a
// finished run's record, read by the commands that reuse finished runs (`cmc sweep`).
//
// JSON maps onto toml++'s tables as to_json writes them: objects -> tables, arrays ->
// arrays, strings, true/false, and numbers as integers (no '.', 'e' or 'E') or doubles,
// each read exactly (strtod of the 17 digits to_json writes gives the same double back,
// so to_json of what is read reproduces the text). null has no TOML counterpart and
// cmc never writes it: refused, as is anything else that is not JSON. NaN and the
// infinities stay the strings to_json writes for them ("NaN", "Infinity", "-Infinity").
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string_view>

#include <toml++/toml.h>

namespace cmc {

// Text that is not JSON of this kind: the message says where (byte offset) and why.
struct JsonError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The object `text` holds (JsonError when it is not one object and nothing after it).
toml::table parse_json(std::string_view text);

// parse_json of a file's contents; JsonError naming the file when it cannot be read or parsed.
toml::table read_json_file(const std::filesystem::path& file);

}  // namespace cmc
