// SPDX-License-Identifier: MIT
#include "shared/h5file.hpp"

#include <fmt/format.h>
#include <hdf5.h>

#include <algorithm>

#include "shared/input_error.hpp"

namespace dld {
namespace {

void check(herr_t status, const std::string& path, const std::string& what) {
  if (status < 0) throw InputError(fmt::format("{}: HDF5 error while {}", path, what));
}

hid_t checked_id(hid_t id, const std::string& path, const std::string& what) {
  if (id < 0) throw InputError(fmt::format("{}: HDF5 error while {}", path, what));
  return id;
}

struct Id {  // closes any HDF5 handle with the right function
  hid_t id;
  herr_t (*close)(hid_t);
  ~Id() {
    if (id >= 0) close(id);
  }
};

}  // namespace

H5File::H5File(const std::string& path, Mode mode) : path_(path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are reported through InputError
  switch (mode) {
    case Mode::kCreate:
      id_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
      break;
    case Mode::kRead:
      id_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
      break;
    case Mode::kReadWrite:
      id_ = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
      break;
  }
  if (id_ < 0)
    throw InputError(
        fmt::format("{}: cannot {} HDF5 file", path, mode == Mode::kCreate ? "create" : "open"));
}

H5File::~H5File() {
  if (id_ >= 0) H5Fclose(id_);
}

H5File::H5File(H5File&& o) noexcept : id_(o.id_), path_(std::move(o.path_)) {
  o.id_ = -1;
}

H5File& H5File::operator=(H5File&& o) noexcept {
  if (this != &o) {
    if (id_ >= 0) H5Fclose(id_);
    id_ = o.id_;
    path_ = std::move(o.path_);
    o.id_ = -1;
  }
  return *this;
}

bool H5File::exists(const std::string& name) const {
  // Walk the path so that a missing intermediate group is not an error.
  std::size_t pos = 0;
  while ((pos = name.find('/', pos + 1)) != std::string::npos) {
    if (H5Lexists(id_, name.substr(0, pos).c_str(), H5P_DEFAULT) <= 0) return false;
  }
  return H5Lexists(id_, name.c_str(), H5P_DEFAULT) > 0;
}

void H5File::make_parents(const std::string& name) {
  std::size_t pos = 0;
  while ((pos = name.find('/', pos + 1)) != std::string::npos) {
    std::string g = name.substr(0, pos);
    if (H5Lexists(id_, g.c_str(), H5P_DEFAULT) <= 0) {
      Id gid{checked_id(H5Gcreate2(id_, g.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), path_,
                        "creating group " + g),
             H5Gclose};
    }
  }
}

namespace {
template <typename T>
void write_any(hid_t file, const std::string& path, const std::string& name, hid_t memtype,
               hid_t filetype, const T* data, const std::vector<std::uint64_t>& dims) {
  if (H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0) H5Ldelete(file, name.c_str(), H5P_DEFAULT);
  std::vector<hsize_t> d(dims.begin(), dims.end());
  Id space{checked_id(H5Screate_simple(static_cast<int>(d.size()), d.data(), nullptr), path,
                      "creating dataspace"),
           H5Sclose};
  Id set{checked_id(H5Dcreate2(file, name.c_str(), filetype, space.id, H5P_DEFAULT, H5P_DEFAULT,
                               H5P_DEFAULT),
                    path, "creating dataset " + name),
         H5Dclose};
  check(H5Dwrite(set.id, memtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), path, "writing " + name);
}
}  // namespace

void H5File::write(const std::string& name, const double* data,
                   const std::vector<std::uint64_t>& dims) {
  make_parents(name);
  write_any(id_, path_, name, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, data, dims);
}

void H5File::write(const std::string& name, const float* data,
                   const std::vector<std::uint64_t>& dims) {
  make_parents(name);
  write_any(id_, path_, name, H5T_NATIVE_FLOAT, H5T_IEEE_F32LE, data, dims);
}

void H5File::write(const std::string& name, const std::int32_t* data,
                   const std::vector<std::uint64_t>& dims) {
  make_parents(name);
  write_any(id_, path_, name, H5T_NATIVE_INT32, H5T_STD_I32LE, data, dims);
}

namespace {
hid_t open_object(hid_t file, const std::string& path, const std::string& object) {
  return checked_id(H5Oopen(file, object.c_str(), H5P_DEFAULT), path, "opening " + object);
}
void write_attr(hid_t obj, const std::string& path, const std::string& name, hid_t type,
                const void* value) {
  if (H5Aexists(obj, name.c_str()) > 0) H5Adelete(obj, name.c_str());
  Id space{H5Screate(H5S_SCALAR), H5Sclose};
  Id attr{checked_id(H5Acreate2(obj, name.c_str(), type, space.id, H5P_DEFAULT, H5P_DEFAULT), path,
                     "creating attribute " + name),
          H5Aclose};
  check(H5Awrite(attr.id, type, value), path, "writing attribute " + name);
}
}  // namespace

void H5File::attribute(const std::string& object, const std::string& name, double value) {
  if (object != "/") make_parents(object + "/x");
  Id obj{open_object(id_, path_, object), H5Oclose};
  write_attr(obj.id, path_, name, H5T_NATIVE_DOUBLE, &value);
}

void H5File::attribute(const std::string& object, const std::string& name, std::int64_t value) {
  if (object != "/") make_parents(object + "/x");
  Id obj{open_object(id_, path_, object), H5Oclose};
  write_attr(obj.id, path_, name, H5T_NATIVE_INT64, &value);
}

void H5File::attribute(const std::string& object, const std::string& name,
                       const std::string& value) {
  if (object != "/") make_parents(object + "/x");
  Id obj{open_object(id_, path_, object), H5Oclose};
  Id type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, value.size() + 1);
  H5Tset_strpad(type.id, H5T_STR_NULLTERM);
  write_attr(obj.id, path_, name, type.id, value.c_str());
}

