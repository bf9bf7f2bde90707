// The stability checks (validation/Stability.hpp): their measures on sequences worked by
// hand, the case file's keys for them, and the checks on a small solved case, where each
// must pass, and fail when its bound is set below what was measured.
#include "Stability.hpp"
#include "sphere_case.hpp"

#include "cmc/input/ValidationRules.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace cmc;

namespace {

// A Hertz sphere on a periodic 32² cell at two loads: Polonsky-Keer, about a second.
const std::string kSphere = sphere_case_text("t", 32, "1e-4, 4e-4") + "[validation]\n";

Case with_checks(const std::string& checks) {
  return parse_case(toml::parse(kSphere + checks), "t.toml");
}

std::string error_of(const std::string& checks) {
  try {
    check_validation_fits(with_checks(checks));
  } catch (const CaseError& e) {
    return e.what();
  }
  return "";
}

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

// r = 1, 0.5, 2, 0.1: the rise from the lowest earlier value 0.5 to 2 is a factor 4.
TEST(Stability, LargestGrowth) {
  EXPECT_DOUBLE_EQ(largest_growth({1.0, 0.5, 2.0, 0.1}), 4.0);
  EXPECT_DOUBLE_EQ(largest_growth({1.0, 0.5, 0.25}), 1.0);  // never rises
  EXPECT_DOUBLE_EQ(largest_growth({0.0, 1.0, 0.5}), 1.0);    // zeros take no part
  EXPECT_EQ(largest_growth({1.0, std::nan("")}), kInf);      // a NaN residual fails any bound
}

// E = -1, -3, -2.5, -4: the rise 0.5 above the lowest earlier -3, over max |E| = 4.
TEST(Stability, LargestRise) {
  EXPECT_DOUBLE_EQ(largest_rise({-1.0, -3.0, -2.5, -4.0}), 0.125);
  EXPECT_DOUBLE_EQ(largest_rise({-1.0, -2.0, -3.0}), 0.0);
  EXPECT_DOUBLE_EQ(largest_rise({std::nan(""), -1.0, -2.0}), 0.0);  // solvers without an energy report NaN
  EXPECT_DOUBLE_EQ(relative_difference(1.0, 1.5, 2.0), 0.25);
  EXPECT_EQ(relative_difference(1.0, std::nan(""), 2.0), kInf);
}

// Each kind reads its own key; a check is a comparison or a stability check, not both; a
// continuity parameter must be a number of the case; what a kind needs of the case is checked.
TEST(Stability, CaseFileKeys) {
  const Case c = with_checks("[[validation.check]]\nkind = \"iterations\"\nbudget = 50\n"
                             "[[validation.check]]\nkind = \"continuity\"\nparameter = \"loading.values\"\n"
                             "observable = \"penetration\"\ntolerance = 0.02\nskip_steps = [1]\n");
  ASSERT_TRUE(c.validation);
  EXPECT_FALSE(c.validation->reference);
  ASSERT_EQ(c.validation->stability.size(), 2u);
  EXPECT_EQ(c.validation->stability[0].bound, 50.0);
  EXPECT_EQ(c.validation->stability[1].change, 0.01);
  EXPECT_EQ(c.validation->stability[1].skip_steps, std::vector<int>{1});
  EXPECT_THROW(with_checks("[[validation.check]]\nkind = \"gap\"\nquantity = \"penetration\"\ntolerance = 1\n"),
               CaseError);
  EXPECT_THROW(with_checks("[[validation.check]]\nkind = \"iterations\"\ntolerance = 5\n"), CaseError);  // budget
  EXPECT_THROW(with_checks("[[validation.check]]\nkind = \"continuity\"\nparameter = \"surface.kind\"\n"
                           "tolerance = 1\n"),
               CaseError);
  EXPECT_THROW(with_checks("[[validation.check]]\nquantity = \"penetration\"\ntolerance = 1\n"), CaseError);
  EXPECT_NE(error_of("[[validation.check]]\nkind = \"energy_rise\"\ntolerance = 0\n").find("adhesive_cg"),
            std::string::npos);
  EXPECT_NE(error_of("[[validation.check]]\nkind = \"hysteresis\"\n").find("unloading"), std::string::npos);
}

// On a Hertz contact every check passes: converged in its budget, residual growth bounded,
// the same bits again and on 2 threads within round-off, continuous in the load, force
// balance, gap and contact fraction to round-off. With the bounds below what was measured,
// each of them fails.
TEST(Stability, HertzPassesAndTighterBoundsFail) {
  const std::string checks =
      "[[validation.check]]\nkind = \"iterations\"\nbudget = 500\n"
      "[[validation.check]]\nkind = \"residual_growth\"\nfactor = 1e6\n"
      "[[validation.check]]\nkind = \"same_bits\"\n"
      "[[validation.check]]\nkind = \"threads\"\ntolerance = 1e-9\n"
      "[[validation.check]]\nkind = \"continuity\"\nparameter = \"loading.values\"\nobservable = \"penetration\"\n"
      "tolerance = 0.02\n"
      "[[validation.check]]\nkind = \"force_balance\"\ntolerance = 1e-6\n"
      "[[validation.check]]\nkind = \"gap\"\ntolerance = 1e-6\n"
      "[[validation.check]]\nkind = \"contact_fraction\"\n";
  const Case c = with_checks(checks);
  RecordedCase rc = solve_recorded(c);
  ASSERT_EQ(rc.history.size(), 2u);  // one solve per load step
  const auto results = evaluate_stability(c, rc);
  ASSERT_EQ(results.size(), 9u);  // the eight, and `finite`
  for (const CheckResult& r : results) EXPECT_TRUE(r.pass) << r.quantity << ": " << r.error << " (" << r.definition << ")";
  // Penetration scales as F^(2/3): 1 % more load moves it by 0.67 %.
  EXPECT_NEAR(results[4].error, 2.0 / 3.0 * 0.01, 1e-3);
  for (std::size_t k : {0u, 1u, 4u}) {
    StabilityCheck tight = c.validation->stability[k];
    tight.bound = results[k].error / 2;  // residual growth: at least 1 (a monotone residual), so below
    Case t = c;
    t.validation->stability = {tight};
    EXPECT_FALSE(evaluate_stability(t, rc).front().pass) << results[k].quantity;
  }
}
