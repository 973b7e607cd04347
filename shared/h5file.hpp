// SPDX-License-Identifier: MIT
// Thin RAII wrapper over the HDF5 C API: the few operations the run files need (datasets of
// doubles, string/number attributes, extendible time-series tables, copying objects between files
// and listing them), groups made on demand.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace dld {

class H5File {
 public:
  enum class Mode { kCreate, kRead, kReadWrite };
  /// kCreate truncates. Errors become InputError naming the file.
  H5File(const std::string& path, Mode mode);
  ~H5File();
  H5File(const H5File&) = delete;
  H5File& operator=(const H5File&) = delete;
  H5File(H5File&& o) noexcept;
  H5File& operator=(H5File&& o) noexcept;

  const std::string& path() const { return path_; }

  /// n-D dataset of doubles (row-major dims); replaces an existing one of the same name.
  void write(const std::string& name, const double* data, const std::vector<std::uint64_t>& dims);
  void write(const std::string& name, const std::vector<double>& data) {
    write(name, data.data(), {data.size()});
  }
  void write(const std::string& name, const float* data, const std::vector<std::uint64_t>& dims);
  void write(const std::string& name, const std::int32_t* data,
             const std::vector<std::uint64_t>& dims);
  /// Attribute on an object (group or dataset path; "/" is the file).
  void attribute(const std::string& object, const std::string& name, double value);
  void attribute(const std::string& object, const std::string& name, std::int64_t value);
  void attribute(const std::string& object, const std::string& name, const std::string& value);
  /// Appends one row to a 2-D table of `row.size()` columns, creating it (chunked, unlimited rows)
  /// on first use with the given column names stored as a "columns" attribute.
  void append_row(const std::string& name, const std::vector<double>& row,
                  const std::vector<std::string>& columns = {});
  /// Appends `count` slabs of shape `slab` (row-major) along the first dimension of an n-D
  /// dataset of doubles (count x slab...), creating it chunked with an unlimited first dimension
  /// on first use: a time series of arrays that grows as a run goes (e.g. node positions).
  void append(const std::string& name, const double* data, std::uint64_t count,
              const std::vector<std::uint64_t>& slab);
  /// Shortens (or lengthens) an extendible dataset along its first dimension to `rows`.
  void resize(const std::string& name, std::uint64_t rows);
  /// `name`: a virtual dataset (HDF5 VDS, no copy of the data) showing slab `index` of the n-D
  /// dataset `source` of this file (its shape without the first dimension), for readers that
  /// take whole datasets only (ParaView's XDMF 3 reader cannot select a hyperslab).
  void view_slab(const std::string& name, const std::string& source, std::uint64_t index);
  /// Removes a dataset or group (its link); absent is not an error.
  void remove(const std::string& name);
  void flush();
  /// Closes the file now and reports a failure to write it out (the destructor cannot): a file
  /// that is renamed into place afterwards must be complete.
  void close();

  /// Copies `object` of `source` ("/" is the whole file: its root group and root attributes) to
  /// `name` in this file, with everything below it and its attributes (H5Ocopy: the copy needs
  /// nothing of the source afterwards, unlike an external link).
  void copy_from(const H5File& source, const std::string& object, const std::string& name);

  bool exists(const std::string& name) const;
  /// Names of the members of a group ("/" is the file), in name order.
  std::vector<std::string> members(const std::string& group) const;
  /// Paths of every dataset below a group, relative to it ("cells/samples"), in name order.
  std::vector<std::string> datasets(const std::string& group = "/") const;
  /// Reads a dataset of doubles (any float type is converted); dims returned through `dims`.
  std::vector<double> read(const std::string& name,
                           std::vector<std::uint64_t>* dims = nullptr) const;
  bool has_attribute(const std::string& object, const std::string& name) const;
  double read_attribute_number(const std::string& object, const std::string& name) const;
  /// A fixed-length string attribute (as attribute() writes); another type is an InputError.
  std::string read_attribute_string(const std::string& object, const std::string& name) const;

 private:
  void make_parents(const std::string& name);
  std::int64_t id_ = -1;
  std::string path_;
};

}  // namespace dld
