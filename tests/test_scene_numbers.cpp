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
const char* kSphere = R"(
[case]
name = "s"
[grid]
n = 32
size = 1e-3
[material]
contact_modulus = 1e6
[surface]
kind = "sphere"
radius = 1e-2
[loading]
control = "force"
values = [1e-4, 2e-4]
)";
// The CaseError message of building the scene of kSphere with `overrides` ("" if none).
std::string scene_error(const std::vector<std::string>& overrides, const char* text = kSphere) {
  toml::table t = toml::parse(text);
  for (const auto& o : overrides) apply_override(t, o);
  try {
    build_scene(parse_case(t, "sphere.toml"));
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
  std::string rough = kSphere;
  rough.replace(rough.find("kind = \"sphere\"\nradius = 1e-2"), 29, "kind = \"self_affine\"\nrms_gradient = 1e308");
  EXPECT_NE(scene_error({}, rough.c_str()).find("[surface] rms_gradient: the surface's heights are not finite"),
            std::string::npos);
}

TEST(SceneNumbers, NonFiniteNumbersAreNeverConverged) {
  const Case c = parse_case(toml::parse(kSphere), "sphere.toml");
  Scene s = build_scene(c);
  s.units.length_m = 1e308;  // as if the check had let grid.size = 1e308 through: forces overflow
  const RunSummary run = run_scene(c, s, {});
  ASSERT_EQ(run.steps.size(), 2u);
  EXPECT_FALSE(std::isfinite(run.steps[0].force));
  EXPECT_FALSE(run.steps[0].result.converged);
  EXPECT_NE(run.steps[0].result.message.find("force is not finite"), std::string::npos);
  EXPECT_EQ(run.status, RunStatus::NotConverged);
}
