// The numeric-validity check of the scene (scene/SceneChecks.hpp): values that overflow or
// underflow once in reduced units are bad input naming their key, before any solve; and a
// run whose numbers are not finite is never "converged" (run/Driver.cpp).
#include "cmc/run/Driver.hpp"
#include "cmc/scene/SceneChecks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

using namespace cmc;

namespace {
// The sphere of cases/validation/hertz-free.toml: 1 mm, E* = 1 MPa, R = 1 cm, 32².
const std::string kSphere = std::string(CMC_SOURCE_DIR) + "/cases/validation/hertz-free.toml";
const std::string kRough = std::string(CMC_SOURCE_DIR) + "/cases/challenge/reference-load-hardwall.toml";
// The CaseError message of building the scene of `file` on 32² with `overrides` ("" if none).
std::string scene_error(std::vector<std::string> overrides, const std::string& file = kSphere) {
  overrides.insert(overrides.begin(), "grid.n=32");
  try {
    build_scene(load_case(file, overrides));
  } catch (const CaseError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(SceneNumbers, OverflowIsBadInputNamingTheKey) {
  EXPECT_EQ(scene_error({}), "");
  EXPECT_NE(scene_error({"grid.size=1e308", "surface.radius=1e308"}).find("[grid] size = 1e+308 m"), std::string::npos);
  EXPECT_NE(scene_error({"surface.radius=1e-300"}).find("[surface] radius = 1e-300 m, which is 1e-297"),
            std::string::npos);
  EXPECT_NE(scene_error({"material.contact_modulus=1e308"}).find("[loading] values[0]"), std::string::npos);
  EXPECT_NE(scene_error({"loading.values=[1e-4, 1e300]"}).find("[loading] values[1] = 1e+300 N"), std::string::npos);
  EXPECT_NE(scene_error({"interaction.kind=\"exponential\"", "interaction.work_of_adhesion=1e300",
                         "interaction.range=1e-6", "solver.kind=\"adhesive_cg\""})
                .find("[interaction] work_of_adhesion = 1e+300"),
            std::string::npos);
  EXPECT_NE(scene_error({"interaction.kind=\"exponential\"", "interaction.work_of_adhesion=0.05",
                         "interaction.tabor=1e308", "solver.kind=\"adhesive_cg\""})
                .find("[interaction] tabor = 1e+308 sets the range rho"),
            std::string::npos);
  // Was exit 4 with an internal name ("DugdaleAdhesion: need a smoothing width ...").
  EXPECT_NE(scene_error({"interaction.kind=\"dugdale\"", "interaction.work_of_adhesion=0.05",
                         "interaction.range=1e-6", "interaction.smoothing=1"})
                .find("[interaction] smoothing = 1 m: expected a width below 2 h0 = 2e-06 m"),
            std::string::npos);
  EXPECT_NE(scene_error({"surface.center=[1e308, 0]"}).find("[surface] center = 1e+308 m"), std::string::npos);
  EXPECT_NE(scene_error({"observables.contact_gap_threshold=1e308"}).find("[observables] contact_gap_threshold"),
            std::string::npos);
  EXPECT_NE(scene_error({"surface.rms_gradient=1e308"}, kRough).find("[surface] rms_gradient: the surface's heights are not finite"),
            std::string::npos);
}

TEST(SceneNumbers, NonFiniteNumbersAreNeverConverged) {
  const Case c = load_case(kSphere, {"grid.n=32"});
  Scene s = build_scene(c);
  s.units.length_m = 1e308;  // as if the check had let grid.size = 1e308 through: forces overflow
  const RunSummary run = run_scene(c, s, {});
  ASSERT_EQ(run.steps.size(), 3u);
  EXPECT_FALSE(std::isfinite(run.steps[0].force));
  EXPECT_FALSE(run.steps[0].result.converged);
  EXPECT_NE(run.steps[0].result.message.find("force is not finite"), std::string::npos);
  EXPECT_EQ(run.status, RunStatus::NotConverged);
}