void H5File::append_row(const std::string& name, const std::vector<double>& row,
                        const std::vector<std::string>& columns) {
  const hsize_t width = row.size();
  if (H5Lexists(id_, name.c_str(), H5P_DEFAULT) <= 0 || !exists(name)) {
    make_parents(name);
    hsize_t dims[2] = {0, width};
    hsize_t maxd[2] = {H5S_UNLIMITED, width};
    hsize_t chunk[2] = {256, width};
    Id space{H5Screate_simple(2, dims, maxd), H5Sclose};
    Id plist{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
    H5Pset_chunk(plist.id, 2, chunk);
    Id set{checked_id(H5Dcreate2(id_, name.c_str(), H5T_IEEE_F64LE, space.id, H5P_DEFAULT, plist.id,
                                 H5P_DEFAULT),
                      path_, "creating table " + name),
           H5Dclose};
    if (!columns.empty()) {
      std::string joined;
      for (std::size_t i = 0; i < columns.size(); ++i) joined += (i ? "," : "") + columns[i];
      Id type{H5Tcopy(H5T_C_S1), H5Tclose};
      H5Tset_size(type.id, joined.size() + 1);
      write_attr(set.id, path_, "columns", type.id, joined.c_str());
    }
  }
  Id set{checked_id(H5Dopen2(id_, name.c_str(), H5P_DEFAULT), path_, "opening " + name), H5Dclose};
  Id fspace0{H5Dget_space(set.id), H5Sclose};
  hsize_t cur[2];
  H5Sget_simple_extent_dims(fspace0.id, cur, nullptr);
  if (cur[1] != width)
    throw InputError(
        fmt::format("{}: table {} has {} columns, row has {}", path_, name, cur[1], width));
  hsize_t next[2] = {cur[0] + 1, width};
  check(H5Dset_extent(set.id, next), path_, "extending " + name);
  Id fspace{H5Dget_space(set.id), H5Sclose};
  hsize_t start[2] = {cur[0], 0};
  hsize_t count[2] = {1, width};
  H5Sselect_hyperslab(fspace.id, H5S_SELECT_SET, start, nullptr, count, nullptr);
  Id mspace{H5Screate_simple(2, count, nullptr), H5Sclose};
  check(H5Dwrite(set.id, H5T_NATIVE_DOUBLE, mspace.id, fspace.id, H5P_DEFAULT, row.data()), path_,
        "appending to " + name);
}

void H5File::append(const std::string& name, const double* data, std::uint64_t count,
                    const std::vector<std::uint64_t>& slab) {
  const int rank = static_cast<int>(slab.size()) + 1;
  std::vector<hsize_t> shape{0};
  shape.insert(shape.end(), slab.begin(), slab.end());
  hsize_t slab_size = 1;
  for (auto v : slab) slab_size *= v;
  if (!exists(name)) {
    make_parents(name);
    std::vector<hsize_t> maxd = shape, chunk = shape;
    maxd[0] = H5S_UNLIMITED;
    // About 1 MiB per chunk and at least one slab: a sample is read or written whole.
    chunk[0] = std::clamp<hsize_t>((1u << 20) / (8 * std::max<hsize_t>(slab_size, 1)), 1, 1024);
    Id space{H5Screate_simple(rank, shape.data(), maxd.data()), H5Sclose};
    Id plist{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
    H5Pset_chunk(plist.id, rank, chunk.data());
    Id set{checked_id(H5Dcreate2(id_, name.c_str(), H5T_IEEE_F64LE, space.id, H5P_DEFAULT, plist.id,
                                 H5P_DEFAULT),
                      path_, "creating dataset " + name),
           H5Dclose};
  }
  Id set{checked_id(H5Dopen2(id_, name.c_str(), H5P_DEFAULT), path_, "opening " + name), H5Dclose};
  Id fspace0{H5Dget_space(set.id), H5Sclose};
  std::vector<hsize_t> cur(static_cast<std::size_t>(rank));
  if (H5Sget_simple_extent_ndims(fspace0.id) != rank)
    throw InputError(fmt::format("{}: dataset {} is not of rank {}", path_, name, rank));
  H5Sget_simple_extent_dims(fspace0.id, cur.data(), nullptr);
  for (std::size_t i = 0; i < slab.size(); ++i)
    if (cur[i + 1] != slab[i])
      throw InputError(fmt::format("{}: dataset {} has another shape than the slab", path_, name));
  if (count == 0) return;
  std::vector<hsize_t> next = cur, start(cur.size(), 0), n = shape;
  next[0] = cur[0] + count;
  check(H5Dset_extent(set.id, next.data()), path_, "extending " + name);
  Id fspace{H5Dget_space(set.id), H5Sclose};
  start[0] = cur[0];
  n[0] = count;
  H5Sselect_hyperslab(fspace.id, H5S_SELECT_SET, start.data(), nullptr, n.data(), nullptr);
  Id mspace{H5Screate_simple(rank, n.data(), nullptr), H5Sclose};
  check(H5Dwrite(set.id, H5T_NATIVE_DOUBLE, mspace.id, fspace.id, H5P_DEFAULT, data), path_,
        "appending to " + name);
}

void H5File::resize(const std::string& name, std::uint64_t rows) {
  Id set{checked_id(H5Dopen2(id_, name.c_str(), H5P_DEFAULT), path_, "opening " + name), H5Dclose};
  Id space{H5Dget_space(set.id), H5Sclose};
  std::vector<hsize_t> d(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space.id)));
  H5Sget_simple_extent_dims(space.id, d.data(), nullptr);
  d[0] = rows;
  check(H5Dset_extent(set.id, d.data()), path_, "resizing " + name);
}

