// The installed Hertz case (a sphere on a free half-space) solved through the library on a
// 64² grid; exit 0 when each step's penetration is within 1e-3 of Hertz's delta = a²/R
// (the case's own tolerance: 6.8e-4 measured at 64², cases/validation/hertz-free.toml).
#include "cmc/analytic/Analytic.hpp"
#include "cmc/run/Driver.hpp"

#include <cmath>
#include <cstdio>

int main() {
  const cmc::Case c = cmc::load_case(CASE_FILE, {"grid.n=64"});
  cmc::Scene scene = cmc::build_scene(c);
  const cmc::RunSummary run = cmc::run_scene(c, scene, [](const cmc::StepRecord&, const cmc::ContactState&) {});
  int bad = run.steps.empty() ? 1 : 0;
  for (const cmc::StepRecord& s : run.steps) {
    const double hertz = cmc::analytic::hertz_from_force(c.contact_modulus, c.surface.radius, s.force).penetration;
    const double error = std::abs(s.penetration / hertz - 1);
    std::printf("force %.4g N: penetration %.6g m, Hertz %.6g m, relative error %.2e\n", s.force, s.penetration,
                hertz, error);
    bad += error > 1e-3;
  }
  return bad == 0 ? 0 : 1;
}
