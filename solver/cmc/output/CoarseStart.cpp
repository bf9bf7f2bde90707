#include "cmc/output/CoarseStart.hpp"

#include "cmc/grid/Ranks.hpp"
#include "cmc/surface/H5Handle.hpp"
#include "cmc/surface/SurfaceIO.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace cmc {

namespace fs = std::filesystem;

namespace {

std::string step_name(int k) {
  char b[32];
  std::snprintf(b, sizeof b, "step_%04d", k);
  return b;
}

// A double attribute of `obj` (NaN when absent or unreadable).
double attribute(hid_t obj, const char* name) {
  if (H5Aexists(obj, name) <= 0) return NAN;
  H5Handle a(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose);
  double v = NAN;
  if (!a.ok() || H5Aread(a, H5T_NATIVE_DOUBLE, &v) < 0) return NAN;
  return v;
}

bool nearly_equal(double a, double b, double rel) { return std::abs(a - b) <= rel * std::max(std::abs(a), std::abs(b)); }

}  // namespace

Field prolong(const Field& coarse, int cnx, int cny, int m) {
  if (cnx < 1 || cny < 1 || m < 1 || coarse.size() != std::size_t(cnx) * std::size_t(cny))
    throw std::invalid_argument("prolong: the coarse field does not match its grid");
  const int nx = cnx * m, ny = cny * m;
  Field fine(std::size_t(nx) * std::size_t(ny));
  const double inv = 1.0 / m;
  Grid::parallel_for(std::size_t(ny), [&](std::size_t b, std::size_t e) {
    for (std::size_t iy = b; iy < e; ++iy) {
      const int j0 = int(iy) / m, j1 = (j0 + 1) % cny;
      const double fy = double(int(iy) - j0 * m) * inv;
      const double* r0 = coarse.data() + std::size_t(j0) * cnx;
      const double* r1 = coarse.data() + std::size_t(j1) * cnx;
      double* out = fine.data() + iy * std::size_t(nx);
      for (int ix = 0; ix < nx; ++ix) {
        const int i0 = ix / m, i1 = (i0 + 1) % cnx;
        const double fx = double(ix - i0 * m) * inv;
        out[ix] = (1.0 - fy) * ((1.0 - fx) * r0[i0] + fx * r0[i1]) + fy * ((1.0 - fx) * r1[i0] + fx * r1[i1]);
      }
    }
  }, std::size_t(nx) * std::size_t(ny));
  return fine;
}