void H5File::view_slab(const std::string& name, const std::string& source, std::uint64_t index) {
  Id set{checked_id(H5Dopen2(id_, source.c_str(), H5P_DEFAULT), path_, "opening " + source),
         H5Dclose};
  Id src_space{H5Dget_space(set.id), H5Sclose};
  std::vector<hsize_t> d(static_cast<std::size_t>(H5Sget_simple_extent_ndims(src_space.id)));
  H5Sget_simple_extent_dims(src_space.id, d.data(), nullptr);
  std::vector<hsize_t> start(d.size(), 0), count = d;
  start[0] = index;
  count[0] = 1;
  check(H5Sselect_hyperslab(src_space.id, H5S_SELECT_SET, start.data(), nullptr, count.data(),
                            nullptr),
        path_, "selecting slab of " + source);
  Id view_space{checked_id(H5Screate_simple(static_cast<int>(d.size()) - 1, d.data() + 1, nullptr),
                           path_, "a dataspace for " + name),
                H5Sclose};
  Id dcpl{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
  check(H5Pset_virtual(dcpl.id, view_space.id, ".", source.c_str(), src_space.id), path_,
        "mapping " + name);
  make_parents(name);
  Id view{checked_id(H5Dcreate2(id_, name.c_str(), H5T_IEEE_F64LE, view_space.id, H5P_DEFAULT,
                                dcpl.id, H5P_DEFAULT),
                     path_, "creating " + name),
          H5Dclose};
}

void H5File::remove(const std::string& name) {
  if (!exists(name)) return;
  check(H5Ldelete(id_, name.c_str(), H5P_DEFAULT), path_, "removing " + name);
}

void H5File::flush() {
  H5Fflush(id_, H5F_SCOPE_GLOBAL);
}

void H5File::close() {
  if (id_ < 0) return;
  const hid_t id = id_;
  id_ = -1;
  check(H5Fclose(id), path_, "closing the file");
}

void H5File::copy_from(const H5File& source, const std::string& object, const std::string& name) {
  make_parents(name);
  check(H5Ocopy(source.id_, object.c_str(), id_, name.c_str(), H5P_DEFAULT, H5P_DEFAULT), path_,
        fmt::format("copying {} of {} to {}", object, source.path_, name));
}

std::vector<std::string> H5File::members(const std::string& group) const {
  Id g{checked_id(H5Gopen2(id_, group.c_str(), H5P_DEFAULT), path_, "opening group " + group),
       H5Gclose};
  H5G_info_t info;
  check(H5Gget_info(g.id, &info), path_, "listing " + group);
  std::vector<std::string> out;
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t n =
        H5Lget_name_by_idx(g.id, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (n < 0) throw InputError(fmt::format("{}: HDF5 error while listing {}", path_, group));
    std::string name(static_cast<std::size_t>(n) + 1, '\0');
    H5Lget_name_by_idx(g.id, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size(),
                       H5P_DEFAULT);
    name.resize(static_cast<std::size_t>(n));
    out.push_back(std::move(name));
  }
  return out;
}

std::vector<std::string> H5File::datasets(const std::string& group) const {
  std::vector<std::string> out;
  const std::string prefix = group == "/" ? "/" : group + "/";
  for (const std::string& m : members(group)) {
    // The object's kind through its handle: H5Oget_info changed signature between HDF5 versions.
    Id obj{open_object(id_, path_, prefix + m), H5Oclose};
    const H5I_type_t kind = H5Iget_type(obj.id);
    if (kind == H5I_DATASET) {
      out.push_back(m);
    } else if (kind == H5I_GROUP) {
      for (const std::string& d : datasets(prefix + m)) {
        std::string path = m;
        out.push_back(path.append("/").append(d));
      }
    }
  }
  return out;
}

std::vector<double> H5File::read(const std::string& name, std::vector<std::uint64_t>* dims) const {
  if (!exists(name)) throw InputError(fmt::format("{}: no dataset '{}'", path_, name));
  Id set{checked_id(H5Dopen2(id_, name.c_str(), H5P_DEFAULT), path_, "opening " + name), H5Dclose};
  Id space{H5Dget_space(set.id), H5Sclose};
  int rank = H5Sget_simple_extent_ndims(space.id);
  std::vector<hsize_t> d(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.id, d.data(), nullptr);
  std::size_t n = 1;
  for (auto v : d) n *= v;
  std::vector<double> out(n);
  if (n > 0)
    check(H5Dread(set.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), path_,
          "reading " + name);
  if (dims) dims->assign(d.begin(), d.end());
  return out;
}

bool H5File::has_attribute(const std::string& object, const std::string& name) const {
  Id obj{open_object(id_, path_, object), H5Oclose};
  return H5Aexists(obj.id, name.c_str()) > 0;
}

double H5File::read_attribute_number(const std::string& object, const std::string& name) const {
  Id obj{open_object(id_, path_, object), H5Oclose};
  if (H5Aexists(obj.id, name.c_str()) <= 0)
    throw InputError(fmt::format("{}: {} has no attribute '{}'", path_, object, name));
  Id attr{H5Aopen(obj.id, name.c_str(), H5P_DEFAULT), H5Aclose};
  double v = 0;
  check(H5Aread(attr.id, H5T_NATIVE_DOUBLE, &v), path_, "reading attribute " + name);
  return v;
}

std::string H5File::read_attribute_string(const std::string& object,
                                          const std::string& name) const {
  Id obj{open_object(id_, path_, object), H5Oclose};
  if (H5Aexists(obj.id, name.c_str()) <= 0)
    throw InputError(fmt::format("{}: {} has no attribute '{}'", path_, object, name));
  Id attr{H5Aopen(obj.id, name.c_str(), H5P_DEFAULT), H5Aclose};
  Id type{H5Aget_type(attr.id), H5Tclose};
  // Raw bytes of a number (or a pointer, for a variable-length string) would be read as text.
  if (H5Tget_class(type.id) != H5T_STRING || H5Tis_variable_str(type.id) > 0)
    throw InputError(
        fmt::format("{}: {} attribute '{}': expected a fixed-length string", path_, object, name));
  std::string s(H5Tget_size(type.id), '\0');
  check(H5Aread(attr.id, type.id, s.data()), path_, "reading attribute " + name);
  s.resize(s.find('\0') == std::string::npos ? s.size() : s.find('\0'));
  return s;
}

}  // namespace dld
