#include "cmc/surface/Topography.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

namespace cmc {

namespace {
template <class F>
Topography fill(const Grid& g, std::string what, F f) {
  Topography t{g, g.field(), std::move(what)};
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) t.heights[std::size_t(iy) * g.nx + ix] = f(ix * g.dx(), iy * g.dy());
  return t;
}
double min_image(double d, double l) { return d - l * std::round(d / l); }
}  // namespace

Topography sphere(const Grid& g, double radius, double x0, double y0, bool periodic) {
  std::ostringstream s;
  s << "paraboloid, R = " << radius << " (reduced), apex at (" << x0 << ", " << y0 << ")";
  return fill(g, s.str(), [&](double x, double y) {
    double dx = x - x0, dy = y - y0;
    if (periodic) dx = min_image(dx, g.lx), dy = min_image(dy, g.ly);
    return (dx * dx + dy * dy) / (2.0 * radius);
  });
}

Topography wavy1d(const Grid& g, double a, double lambda) {
  std::ostringstream s;
  s << "1-D wavy surface, amplitude " << a << ", wavelength " << lambda << " (reduced)";
  return fill(g, s.str(), [&](double x, double) { return a * (1.0 - std::cos(2.0 * std::numbers::pi * x / lambda)); });
}

Topography wavy2d(const Grid& g, double a, double lambda) {
  std::ostringstream s;
  s << "2-D wavy surface, amplitude " << a << ", wavelength " << lambda << " (reduced)";
  const double k = 2.0 * std::numbers::pi / lambda;
  return fill(g, s.str(), [&](double x, double y) { return a * (1.0 - std::cos(k * x) * std::cos(k * y)); });
}

Topography flat(const Grid& g) { return {g, g.field(), "flat"}; }

}  // namespace cmc
