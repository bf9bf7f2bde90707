// The harness's pieces that the reports and `cmc refine` rely on: the order fit and
// the profile tables.
#include "Profiles.hpp"
#include "Refine.hpp"
#include "Validate.hpp"

#include "cmc/analytic/Analytic.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

using namespace cmc;

// Values that follow n^-2 exactly give order 2, and the fitted line goes through them.
TEST(FitOrder, ExactPowerLaw) {
  const std::vector<int> n{64, 128, 256};
  const std::vector<double> v{3.0 / (64.0 * 64), 3.0 / (128.0 * 128), 3.0 / (256.0 * 256)};
  const OrderFit f = fit_order(n, v);
  EXPECT_NEAR(f.order, 2.0, 1e-12);
  for (std::size_t k = 0; k < n.size(); ++k) EXPECT_NEAR(f.at(n[k]) / v[k], 1.0, 1e-12);
  // The required-order guide shares the centroid: at the geometric mean grid it equals the fit.
  const double nbar = std::exp(f.mean_log_n);
  EXPECT_NEAR(f.line(nbar, 1.2) / f.at(nbar), 1.0, 1e-12);
  EXPECT_NEAR(f.line(128, 1.2) / f.line(256, 1.2), std::pow(2.0, 1.2), 1e-12);
}

// A value that does not shrink gives order ~0; too few or equal grids are errors.
TEST(FitOrder, FlatAndBadInput) {
  EXPECT_NEAR(fit_order({64, 128}, {1e-3, 1e-3}).order, 0.0, 1e-12);
  EXPECT_THROW(fit_order({64}, {1e-3}), std::invalid_argument);
  EXPECT_THROW(fit_order({64, 64}, {1e-3, 2e-3}), std::invalid_argument);
  EXPECT_THROW(fit_order({64, 128}, {1e-3}), std::invalid_argument);
}

// Hertz gap (Johnson 1985 eq. 3.42b): zero at the contact edge, continuous, and far
// away approaching the undeformed sphere r^2/2R minus the penetration a^2/R.
TEST(HertzGap, EdgeAndFarField) {
  const double R = 2.0, a = 0.1;
  EXPECT_EQ(analytic::hertz_gap(R, a, 0.5 * a), 0.0);
  EXPECT_NEAR(analytic::hertz_gap(R, a, a * (1 + 1e-9)), 0.0, 1e-6 * a * a / R);
  const double r = 1000 * a;
  // Far field: the elastic displacement decays as a^3/(R r) (point load), so the gap is
  // r^2/2R - a^2/R + O(a^3/(R r)).
  EXPECT_NEAR(analytic::hertz_gap(R, a, r), r * r / (2 * R) - a * a / R, 1e-2 * a * a / R);
  EXPECT_GT(analytic::hertz_gap(R, a, 1.5 * a), analytic::hertz_gap(R, a, 1.2 * a));
  EXPECT_THROW(analytic::hertz_gap(R, 0.0, a), std::invalid_argument);
}

TEST(Profiles, OnlyFieldWiseReferences) {
  EXPECT_TRUE(has_profiles(ValidationReference::Hertz));
  EXPECT_TRUE(has_profiles(ValidationReference::Westergaard));
  EXPECT_FALSE(has_profiles(ValidationReference::Jkr));
  EXPECT_THROW(profiles_csv(ValidationReference::Johnson, Scene{}, {}), std::invalid_argument);
}

