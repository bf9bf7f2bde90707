// Solved fields beside their analytic reference, point by point, for the validation
// report's profile figures (python/cmc/report/validation.py only draws these columns).
//
// `cmc validate --out DIR` writes DIR/<case>/profiles.csv for the references that have
// a field-wise closed form (hertz, hertz_periodic, westergaard): one row per grid point
// near the contact and per load step, every column dimensionless and computed here from
// the same geometry as the checks in Validate.cpp (contact centre, periodic images).
#pragma once

#include "cmc/contact/Solver.hpp"
#include "cmc/scene/Scene.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace cmc {

// True if `reference` has a profile table (hertz, hertz_periodic, westergaard).
bool has_profiles(ValidationReference reference);

// The table as CSV text: '#' comment lines (what each column is, and its source), a
// header row, then rows of %.9e numbers. Throws std::invalid_argument for a reference
// without profiles.
std::string profiles_csv(ValidationReference reference, const Scene& s, const std::vector<ContactState>& states);

}  // namespace cmc
