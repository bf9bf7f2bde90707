#include "cmc/output/JsonRead.hpp"

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

namespace cmc {

namespace {

// Nesting deeper than this is refused (summary.json nests 4 deep; the limit keeps a
// hostile file from exhausting the stack).
constexpr int kMaxDepth = 64;

class JsonParser {
 public:
  explicit JsonParser(std::string_view text) : s_(text) {}

  toml::table document() {
    skip_space();
    if (peek() != '{') fail("expected an object '{'");
    toml::table t = object(0);
    skip_space();
    if (i_ != s_.size()) fail("text after the object");
    return t;
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw JsonError("not cmc's JSON at byte " + std::to_string(i_) + ": " + why);
  }
  char peek() const { return i_ < s_.size() ? s_[i_] : '\0'; }
  void skip_space() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r')) ++i_;
  }
  void expect(char c) {
    skip_space();
    if (peek() != c) fail(std::string("expected '") + c + "'");
    ++i_;
  }
  bool literal(std::string_view word) {
    if (s_.substr(i_, word.size()) != word) return false;
    i_ += word.size();
    return true;
  }

  // The members of an object or the elements of an array: between `open` and `close`,
  // separated by commas, each read by `each`.
  template <class Each>
  void sequence(char open, char close, int depth, Each each) {
    if (depth > kMaxDepth) fail("nested too deeply");
    expect(open);
    skip_space();
    if (peek() == close) return void(++i_);
    for (;;) {
      each();
      skip_space();
      if (peek() != ',') break;
      ++i_;
    }
    expect(close);
  }
  toml::table object(int depth) {
    toml::table t;
    sequence('{', '}', depth, [&] {
      skip_space();
      if (peek() != '"') fail("expected a key in quotes");
      const std::string key = string();
      expect(':');
      if (t.contains(key)) fail("key \"" + key + "\" twice");
      value(depth, [&](auto&& v) { t.insert(key, std::forward<decltype(v)>(v)); });
    });
    return t;
  }
  toml::array array(int depth) {
    toml::array a;
    sequence('[', ']', depth, [&] { value(depth, [&](auto&& v) { a.push_back(std::forward<decltype(v)>(v)); }); });
    return a;
  }

  // One value, into a table under `key` or at the end of an array.
  template <class Put>
  void value(int depth, Put put) {
    skip_space();
    const char c = peek();
    if (c == '{') put(object(depth + 1));
    else if (c == '[') put(array(depth + 1));
    else if (c == '"') put(string());
    else if (literal("true")) put(true);
    else if (literal("false")) put(false);
    else if (c == '-' || (c >= '0' && c <= '9')) number(put);
    else if (literal("null")) fail("null (cmc writes none)");
    else fail("expected a value");
  }

  template <class Put>
  void number(Put put) {
    const std::size_t start = i_;
    if (peek() == '-') ++i_;
    bool is_float = false;
    while (i_ < s_.size()) {
      const char c = s_[i_];
      if (c == '.' || c == 'e' || c == 'E') is_float = true;
      else if (!(c >= '0' && c <= '9') && c != '+' && c != '-') break;
      ++i_;
    }
    const std::string text(s_.substr(start, i_ - start));
    char* end = nullptr;
    errno = 0;
    if (is_float) {
      const double d = std::strtod(text.c_str(), &end);
      if (end != text.c_str() + text.size()) fail("malformed number '" + text + "'");
      put(d);
    } else {
      const long long n = std::strtoll(text.c_str(), &end, 10);
      if (end != text.c_str() + text.size() || errno == ERANGE) fail("malformed whole number '" + text + "'");
      put(int64_t(n));
    }
  }

  std::string string() {
    ++i_;  // the opening quote
    std::string out;
    for (;;) {
      if (i_ >= s_.size()) fail("unterminated string");
      const char c = s_[i_++];
      if (c == '"') return out;
      if (static_cast<unsigned char>(c) < 0x20) fail("a control character in a string");
      if (c != '\\') {
        out += c;
        continue;
      }
      const char e = peek();
      ++i_;
      switch (e) {
        case '"': case '\\': case '/': out += e; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': utf8(code_point(), out); break;
        default: fail("unknown escape in a string");
      }
    }
  }
  unsigned hex4() {
    if (i_ + 4 > s_.size()) fail("short \\u escape");
    unsigned v = 0;
    for (int k = 0; k < 4; ++k) {
      const char c = s_[i_++];
      v = v * 16 + unsigned(c >= '0' && c <= '9'   ? c - '0'
                            : c >= 'a' && c <= 'f' ? c - 'a' + 10
                            : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                                   : (fail("malformed \\u escape"), 0));
    }
    return v;
  }
  // After "\u": one code point, a surrogate pair joined.
  unsigned code_point() {
    const unsigned hi = hex4();
    if (hi < 0xD800 || hi > 0xDFFF) return hi;
    if (hi > 0xDBFF || !literal("\\u")) fail("unpaired surrogate in a \\u escape");
    const unsigned lo = hex4();
    if (lo < 0xDC00 || lo > 0xDFFF) fail("unpaired surrogate in a \\u escape");
    return 0x10000 + ((hi - 0xD800) << 10) + (lo - 0xDC00);
  }
  static void utf8(unsigned cp, std::string& out) {
    if (cp < 0x80) {
      out += char(cp);
    } else if (cp < 0x800) {
      out += char(0xC0 | (cp >> 6)), out += char(0x80 | (cp & 0x3F));
    } else if (cp < 0x10000) {
      out += char(0xE0 | (cp >> 12)), out += char(0x80 | ((cp >> 6) & 0x3F)), out += char(0x80 | (cp & 0x3F));
    } else {
      out += char(0xF0 | (cp >> 18)), out += char(0x80 | ((cp >> 12) & 0x3F));
      out += char(0x80 | ((cp >> 6) & 0x3F)), out += char(0x80 | (cp & 0x3F));
    }
  }

  std::string_view s_;
  std::size_t i_ = 0;
};

}  // namespace

toml::table parse_json(std::string_view text) { return JsonParser(text).document(); }

toml::table read_json_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw JsonError(file.string() + ": cannot be read");
  std::ostringstream text;
  text << in.rdbuf();
  try {
    return parse_json(text.str());
  } catch (const JsonError& e) {
    throw JsonError(file.string() + ": " + e.what());
  }
}

}  // namespace cmc
