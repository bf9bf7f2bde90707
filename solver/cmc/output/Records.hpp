// How a step's branch and a solve's diagnostics are written in summary.json and in
// checkpoints, and read back from a checkpoint. Internal to the output layer.
#pragma once

#include "cmc/run/Driver.hpp"

#include <string>

#include <toml++/toml.h>

namespace cmc::records {

// Enum values as summary.json and result.h5 name them.
const char* branch_name(Branch b);
// The branch of a checkpoint's step (CaseError naming `file` for another word).
Branch branch_named(const std::string& name, const std::string& file);
toml::table diagnostics_table(const SolveDiagnostics& d);
SolveDiagnostics diagnostics_from(toml::node_view<const toml::node> t);

}  // namespace cmc::records