// The refinement table: a value converging as v(n) = 1 + 8/n^2 shows successive
// relative changes |v_fine - v_coarse| / |v_fine| and an observed order of 2; an
// observable's own entry in "observables" takes precedence over the step's.
TEST(Refinement, ChangesAndOrder) {
  std::vector<RefinementGrid> grids;
  for (int n : {16, 32, 64, 128}) {
    RefinementGrid g;
    g.n = n, g.status = "converged";
    const double v = 1 + 8.0 / (double(n) * n);
    g.last_step = toml::table{{"penetration", v}, {"mean_gap", 5.0}, {"iterations", n},
                              {"observables", toml::table{{"mean_gap", v}}}};
    grids.push_back(g);
  }
  const auto rows = refinement_rows(grids);
  ASSERT_GE(rows.size(), 3u);
  EXPECT_EQ(rows[0].observable, "mean_gap");  // observables first
  for (const auto& r : rows) {
    if (r.observable != "penetration" && r.observable != "mean_gap") continue;
    ASSERT_EQ(r.changes.size(), 3u);
    const double v64 = 1 + 8.0 / 4096, v128 = 1 + 8.0 / 16384;
    EXPECT_NEAR(*r.changes[2], (v64 - v128) / v128, 1e-15);
    ASSERT_TRUE(r.order.has_value());
    EXPECT_NEAR(*r.order, 2.0, 1e-9);
  }
  const std::string md = refinement_markdown("x.toml", grids, rows);
  EXPECT_NE(md.find("| n = 16 | n = 32 | n = 64 | n = 128 | change 16→32 |"), std::string::npos);
  EXPECT_THROW(refinement_rows({grids[1], grids[0]}), std::invalid_argument);
}

// Two grids give changes but no order; a missing value gives no change.
TEST(Refinement, TwoGridsNoOrder) {
  RefinementGrid a, b;
  a.n = 32, b.n = 64;
  a.last_step = toml::table{{"penetration", 2.0}};
  b.last_step = toml::table{{"penetration", 1.0}, {"mean_gap", 3.0}};
  for (const auto& r : refinement_rows({a, b})) {
    if (r.observable == "penetration") EXPECT_DOUBLE_EQ(*r.changes[0], 1.0);
    if (r.observable == "mean_gap") EXPECT_FALSE(r.changes[0].has_value());
    EXPECT_FALSE(r.order.has_value());
  }
}

// The Johnson "mean_gap" check: a state that sits on Johnson's p̄–ḡ relation scores ~0,
// one whose mean pressure is off by 2e-3 p* scores 2e-3, and a state out of contact or at
// a mean gap where Johnson has no state (above the snap-off gap) is not scored.
TEST(JohnsonMeanGap, ScoresTheOffsetAndSkipsStatesWithoutAJohnsonState) {
  const Case c = load_case(std::string(CMC_SOURCE_DIR) + "/cases/validation/johnson-alpha03.toml");
  const Scene s = build_scene(c);
  const double h = s.wave_amplitude, lambda = s.wavelength, w = 0.3 * 0.3 * M_PI * M_PI * h * h / (2 * lambda);
  ASSERT_NEAR(analytic::johnson_alpha(1.0, w, h, lambda), 0.3, 1e-6);
  const double pstar = analytic::westergaard_full_contact_pressure(1.0, h, lambda);
  const double a = 0.3 * lambda, gbar = analytic::johnson_mean_gap(1.0, w, h, lambda, a);
  const std::size_t n = s.grid.size();
  auto state = [&](double mean_gap, double pbar) {
    ContactState st;
    st.gap.assign(n, 0.0);  // the first half closed, the rest carries the mean gap
    for (std::size_t k = n / 2; k < n; ++k) st.gap[k] = 2.0 * mean_gap;
    st.pressure.assign(n, pbar);
    st.mean_pressure = pbar;
    return st;
  };
  const double pj = analytic::johnson_mean_pressure(1.0, w, h, lambda, a);
  const RunSummary run;
  std::string def;
  EXPECT_LT(validation_error(ValidationReference::Johnson, ValidationQuantity::MeanGap, s, {state(gbar, pj)}, run, &def),
            1e-9);
  EXPECT_NE(def.find("solved mean gap"), std::string::npos) << def;
  EXPECT_NEAR(validation_error(ValidationReference::Johnson, ValidationQuantity::MeanGap, s,
                               {state(gbar, pj + 2e-3 * pstar)}, run),
              2e-3, 1e-9);
  ContactState open = state(gbar, pj + 0.1 * pstar);
  open.gap.assign(n, gbar);  // no closed point
  ContactState above = state(2.0 * h, 0.1 * pstar);  // ḡ above Johnson's largest mean gap (1.39 h at α = 0.3)
  EXPECT_EQ(validation_error(ValidationReference::Johnson, ValidationQuantity::MeanGap, s, {open, above}, run), 0.0);
}
