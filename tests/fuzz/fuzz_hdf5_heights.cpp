// libFuzzer target: cmc's HDF5 height reader (surface/SurfaceIO: read_hdf5_heights with the
// box size from the dataset's attributes or given, read_challenge_hdf5) on well-formed
// HDF5 files of every shape the reader may meet.
//
// The input does not hold the file's bytes (fuzz_hdf5_bytes does that, and mostly finds
// bugs of libhdf5's decoder): it chooses the file, which this target writes with the
// HDF5 library: dataset name and place, rank and extent, stored type (IEEE and big-endian
// floats, a 16-bit float, integers of every width, long double, strings, compound, enum),
// layout (contiguous, compact, chunked with shuffle/deflate/fletcher32 filters), whether
// its data was written, the raw bytes of the data (so NaN, infinities, subnormals appear),
// and the "lx"/"ly" attributes (absent, on the file instead of the dataset, of another
// type, of several elements, not positive).
//
// Checked against an oracle: what the reader must refuse (a SurfaceFileError: no dataset
// "surface", rank other than 2, an empty extent, a non-numeric type, data never written,
// a non-finite height, a size attribute absent, not one positive finite number, a
// non-square challenge map) and, for a map it reads, that it equals the dataset as HDF5
// converts it to double (nx = the fastest dimension) times the height scale, with the box
// size asked for. Nothing may stay open in HDF5 after a read.
#include "FuzzInput.hpp"

#include "cmc/surface/SurfaceIO.hpp"

#include <fuzzer/FuzzedDataProvider.h>
#include <hdf5.h>

#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace {

using cmc::fuzz::require;

constexpr double kScale = 1e-6;
constexpr std::size_t kMaxBytes = 1 << 16;  // data written per file
constexpr double kMaxChunks = 1024;          // chunks written per file (see write_file)

// HDF5 ids the writer makes, closed in reverse order.
struct Ids {
  std::vector<std::pair<hid_t, herr_t (*)(hid_t)>> ids;
  hid_t add(hid_t id, herr_t (*close)(hid_t)) {
    if (id >= 0) ids.emplace_back(id, close);
    return id;
  }
  ~Ids() {
    for (auto it = ids.rbegin(); it != ids.rend(); ++it) it->second(it->first);
  }
};

enum class AttrMode { Absent, Double, Int, OneElementArray, ManyElements, String, OnFile };

struct AttrPlan {
  AttrMode mode = AttrMode::Absent;
  double value = 0;
  int count = 1;
};

struct FilePlan {
  std::string name = "surface";
  bool as_group = false;  // "surface" is a group, not a dataset
  int rank = 2;
  std::vector<hsize_t> dims;
  int type = 0;  // index into file_type()
  int layout = 0;  // 0 contiguous, 1 compact, 2 chunked
  std::vector<hsize_t> chunk;
  bool shuffle = false, deflate = false, fletcher = false;
  bool written = true;
  std::vector<unsigned char> data;
  AttrPlan lx, ly;
};

constexpr int kNumericTypes = 13;  // file_type(0 .. kNumericTypes-1) are numeric
hid_t file_type(int k, Ids& ids) {
  switch (k) {
    case 0: return H5T_IEEE_F64LE;
    case 1: return H5T_IEEE_F64BE;
    case 2: return H5T_IEEE_F32LE;
    case 3: return H5T_IEEE_F32BE;
    case 4: return H5T_STD_I8LE;
    case 5: return H5T_STD_U8LE;
    case 6: return H5T_STD_I16BE;
    case 7: return H5T_STD_I32LE;
    case 8: return H5T_STD_U32BE;
    case 9: return H5T_STD_I64LE;
    case 10: return H5T_STD_U64LE;
    case 11: return H5T_NATIVE_LDOUBLE;
    case 12: {  // IEEE half precision, as a user-defined float
      const hid_t t = ids.add(H5Tcopy(H5T_IEEE_F32LE), H5Tclose);
      if (t < 0 || H5Tset_fields(t, 15, 10, 5, 0, 10) < 0 || H5Tset_size(t, 2) < 0 || H5Tset_ebias(t, 15) < 0)
        return -1;
      return t;
    }
    case 13: {
      const hid_t t = ids.add(H5Tcopy(H5T_C_S1), H5Tclose);
      return t >= 0 && H5Tset_size(t, 8) >= 0 ? t : -1;
    }
    case 14: {
      const hid_t t = ids.add(H5Tcreate(H5T_COMPOUND, 16), H5Tclose);
      if (t < 0 || H5Tinsert(t, "re", 0, H5T_NATIVE_DOUBLE) < 0 || H5Tinsert(t, "im", 8, H5T_NATIVE_DOUBLE) < 0)
        return -1;
      return t;
    }
    default: {
      const hid_t t = ids.add(H5Tenum_create(H5T_NATIVE_INT), H5Tclose);
      int a = 0, b = 1;
      if (t < 0 || H5Tenum_insert(t, "a", &a) < 0 || H5Tenum_insert(t, "b", &b) < 0) return -1;
      return t;
    }
  }
}

