// parse_json (output/JsonRead.hpp): cmc's JSON read back exactly, anything else refused.
#include "cmc/output/JsonRead.hpp"
#include "cmc/output/Writer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace cmc;

namespace {
// A table of every kind summary.json holds, with doubles that need all 17 digits.
toml::table sample() {
  toml::table step{{"index", 0},
                   {"converged", true},
                   {"jump", false},
                   {"mean_gap", 1.0027458531842158e-06},
                   {"tolerance", 0.1 + 0.2},
                   {"n_patches", 3374.0},
                   {"message", "quote \" backslash \\ tab \t newline \n µm"},
                   {"observables", toml::table{{"contact_fraction", 0.026139020919799805}}}};
  return toml::table{{"cmc_version", "0.1.0"},
                     {"grid", toml::table{{"nx", 2048}, {"size_x", 1e-4}}},
                     {"steps", toml::array{step, toml::table{}}},
                     {"warnings", toml::array{}},
                     {"values", toml::array{250000.0, -3.5e-300, 7}}};
}
}  // namespace

TEST(JsonRead, ReadsBackWhatToJsonWrites) {
  const std::string text = to_json(sample());
  const toml::table t = parse_json(text);
  EXPECT_EQ(to_json(t), text);  // every value, digit for digit
  EXPECT_EQ(t["grid"]["nx"].value<int64_t>(), 2048);
  EXPECT_EQ(t["steps"][0]["mean_gap"].value<double>(), 1.0027458531842158e-06);
  EXPECT_EQ(t["steps"][0]["tolerance"].value<double>(), 0.1 + 0.2);
  EXPECT_TRUE(t["steps"][0]["n_patches"].is_floating_point());  // 3374.0 stays a double
  EXPECT_EQ(t["steps"][0]["message"].value<std::string>(), "quote \" backslash \\ tab \t newline \n µm");
  EXPECT_EQ(t["steps"][0]["converged"].value<bool>(), true);
}

TEST(JsonRead, NotANumberStaysTheStringToJsonWrites) {
  const std::string text = to_json(toml::table{{"x", std::numeric_limits<double>::quiet_NaN()}});
  const toml::table t = parse_json(text);
  EXPECT_EQ(to_json(t), text);
}

TEST(JsonRead, UnicodeEscapes) {
  const toml::table t = parse_json(R"({"a": "\u00b5m \ud83d\ude00 \/"})");
  EXPECT_EQ(t["a"].value<std::string>(), "\xc2\xb5m \xf0\x9f\x98\x80 /");
}

TEST(JsonRead, RefusesWhatIsNotCmcJson) {
  for (const char* bad : {"", "[1, 2]", "{", "{\"a\": }", "{\"a\": 1,}", "{\"a\": 1} x", "{\"a\": null}",
                          "{\"a\": 1, \"a\": 2}", "{\"a\": \"\\x\"}", "{\"a\": \"\\ud83d\"}", "{\"a\": 1.2.3}",
                          "{\"a\": 99999999999999999999}", "{\"a\": \"unterminated}", "{a: 1}"})
    EXPECT_THROW(parse_json(bad), JsonError) << bad;
  std::string deep = "{\"a\": ";
  for (int i = 0; i < 100; ++i) deep += "[";
  EXPECT_THROW(parse_json(deep), JsonError);  // nested too deeply, not a stack overflow
}

TEST(JsonRead, FileErrorsNameTheFile) {
  try {
    read_json_file("/nonexistent/summary.json");
    FAIL() << "no error";
  } catch (const JsonError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/summary.json"), std::string::npos) << e.what();
  }
}
