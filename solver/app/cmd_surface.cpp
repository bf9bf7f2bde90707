// cmc surface: the indenter surface of a case, its statistics, and optionally the
// height map as a file (HDF5 dataset "surface" in metres, with lx/ly attributes).
#include "commands.hpp"

#include "cmc/grid/FilePaths.hpp"
#include "cmc/scene/Scene.hpp"
#include "cmc/surface/SurfaceIO.hpp"
#include "cmc/surface/SurfaceStats.hpp"

#include <cstdio>

namespace cmc::app {

namespace {
const char* kSurfaceHelp = R"(usage: cmc surface CASE.toml [--write FILE.h5] [--set section.key=value ...]

Builds the case's surface on its grid and prints its statistics in SI units: mean,
min and max height, rms height, rms gradient, rms curvature and R_c (the inverse rms
line-scan curvature), the Tabor parameter when the case has adhesion, and the grid
spacing relative to the surface's short cutoff. --write saves the height map (metres)
as HDF5 (dataset "surface", attributes lx and ly in metres), atomically: FILE.h5 must be a
new path or a regular file (a folder, device, FIFO or symbolic link is refused, exit 2).
)";
}  // namespace

int cmd_surface(int argc, char** argv) {
  const Args a = parse_args(argc, argv, 2, {"--write"});
  if (a.help) return std::fputs(kSurfaceHelp, stdout), kOk;
  if (a.positional.size() != 1) throw CaseError("cmc surface takes exactly one case file (see cmc surface --help)");
  const std::string out = a.option("--write");
  if (!out.empty()) check_output_file(out);  // refused before the surface is made (grid/FilePaths.hpp)
  const Case c = load_case(a.positional[0], a.overrides);
  const Scene s = build_scene(c);
  const SurfaceStatistics st = surface_statistics(s.grid, s.topography.heights);
  const double L = s.units.length_m;
  std::printf("surface of %s: %s\n", c.name.c_str(), s.topography.description.c_str());
  std::printf("  grid             %d x %d, dx = %.6g m, size %.6g x %.6g m\n", s.grid.nx, s.grid.ny, s.grid.dx() * L,
              s.grid.lx * L, s.grid.ly * L);
  std::printf("  mean height      %.6g m\n  min, max height  %.6g m, %.6g m\n  rms height       %.6g m\n", st.mean * L,
              st.min * L, st.max * L, st.rms_height * L);
  std::printf("  rms gradient     %.12g\n  rms curvature    %.6g 1/m\n  R_c              %.6g m\n", st.rms_gradient,
              st.rms_curvature / L, st.curvature_radius * L);
  const SurfaceFacts& f = s.surface_facts;
  for (const auto& [name, v] : {std::pair{"modes_dropped", f.modes_dropped},
                                {"dx_over_cutoff_wavelength", f.dx_over_cutoff_wavelength},
                                {"dx_over_range", f.dx_over_range}, {"tabor_parameter", f.tabor_parameter},
                                {"specified_range", f.specified_range}, {"law_head", f.law_head}})
    if (v) std::printf("  %-16s %.6g\n", name, *v);
  for (const auto& w : s.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  if (!out.empty()) {
    HeightMap m{Grid{s.grid.nx, s.grid.ny, s.grid.lx * L, s.grid.ly * L}, s.topography.heights};
    for (auto& h : m.heights) h *= L;
    write_hdf5_heights(out, m);
    std::printf("wrote %s (dataset \"surface\", heights in m)\n", out.c_str());
  }
  return kOk;
}

}  // namespace cmc::app