AttrPlan attr_plan(FuzzedDataProvider& in) {
  AttrPlan a;
  a.mode = in.PickValueInArray({AttrMode::Double, AttrMode::Double, AttrMode::Double, AttrMode::Absent, AttrMode::Int,
                                AttrMode::OneElementArray, AttrMode::ManyElements, AttrMode::String, AttrMode::OnFile});
  a.value = in.PickValueInArray({1e-4, 1.0, 2.5e-3, 0.0, -1.0, std::numeric_limits<double>::quiet_NaN(),
                                 std::numeric_limits<double>::infinity(), 1e308, 5e-324});
  if (in.ConsumeBool()) a.value = in.ConsumeFloatingPoint<double>();
  a.count = in.ConsumeIntegralInRange(2, 5);
  return a;
}

FilePlan plan(FuzzedDataProvider& in) {
  FilePlan p;
  p.name = in.PickValueInArray({"surface", "surface", "surface", "surface", "heights", "group/surface"});
  p.as_group = in.ConsumeIntegralInRange(0, 15) == 0;
  p.rank = in.PickValueInArray({2, 2, 2, 2, 2, 0, 1, 3});
  // Mostly small extents with data; sometimes a huge declared extent (never written:
  // the file holds almost nothing, the reader must not believe it).
  const bool huge = in.ConsumeIntegralInRange(0, 15) == 0;
  for (int r = 0; r < p.rank; ++r)
    p.dims.push_back(huge ? in.ConsumeIntegralInRange<hsize_t>(1, hsize_t(1) << 22) : in.ConsumeIntegralInRange<hsize_t>(0, 24));
  p.type = in.ConsumeIntegralInRange(0, kNumericTypes + 2);
  p.layout = in.ConsumeIntegralInRange(0, 2);
  for (int r = 0; r < p.rank; ++r) p.chunk.push_back(in.ConsumeIntegralInRange<hsize_t>(1, std::max<hsize_t>(1, std::min<hsize_t>(p.dims[std::size_t(r)], 64))));
  p.shuffle = in.ConsumeBool();
  p.deflate = in.ConsumeBool();
  p.fletcher = in.ConsumeBool();
  p.written = !huge && in.ConsumeIntegralInRange(0, 7) != 0;
  p.lx = attr_plan(in);
  p.ly = attr_plan(in);
  p.data = in.ConsumeRemainingBytes<unsigned char>();
  return p;
}

