// libFuzzer target: the case parser as `cmc run CASE.toml --set k=v ...` uses it
// (cmc::load_case: TOML text -> overrides -> validated Case).
//
// Input: the case file's text, then any number of `--set` strings, each after a NUL
// byte: "<toml>\0grid.n=64\0solver.tolerance=1e-8". Bad input must end in a CaseError
// (the documented error, exit code 2); anything else thrown is a finding. A case that
// parses must keep the parser's promises (the checks below), and its resolved table
// (what summary.json records as "the case as run") must parse again to the same case.
#include "FuzzInput.hpp"

#include "cmc/input/Case.hpp"

#include <cmath>
#include <exception>
#include <string>
#include <vector>

namespace {

void check_parsed(const cmc::Case& c) {
  using cmc::fuzz::require;
  require(c.grid.nx >= 1 && c.grid.ny >= 1, "grid without points");
  require(std::isfinite(c.grid.size_x) && c.grid.size_x > 0 && std::isfinite(c.grid.size_y) && c.grid.size_y > 0,
          "grid size not positive and finite");
  require(std::isfinite(c.contact_modulus) && c.contact_modulus > 0, "contact modulus not positive and finite");
  require(c.solver.kind != cmc::SolverKind::Auto, "solver kind left at auto");
  require(c.solver.tolerance > 0 && c.solver.max_iterations >= 1 && c.solver.recompute_every >= 1,
          "solver settings out of range");
  require(!c.loading.values.empty(), "no load steps");
  for (double v : c.loading.values) require(std::isfinite(v), "non-finite load value");
  for (double v : c.loading.unloading) require(std::isfinite(v), "non-finite unloading value");
  if (c.validation) {
    require(!c.validation->checks.empty() || c.validation->refinement, "validation without checks");
    if (c.validation->refinement) {
      const auto& g = c.validation->refinement->grids;
      require(g.size() >= 2, "refinement with fewer than 2 grids");
      for (std::size_t i = 0; i < g.size(); ++i)
        require(g[i] >= 2 && (i == 0 || g[i] > g[i - 1]), "refinement grids not increasing");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static cmc::fuzz::TempFile file("case.toml");
  const std::string_view in = cmc::fuzz::as_text(data, size);
  const std::size_t nul = in.find('\0');
  file.write(in.substr(0, nul));
  std::vector<std::string> overrides;
  for (std::size_t pos = nul; pos != std::string_view::npos && pos < in.size();) {
    const std::size_t next = in.find('\0', pos + 1);
    overrides.emplace_back(in.substr(pos + 1, next == std::string_view::npos ? std::string_view::npos : next - pos - 1));
    pos = next;
  }
  try {
    const cmc::Case c = cmc::load_case(file.path(), overrides);
    check_parsed(c);
    // The resolved case is a case: parsing it again must give the same resolved table.
    cmc::Case again;
    try {
      again = cmc::parse_case(c.resolved, "resolved");
    } catch (const cmc::CaseError& e) {
      cmc::fuzz::fail(std::string("the resolved case does not parse again: ") + e.what());
    }
    cmc::fuzz::require(again.resolved == c.resolved, "the resolved case resolves to a different case");
  } catch (const cmc::CaseError&) {
    // bad input, reported as such
  } catch (const std::exception& e) {
    cmc::fuzz::fail(std::string("load_case threw something other than CaseError: ") + e.what());
  }
  return 0;
}
