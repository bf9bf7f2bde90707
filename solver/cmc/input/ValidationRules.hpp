// What each analytic reference of a [validation] section compares, and so what the case
// must be for it: checked when the case is read, before anything is solved. A reference
// on the wrong problem (westergaard on a sphere) or a quantity it does not have (jkr with
// a penetration check) used to be solved first and then fail with exit 4 and an internal
// name; now `cmc validate` refuses it (CaseError, exit 2) naming the key and what is
// expected, before anything is solved.
//
//   reference        surface   interaction               boundary   quantities
//   hertz            sphere    hard_wall                 any        penetration, pressure_profile
//   hertz_periodic   sphere    hard_wall                 periodic   penetration, pressure_profile
//   westergaard      wavy1d    hard_wall                 periodic   mean_pressure, pressure_profile, mean_gap
//   jkr              sphere    exponential               any        force, pulloff
//   maugis_dugdale   sphere    dugdale                   any        force, pulloff
//   johnson          wavy1d    exponential or dugdale    periodic   mean_pressure, mean_gap, pulloff
//
// (validation/Validate.cpp computes each; cases/README.md, [validation], lists the table.)
//
// Stability checks (validation/Stability.hpp) need no reference; three need something of the
// case: energy_rise and pulloff the adhesive CG, hysteresis unloading steps.
#pragma once

#include "cmc/input/Case.hpp"

namespace cmc {

// Throws CaseError naming the key ([validation] reference, [[validation.check]] quantity or
// kind, [validation.refinement] quantity) when the case is not what its reference or a
// stability check compares.
// Called by `cmc validate` for every case before anything is solved; `cmc run` does not
// read [validation], so a validation case may still be run with other physics.
void check_validation_fits(const Case& c);

}  // namespace cmc
