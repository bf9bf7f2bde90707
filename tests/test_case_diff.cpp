// compare_cases (output/CaseDiff.hpp): which checkpoints a resumed run may continue.
#include "cmc/input/Case.hpp"
#include "cmc/output/CaseDiff.hpp"
#include "cmc/output/Writer.hpp"

#include <gtest/gtest.h>

#include <toml++/toml.h>

using namespace cmc;

namespace {
toml::table resolved_case() {
  return toml::table{{"case", toml::table{{"name", "x"}}},
                     {"grid", toml::table{{"n", 64}, {"size", 1e-4}, {"boundary", "periodic"}, {"backend", "cpu"}}},
                     {"loading", toml::table{{"values", toml::array{2.5e5, 3e5}}, {"max_halvings", 5}}}};
}
}  // namespace

TEST(CaseDiff, SameCaseIsSame) {
  const std::string j = to_json(resolved_case());
  const CaseDiff d = compare_cases(j, j);
  EXPECT_TRUE(d.same()) << d.mismatch;
  EXPECT_TRUE(d.defaulted.empty());
}

// A checkpoint written before grid.backend existed: accepted, and the key is reported.
TEST(CaseDiff, NewKeyAtItsDefaultIsAccepted) {
  toml::table old = resolved_case();
  old["grid"].as_table()->erase("backend");
  const CaseDiff d = compare_cases(to_json(old), to_json(resolved_case()));
  EXPECT_TRUE(d.same()) << d.mismatch;
  ASSERT_EQ(d.defaulted.size(), 1u);
  EXPECT_EQ(d.defaulted[0], "grid.backend = \"cpu\"");
}

// ... but not at another value, and a key with no documented default is never assumed.
TEST(CaseDiff, NewKeyAwayFromItsDefaultIsRefused) {
  toml::table old = resolved_case();
  old["grid"].as_table()->erase("backend");
  toml::table now = resolved_case();
  now["grid"].as_table()->insert_or_assign("backend", "cuda");
  const CaseDiff d = compare_cases(to_json(old), to_json(now));
  EXPECT_FALSE(d.same());
  EXPECT_NE(d.mismatch.find("grid.backend"), std::string::npos) << d.mismatch;
  now = resolved_case();
  now["grid"].as_table()->insert_or_assign("invented", 1);
  EXPECT_FALSE(compare_cases(to_json(resolved_case()), to_json(now)).same());
}

// Another --set: refused, naming the key and both values; arrays compared whole.
TEST(CaseDiff, ChangedValueIsNamed) {
  toml::table now = resolved_case();
  now["grid"].as_table()->insert_or_assign("n", 128);
  const CaseDiff d = compare_cases(to_json(resolved_case()), to_json(now));
  EXPECT_EQ(d.mismatch, "key grid.n: 64 in the checkpoint, 128 here");
  now = resolved_case();
  now["loading"].as_table()->insert_or_assign("values", toml::array{2.5e5, 3.5e5});
  const CaseDiff a = compare_cases(to_json(resolved_case()), to_json(now));
  EXPECT_NE(a.mismatch.find("loading.values"), std::string::npos) << a.mismatch;
  // A key the checkpoint has and this version lacks is a difference too.
  now = resolved_case();
  now["loading"].as_table()->erase("max_halvings");
  EXPECT_NE(compare_cases(to_json(resolved_case()), to_json(now)).mismatch.find("loading.max_halvings"),
            std::string::npos);
}

// The description is free text: reported, not refused; the name is not.
TEST(CaseDiff, AnotherDescriptionIsReportedNotRefused) {
  toml::table was = resolved_case();
  was["case"].as_table()->insert_or_assign("description", "old words");
  toml::table now = resolved_case();
  now["case"].as_table()->insert_or_assign("description", "new words");
  const CaseDiff d = compare_cases(to_json(was), to_json(now));
  EXPECT_TRUE(d.same()) << d.mismatch;
  ASSERT_EQ(d.text_changed.size(), 1u);
  EXPECT_EQ(d.text_changed[0], "case.description");
  now["case"].as_table()->insert_or_assign("name", "y");
  EXPECT_EQ(compare_cases(to_json(was), to_json(now)).mismatch.rfind("key case.name", 0), 0u);
}

// A stopping limit may change (the caller checks that the checkpoint has not reached it):
// listed with both values, not refused; also when the checkpoint predates the key.
TEST(CaseDiff, StoppingLimitIsListedNotRefused) {
  toml::table was = resolved_case();
  was.insert_or_assign("solver", toml::table{{"max_outer_steps", 1000}, {"tension_tolerance", 1e-3}});
  toml::table now = was;
  now["solver"].as_table()->insert_or_assign("max_outer_steps", 400);
  CaseDiff d = compare_cases(to_json(was), to_json(now));
  EXPECT_TRUE(d.same()) << d.mismatch;
  ASSERT_EQ(d.limits_changed.size(), 1u);
  EXPECT_EQ(d.limits_changed[0], "solver.max_outer_steps: 1000 in the checkpoint, 400 here");
  // Written before the key: the older version stopped at the default.
  was["solver"].as_table()->erase("max_outer_steps");
  d = compare_cases(to_json(was), to_json(now));
  EXPECT_TRUE(d.same()) << d.mismatch;
  ASSERT_EQ(d.limits_changed.size(), 1u);
  EXPECT_EQ(d.limits_changed[0], "solver.max_outer_steps: 1000 (its default) in the checkpoint, 400 here");
  EXPECT_TRUE(d.defaulted.empty());
  // A tolerance is not a limit: the path to it depends on it.
  now = was;
  now["solver"].as_table()->insert_or_assign("tension_tolerance", 1e-4);
  EXPECT_EQ(compare_cases(to_json(was), to_json(now)).mismatch.rfind("key solver.tension_tolerance", 0), 0u);
}