namespace {

[[noreturn]] void fail_start(const fs::path& dir, const std::string& what) {
  throw CaseError("--start-from " + dir.string() + ": " + what);
}

// Whether a start from a coarser run serves this case, and `dir` holds a finished run with fields.
void check_start_applies(const fs::path& dir, const Case& c, const Scene& s) {
  auto fail = [&](const std::string& what) { fail_start(dir, what); };
  if (ranks() > 1) fail("not available in a distributed run yet (run the start on one process)");
  if (c.solver.kind != SolverKind::QuasiStatic && c.solver.kind != SolverKind::PolonskyKeer)
    fail("a start from a coarser run serves the quasi-static and Polonsky-Keer solvers only (this case's "
         "[solver] kind is another)");
  if (s.targets.size() != 1) fail("a start from a coarser run serves a case with one load step (this one has " +
                                  std::to_string(s.targets.size()) + ")");
  if (!s.half_space->periodic()) fail("a start from a coarser run needs a periodic boundary");
  const fs::path file = dir / "result.h5";
  std::error_code ec;
  if (fs::exists(dir / "INCOMPLETE", ec) || !fs::exists(dir / "summary.json", ec))
    fail("holds no finished run (no summary.json, or an INCOMPLETE marker): finish that run first");
  if (!fs::exists(file, ec))
    fail("holds a run without fields (no result.h5): run that case with --set output.fields=true");
}

// The last step of the coarse run's result.h5: its group's name and its load (SI).
struct LastStep {
  std::string step;
  double mean_pressure_pa = NAN, penetration_m = NAN;
};

LastStep read_last_step(const fs::path& dir, const fs::path& file, double lx_m, double ly_m) {
  auto fail = [&](const std::string& what) { fail_start(dir, what); };
  LastStep last_step;
  H5Quiet quiet;
  H5Handle f(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!f.ok()) fail(file.string() + " is not a readable HDF5 file");
  const double sx = attribute(f, "size_x"), sy = attribute(f, "size_y");
  if (!nearly_equal(sx, lx_m, 1e-9) || !nearly_equal(sy, ly_m, 1e-9)) {
    std::ostringstream m;
    m << file.string() << " covers " << sx << " x " << sy << " m, this case " << lx_m << " x " << ly_m
      << " m: a start needs the same box";
    fail(m.str());
  }
  int last = -1;
  while (H5Lexists(f, step_name(last + 1).c_str(), H5P_DEFAULT) > 0) ++last;
  if (last < 0) fail(file.string() + " holds no step");
  const std::string step = step_name(last);
  for (const char* field : {"gap", "pressure", "displacement"})
    if (H5Lexists(f, (step + "/" + field).c_str(), H5P_DEFAULT) <= 0)
      fail(file.string() + " holds no fields (no " + step + "/" + field + "): run that case with --set "
           "output.fields=true");
  H5Handle g(H5Gopen2(f, step.c_str(), H5P_DEFAULT), H5Gclose);
  last_step.step = step;
  last_step.mean_pressure_pa = g.ok() ? attribute(g, "mean_pressure") : NAN;
  last_step.penetration_m = g.ok() ? attribute(g, "penetration") : NAN;
  if (!std::isfinite(last_step.mean_pressure_pa) || !std::isfinite(last_step.penetration_m))
    fail(file.string() + ": " + step + " lacks its attributes mean_pressure and penetration");
  return last_step;
}

// How far the coarse run's heights (SI, cnx x cny) are from this case's at the points both
// grids share (every m-th of this grid's), relative to the rms height.
double surface_difference(const HeightMap& heights, const Scene& s, int cnx, int cny, int m) {
  const Units& u = s.units;
  const int nx = s.grid.nx;
  const Field& h = s.topography.heights;  // reduced
  Field dh(heights.heights.size()), hc(heights.heights.size());
  Grid::parallel_for(std::size_t(cny), [&](std::size_t b, std::size_t e) {
    for (std::size_t j = b; j < e; ++j)
      for (int i = 0; i < cnx; ++i) {
        const std::size_t k = j * std::size_t(cnx) + std::size_t(i);
        hc[k] = u.length(heights.heights[k]);
        dh[k] = hc[k] - h[(j * std::size_t(m)) * std::size_t(nx) + std::size_t(i) * std::size_t(m)];
      }
  });
  const double mean_h = Grid::mean(hc), mean_dh = Grid::mean(dh);
  double var_h = 0.0, var_dh = 0.0;
  {
    LocalReductions local;  // fields every rank holds whole (one rank here anyway)
    var_h = Grid::dot(hc, hc) / double(hc.size()) - mean_h * mean_h;
    var_dh = Grid::dot(dh, dh) / double(dh.size()) - mean_dh * mean_dh;
  }
  return std::sqrt(std::max(0.0, var_dh) / std::max(var_h, 1e-300));
}

// A start from a load no larger than this case's (the quasi-static solver's start from above).
void check_start_load(const fs::path& dir, const Scene& s, const LastStep& last) {
  const Units& u = s.units;
  const Target& t = s.targets[0];
  if (t.control == Control::MeanPressure && u.pressure(last.mean_pressure_pa) > t.value * (1.0 + 1e-9) + 1e-300) {
    std::ostringstream msg;
    msg << "its last step is at " << last.mean_pressure_pa << " Pa, more than this case's " << u.to_pa(t.value)
        << " Pa: a start needs the same or a smaller load";
    fail_start(dir, msg.str());
  }
  if (t.control == Control::Penetration && u.length(last.penetration_m) > t.value + 1e-12 * std::abs(t.value)) {
    std::ostringstream msg;
    msg << "its last step is at penetration " << last.penetration_m << " m, more than this case's "
        << u.to_m(t.value) << " m: a start needs the same or a smaller load";
    fail_start(dir, msg.str());
  }
}

}  // namespace

