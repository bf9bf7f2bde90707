// Grid-refinement study of a case without an analytic reference (e.g. the challenge):
// the same case on several grids, and for every scalar observable of the last load
// step its change between successive grids and the observed order of those changes.
// `cmc refine` (solver/app/cmd_refine.cpp) runs the grids; this file makes the table.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <toml++/toml.h>

namespace cmc {

// One grid of the study: its size, status and the last step's record as summary.json
// writes it (Writer::step_json), plus the grid facts shown in the grid table.
struct RefinementGrid {
  int n = 0;
  std::string status;
  double dx_m = 0.0;
  toml::table last_step;  // keys as in summary.json "steps"; "observables" take precedence
  toml::table facts;      // e.g. dx_over_cutoff_wavelength, modes_dropped (from surface_facts)
};

struct RefinementRow {
  std::string observable;
  std::vector<std::optional<double>> values;   // per grid (absent where a grid lacks it)
  // |v_{k+1} - v_k| / |v_{k+1}| for successive grids k, k+1; the last one, between the
  // two finest grids, is the estimated discretisation error of the finest.
  std::vector<std::optional<double>> changes;
  // fit_order (Validate.hpp) of the absolute changes |v_{k+1} - v_k| against n_k: needs
  // three or more grids and no zero change.
  std::optional<double> order;
};

// The rows, in the order: the last step's observables, then penetration, mean_gap,
// contact_fraction, iterations, wall_s (those not already listed). Grids must increase.
std::vector<RefinementRow> refinement_rows(const std::vector<RefinementGrid>& grids);

// The study as Markdown (value table, then grid table) and as a TOML table for JSON.
std::string refinement_markdown(const std::string& case_file, const std::vector<RefinementGrid>& grids,
                                const std::vector<RefinementRow>& rows);
toml::table refinement_record(const std::string& case_file, const std::vector<RefinementGrid>& grids,
                              const std::vector<RefinementRow>& rows);

}  // namespace cmc