bool write_attr(hid_t obj, const char* name, const AttrPlan& a) {
  Ids ids;
  hid_t space = -1, type = H5T_NATIVE_DOUBLE;
  std::vector<double> dv(std::size_t(a.count), a.value);
  const int iv = std::isfinite(a.value) && std::abs(a.value) < 2e9 ? int(a.value) : 7;
  const char text[8] = "0.001";
  const void* buf = &a.value;
  switch (a.mode) {
    case AttrMode::Absent: return true;
    case AttrMode::Double:
    case AttrMode::OnFile: space = ids.add(H5Screate(H5S_SCALAR), H5Sclose); break;
    case AttrMode::Int:
      space = ids.add(H5Screate(H5S_SCALAR), H5Sclose);
      type = H5T_NATIVE_INT;
      buf = &iv;
      break;
    case AttrMode::OneElementArray:
    case AttrMode::ManyElements: {
      const hsize_t n = a.mode == AttrMode::OneElementArray ? 1 : hsize_t(a.count);
      space = ids.add(H5Screate_simple(1, &n, nullptr), H5Sclose);
      buf = dv.data();
      break;
    }
    case AttrMode::String:
      space = ids.add(H5Screate(H5S_SCALAR), H5Sclose);
      type = ids.add(H5Tcopy(H5T_C_S1), H5Tclose);
      if (type < 0 || H5Tset_size(type, sizeof text) < 0) return false;
      buf = text;
      break;
  }
  const hid_t attr = ids.add(H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  return attr >= 0 && H5Awrite(attr, type, buf) >= 0;
}

// Writes the planned file; false if HDF5 refuses the combination (then nothing is tested).
bool write_file(const std::string& path, const FilePlan& p) {
  Ids ids;
  const hid_t f = ids.add(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
  if (f < 0) return false;
  if (p.as_group) return ids.add(H5Gcreate2(f, "surface", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose) >= 0;
  const hid_t type = file_type(p.type, ids);
  if (type < 0) return false;
  const hid_t space = ids.add(p.rank == 0 ? H5Screate(H5S_SCALAR) : H5Screate_simple(p.rank, p.dims.data(), nullptr), H5Sclose);
  if (space < 0) return false;
  const hid_t dcpl = ids.add(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  const hid_t lcpl = ids.add(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  if (dcpl < 0 || lcpl < 0 || H5Pset_create_intermediate_group(lcpl, 1) < 0) return false;
  hssize_t points = H5Sget_simple_extent_npoints(space);
  const std::size_t bytes = std::size_t(points) * H5Tget_size(type);
  if (p.layout == 1) {
    if (bytes > 60000 || H5Pset_layout(dcpl, H5D_COMPACT) < 0) return false;
  } else if (p.layout == 2 && p.rank > 0) {
    // HDF5 sends every chunk through the filter pipeline when the file is written: 24³ points
    // in one-point chunks with shuffle, deflate and Fletcher-32 took 2 s under ASan, past
    // libFuzzer's 1 s timeout (as a CI fuzz run showed). That is the harness's
    // own writing, not the reader, so plans with that many chunks are skipped.
    double chunks = 1.0;
    for (std::size_t r = 0; r < p.chunk.size(); ++r) {
      if (p.chunk[r] == 0) return false;
      chunks *= std::ceil(double(p.dims[r]) / double(p.chunk[r]));
    }
    if (p.written && chunks > kMaxChunks) return false;
    if (H5Pset_chunk(dcpl, p.rank, p.chunk.data()) < 0) return false;
    if (p.shuffle && H5Pset_shuffle(dcpl) < 0) return false;
    if (p.deflate && H5Pset_deflate(dcpl, 6) < 0) return false;
    if (p.fletcher && H5Pset_fletcher32(dcpl) < 0) return false;
  }
  const hid_t d = ids.add(H5Dcreate2(f, p.name.c_str(), type, space, lcpl, dcpl, H5P_DEFAULT), H5Dclose);
  if (d < 0) return false;
  if (p.written && points > 0) {
    if (bytes > kMaxBytes) return false;
    std::vector<unsigned char> raw(bytes, 0);
    if (!p.data.empty()) std::memcpy(raw.data(), p.data.data(), std::min(bytes, p.data.size()));
    if (H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data()) < 0) return false;
  }
  if (!write_attr(p.lx.mode == AttrMode::OnFile ? f : d, "lx", p.lx)) return false;
  if (!write_attr(p.ly.mode == AttrMode::OnFile ? f : d, "ly", p.ly)) return false;
  return true;
}

// What the reader must give: the dataset converted to double by HDF5 (before the height
// scale), or nothing when it must refuse the file (for the reason given).
struct Expected {
  std::optional<std::string> refuse;
  int nx = 0, ny = 0;
  std::vector<double> heights;
};

Expected expected(const std::string& path, const FilePlan& p) {
  Expected e;
  if (p.as_group || p.name != "surface") return e.refuse = "no dataset 'surface'", e;
  if (p.rank != 2) return e.refuse = "rank " + std::to_string(p.rank), e;
  if (p.dims[0] == 0 || p.dims[1] == 0) return e.refuse = "empty extent", e;
  if (p.type >= kNumericTypes) return e.refuse = "not numeric", e;
  if (!p.written && p.layout != 1) return e.refuse = "data never written", e;  // compact: always allocated
  e.ny = int(p.dims[0]);
  e.nx = int(p.dims[1]);
  e.heights.resize(std::size_t(e.nx) * std::size_t(e.ny));
  Ids ids;
  const hid_t f = ids.add(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  const hid_t d = ids.add(H5Dopen2(f, "surface", H5P_DEFAULT), H5Dclose);
  if (d < 0 || H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, e.heights.data()) < 0)
    cmc::fuzz::fail("the target could not read back the file it wrote");
  for (double h : e.heights)
    if (!std::isfinite(h)) return e.refuse = "a non-finite height", e;
  return e;
}

std::optional<std::string> size_refusal(const AttrPlan& a) {
  switch (a.mode) {
    case AttrMode::Absent:
    case AttrMode::OnFile: return "size attribute absent from the dataset";
    case AttrMode::ManyElements: return "size attribute of several elements";
    case AttrMode::String: return "size attribute not a number";
    case AttrMode::Int: {
      const double v = std::isfinite(a.value) && std::abs(a.value) < 2e9 ? double(int(a.value)) : 7.0;
      return v > 0 ? std::nullopt : std::optional<std::string>("size attribute not positive");
    }
    default: return std::isfinite(a.value) && a.value > 0 ? std::nullopt : std::optional<std::string>("size attribute not positive and finite");
  }
}
double size_value(const AttrPlan& a) {
  if (a.mode == AttrMode::Int) return std::isfinite(a.value) && std::abs(a.value) < 2e9 ? double(int(a.value)) : 7.0;
  return a.value;
}

template <class Read>
void check_read(const char* what, const Expected& e, std::optional<std::string> refuse, bool square, double lx,
                double ly, double scale, Read&& read) {
  if (!refuse) refuse = e.refuse;
  if (!refuse && square && e.nx != e.ny) refuse = "not square";
  try {
    const cmc::HeightMap m = read();
    require(!refuse, std::string(what) + " read a file it must refuse (" + refuse.value_or("") + ")");
    require(m.grid.nx == e.nx && m.grid.ny == e.ny, std::string(what) + ": wrong grid " + std::to_string(m.grid.nx) +
                                                        " x " + std::to_string(m.grid.ny));
    require(m.grid.lx == lx && m.grid.ly == ly, std::string(what) + ": wrong box size");
    require(m.heights.size() == e.heights.size(), std::string(what) + ": wrong number of heights");
    for (std::size_t i = 0; i < e.heights.size(); ++i)
      require(m.heights[i] == e.heights[i] * scale,
              std::string(what) + ": height " + std::to_string(i) + " differs from the file");
  } catch (const cmc::SurfaceFileError& err) {
    require(bool(refuse), std::string(what) + " refused a good file: " + err.what());
  } catch (const std::exception& err) {
    cmc::fuzz::fail(std::string(what) + " threw something other than SurfaceFileError: " + err.what());
  }
  const ssize_t open = H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL);
  require(open == 0, std::string(what) + " left " + std::to_string(open) + " HDF5 object(s) open");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static cmc::fuzz::TempFile file("surface.h5");
  static const bool quiet = (H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr), true);
  (void)quiet;
  FuzzedDataProvider in(data, size);
  const FilePlan p = plan(in);
  if (!write_file(file.path(), p)) return 0;
  require(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL) == 0, "the target left HDF5 objects open");
  const Expected e = expected(file.path(), p);
  std::optional<std::string> by_attrs = size_refusal(p.lx);
  if (!by_attrs) by_attrs = size_refusal(p.ly);
  check_read("read_hdf5_heights (size from attributes)", e, by_attrs, false, size_value(p.lx), size_value(p.ly), kScale,
             [&] { return cmc::read_hdf5_heights(file.path(), "surface", 0.0, 0.0, kScale); });
  check_read("read_hdf5_heights (size given)", e, std::nullopt, false, 2e-4, 1e-4, kScale,
             [&] { return cmc::read_hdf5_heights(file.path(), "surface", 2e-4, 1e-4, kScale); });
  check_read("read_challenge_hdf5", e, std::nullopt, true, 1.0, 1.0, 1.0,
             [&] { return cmc::read_challenge_hdf5(file.path()); });
  return 0;
}