CoarseStart read_coarse_start(const fs::path& dir, const Case& c, const Scene& s, double lift) {
  auto fail = [&](const std::string& what) { fail_start(dir, what); };
  if (!(lift >= 0.0) || !std::isfinite(lift)) throw std::invalid_argument("read_coarse_start: lift must be >= 0");
  check_start_applies(dir, c, s);
  const fs::path file = dir / "result.h5";
  const Units& u = s.units;
  const double lx_m = u.to_m(s.grid.lx), ly_m = u.to_m(s.grid.ly);
  const LastStep last = read_last_step(dir, file, lx_m, ly_m);
  const std::string& step = last.step;
  // The fields (SI), each checked for shape and finite values by the reader.
  auto read = [&](const std::string& name) { return read_hdf5_heights(file, name, lx_m, ly_m); };
  HeightMap gap = read(step + "/gap"), pressure = read(step + "/pressure"), displacement = read(step + "/displacement");
  HeightMap heights = read("heights");
  const int cnx = gap.grid.nx, cny = gap.grid.ny;
  for (const HeightMap* m : {&pressure, &displacement, &heights})
    if (m->grid.nx != cnx || m->grid.ny != cny) fail(file.string() + ": its fields differ in shape");
  const int nx = s.grid.nx, ny = s.grid.ny;
  if (nx % cnx != 0 || ny % cny != 0 || nx / cnx != ny / cny)
    fail("its grid, " + std::to_string(cnx) + " x " + std::to_string(cny) + ", does not divide this case's " +
         std::to_string(nx) + " x " + std::to_string(ny) + " by one whole factor");
  const int m = nx / cnx;

  // The same surface: the heights at the points both grids share.
  const double rel = surface_difference(heights, s, cnx, cny, m);
  if (!(rel <= 1e-2)) {
    std::ostringstream msg;
    msg << "its surface is not this case's: at the points both grids share the heights differ by " << 100 * rel
        << " % of the rms height (the same surface on two grids: below 1e-6 %); a start needs the same surface "
           "(seed, spectrum, size)";
    fail(msg.str());
  }
  check_start_load(dir, s, last);

  CoarseStart out;
  ContactState& st = out.state;
  auto reduced = [&](Field f, double (Units::*to)(double) const) {
    for (double& v : f) v = (u.*to)(v);
    return f;
  };
  st.gap = prolong(reduced(std::move(gap.heights), &Units::length), cnx, cny, m);
  Grid::parallel_for(st.gap.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) st.gap[i] = std::max(0.0, st.gap[i]) + lift;
  });
  st.pressure = prolong(reduced(std::move(pressure.heights), &Units::pressure), cnx, cny, m);
  st.displacement = prolong(reduced(std::move(displacement.heights), &Units::length), cnx, cny, m);
  st.penetration = u.length(last.penetration_m);
  st.mean_pressure = Grid::mean(st.pressure);
  out.record = toml::table{{"folder", dir.string()},
                           {"grid", toml::array{cnx, cny}},
                           {"factor", m},
                           {"step", step},
                           {"mean_pressure", last.mean_pressure_pa},
                           {"surface_difference", rel},
                           {"gap_lift", u.to_m(lift)},
                           {"method", "periodic bilinear prolongation of the last step's gap (raised by "
                                      "gap_lift), pressure and displacement (solver/cmc/output/CoarseStart.hpp)"}};
  return out;
}

}  // namespace cmc
