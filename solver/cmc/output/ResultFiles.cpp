#include "cmc/output/ResultFiles.hpp"

#include "cmc/grid/Ranks.hpp"
#include "cmc/output/Hdf5Fields.hpp"
#include "cmc/output/Records.hpp"
#include "cmc/surface/H5Handle.hpp"

#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace cmc {

namespace fs = std::filesystem;
using namespace h5;

void write_step_file(const fs::path& tmp, const StepRecord& rec, const ContactState& st, const Scene& s,
                     bool fields) {
  const bool root = is_root();
  H5Handle file, grp;
  const Units& u = s.units;
  char name[32];
  std::snprintf(name, sizeof name, "step_%04d", rec.index);
  if (root) {
    file = H5Handle(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
    if (!file.ok()) throw std::runtime_error(tmp.string() + ": cannot create the HDF5 file");
    grp = H5Handle(H5Gcreate2(file, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    check(grp, std::string("group ") + name);
  }
  if (fields) {
    dataset(grp, "pressure", s.grid, st.pressure, u.pressure_pa, "Pa", "interfacial pressure, compressive > 0");
    dataset(grp, "displacement", s.grid, st.displacement, u.length_m, "m", "surface displacement into the solid");
    dataset(grp, "gap", s.grid, st.gap, u.length_m, "m", "interfacial gap g = h - penetration + u");
  }
  if (!root) return;
  attr_double(grp, "mean_pressure", rec.mean_pressure);
  attr_double(grp, "penetration", rec.penetration);
  attr_double(grp, "mean_gap", rec.mean_gap);
  attr_string(grp, "branch", records::branch_name(rec.branch));
  if (rec.observables) {
    H5Handle og(H5Gcreate2(grp, "observables", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    check(og, "group observables");
    for (const auto& [oname, a] : rec.observables->arrays) vector_dataset(og, oname, a.values, a.unit.c_str());
  }
  grp.reset();
  check(file.reset(), "closing " + tmp.string());
}

void write_result_file(const fs::path& tmp, const Case& c, const Scene& s, const std::vector<StepRecord>& steps,
                       const std::vector<fs::path>& step_files, bool fields) {
  H5Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
  if (!file.ok()) throw std::runtime_error(tmp.string() + ": cannot create the HDF5 file");
  const Units& u = s.units;
  const Grid& g = s.grid;
  const hid_t root = file;
  attr_string(root, "case", c.name);
  attr_string(root, "cmc_version", CMC_VERSION);
  attr_double(root, "dx", u.to_m(g.dx()));
  attr_double(root, "dy", u.to_m(g.dy()));
  attr_double(root, "size_x", u.to_m(g.lx));
  attr_double(root, "size_y", u.to_m(g.ly));
  attr_string(root, "length_units", "m");
  if (fields)
    dataset(root, "heights", g, s.topography.heights, u.length_m, "m",
            "indenter heights h (gap g = h - penetration + u)");
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const StepRecord& r = steps[k];
    const fs::path& from = step_files[k];
    H5Handle src(H5Fopen(from.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!src.ok()) throw std::runtime_error(from.string() + ": the results of step " + std::to_string(r.index) +
                                            " are missing");
    char name[32];
    std::snprintf(name, sizeof name, "step_%04d", r.index);
    check(H5Ocopy(src, name, file, name, H5P_DEFAULT, H5P_DEFAULT), std::string("copying ") + name);
  }
  check(file.reset(), "closing " + tmp.string());  // a failed close may leave it incomplete
}

std::string xdmf_text(const std::vector<StepRecord>& steps, const Scene& s) {
  const Grid& g = s.grid;
  const Units& u = s.units;
  std::ostringstream x;
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
    << "<Grid Name=\"steps\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const auto& r : steps) {
    char name[32];
    std::snprintf(name, sizeof name, "step_%04d", r.index);
    x << "<Grid Name=\"" << name << "\"><Time Value=\"" << r.index << "\"/>\n"
      << "<Topology TopologyType=\"2DCoRectMesh\" Dimensions=\"" << g.ny << " " << g.nx << "\"/>\n"
      << "<Geometry GeometryType=\"ORIGIN_DXDY\"><DataItem Dimensions=\"2\" Format=\"XML\">0 0</DataItem>"
      << "<DataItem Dimensions=\"2\" Format=\"XML\">" << u.to_m(g.dy()) << " " << u.to_m(g.dx())
      << "</DataItem></Geometry>\n";
    for (const char* f : {"pressure", "gap", "displacement"})
      x << "<Attribute Name=\"" << f << "\" Center=\"Node\"><DataItem Dimensions=\"" << g.ny << " " << g.nx
        << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">result.h5:/" << name << "/" << f
        << "</DataItem></Attribute>\n";
    x << "</Grid>\n";
  }
  x << "</Grid>\n</Domain>\n</Xdmf>\n";
  return x.str();
}

}  // namespace cmc
