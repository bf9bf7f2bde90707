#include "cmc/Scene.hpp"

namespace cmc {

Scene build_scene(const Case& c) {
  Scene s;
  s.units.length_m = c.grid.size_x;
  s.units.pressure_pa = c.contact_modulus;
  const Units& u = s.units;
  s.grid = Grid{c.grid.nx, c.grid.ny, 1.0, u.length(c.grid.size_y)};
  const auto& sf = c.surface;
  if (sf.kind == "sphere") {
    s.sphere_radius = u.length(sf.radius);
    s.apex_x = sf.center ? u.length((*sf.center)[0]) : 0.5 * s.grid.lx;
    s.apex_y = sf.center ? u.length((*sf.center)[1]) : 0.5 * s.grid.ly;
    s.topography = sphere(s.grid, s.sphere_radius, s.apex_x, s.apex_y, c.grid.periodic);
  } else if (sf.kind == "wavy1d" || sf.kind == "wavy2d") {
    s.wave_amplitude = u.length(sf.amplitude), s.wavelength = u.length(sf.wavelength);
    s.topography = (sf.kind == "wavy1d" ? wavy1d : wavy2d)(s.grid, s.wave_amplitude, s.wavelength);
  } else {
    s.topography = flat(s.grid);
  }
  s.mean_height = Grid::mean(s.topography.heights);
  s.half_space = make_half_space(s.grid, 1.0, c.grid.periodic);  // E* = 1 in reduced units

  const std::string& ctl = c.loading.control;
  for (double v : c.loading.values) {
    if (ctl == "force") s.targets.push_back({Control::MeanPressure, u.force(v) / s.grid.area()});
    else if (ctl == "mean_pressure") s.targets.push_back({Control::MeanPressure, u.pressure(v)});
    else if (ctl == "penetration") s.targets.push_back({Control::Penetration, u.length(v)});
    else s.targets.push_back({Control::Penetration, s.mean_height - u.length(v)});  // periodic: <g> = <h> − δ
  }
  return s;
}

}  // namespace cmc
