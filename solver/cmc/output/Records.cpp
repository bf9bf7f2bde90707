#include "cmc/output/Records.hpp"

namespace cmc::records {

const char* branch_name(Branch b) { return b == Branch::Loading ? "loading" : "unloading"; }
Branch branch_named(const std::string& name, const std::string& file) {
  if (name == branch_name(Branch::Loading)) return Branch::Loading;
  if (name == branch_name(Branch::Unloading)) return Branch::Unloading;
  throw CaseError(file + ": step branch '" + name + "': expected \"loading\" or \"unloading\"; run without --resume");
}

toml::table diagnostics_table(const SolveDiagnostics& d) {
  return toml::table{{"restarts", d.restarts},
                     {"backtracks", d.backtracks},
                     {"negative_curvature", d.negative_curvature},
                     {"clipped_steps", d.clipped_steps},
                     {"exact_recomputes", d.exact_recomputes},
                     {"outer_iterations", d.outer_iterations}};
}
SolveDiagnostics diagnostics_from(toml::node_view<const toml::node> t) {
  SolveDiagnostics d;
  d.restarts = int(t["restarts"].value_or(0));
  d.backtracks = int(t["backtracks"].value_or(0));
  d.negative_curvature = int(t["negative_curvature"].value_or(0));
  d.clipped_steps = int(t["clipped_steps"].value_or(0));
  d.exact_recomputes = int(t["exact_recomputes"].value_or(0));
  d.outer_iterations = int(t["outer_iterations"].value_or(0));
  return d;
}

}  // namespace cmc::records
