#include "mlce/reader/mbdyn_netcdf.hpp"

#include <netcdf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <fstream>
#include <limits>
#include <optional>

#include "mlce/reader/mbdyn_text.hpp"
#include "mlce/reader/orientation.hpp"
#include "mlce/reader/table.hpp"
#include "byte_codec.hpp"
#include "triplets.hpp"
#include "isolated_run.hpp"
#include "line_source.hpp"
#include "node_fields.hpp"

namespace mlce::reader {
namespace {

/// The first `n` bytes of the file (fewer when it is shorter or cannot be read): its format's magic.
std::string leading_bytes(const std::string& path, std::size_t n) {
  std::string bytes(n, '\0');
  std::ifstream in(path, std::ios::binary);
  in.read(bytes.data(), static_cast<std::streamsize>(n));
  bytes.resize(static_cast<std::size_t>(in.gcount()));
  return bytes;
}

/// libnetcdf trusts the counts of a classic-format header: one corrupted byte can make nc_open
/// allocate and copy for a minute (seen: 50 s and 15 GB for a flipped byte in a 0.5 MB file). The
/// header (NetCDF classic format specification: magic, numrecs, dim_list, gatt_list, var_list) is
/// walked here first, every count checked against the bytes left in the file, so that a corrupted
/// file is one error at once. Returns the file size for a classic file, nullopt for another format
/// (netCDF-4/HDF5: nc_open's business).
std::optional<std::uint64_t> check_classic_header(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  const std::uint64_t size = std::filesystem::file_size(path, ec);
  char magic[4] = {};
  if (!in || ec || !in.read(magic, 4) || magic[0] != 'C' || magic[1] != 'D' || magic[2] != 'F') return std::nullopt;
  const int version = static_cast<unsigned char>(magic[3]);
  if (version != 1 && version != 2 && version != 5) return std::nullopt;  // nc_open names it
  const bool wide = version == 5;                                          // 64-bit counts
  std::uint64_t pos = 4, count_at = 4;  // the read position; where the last count was read
  auto corrupt = [&](const std::string& what, std::uint64_t at) {
    return ReadError(path + ": corrupt NetCDF header at byte " + std::to_string(at) + ": " + what);
  };
  auto word = [&](int bytes) {
    unsigned char b[8] = {};
    if (!in.read(reinterpret_cast<char*>(b), bytes)) throw corrupt("the file ends inside its header", pos);
    pos += static_cast<std::uint64_t>(bytes);
    std::uint64_t v = 0;
    for (int k = 0; k < bytes; ++k) v = v << 8 | b[k];  // big-endian
    return v;
  };
  auto count = [&] {
    count_at = pos;
    return word(wide ? 8 : 4);
  };
  auto fits = [&](std::uint64_t items, std::uint64_t min_bytes, const char* what) {  // the last count's items
    if (items > (size - pos) / min_bytes)
      throw corrupt(std::to_string(items) + " " + what + " cannot fit in the file's " + std::to_string(size) + " bytes",
                    count_at);
  };
  auto skip = [&](std::uint64_t bytes) {
    fits(bytes, 1, "bytes");
    in.seekg(static_cast<std::streamoff>(bytes), std::ios::cur);
    pos += bytes;
  };
  auto name = [&] {
    const std::uint64_t length = count();
    fits(length, 1, "name bytes");
    skip((length + 3) / 4 * 4);
  };
  auto list = [&](std::uint64_t tag, std::uint64_t min_bytes, const char* what) {
    const std::uint64_t t = word(4), n = count();
    if (t == 0 && n == 0) return std::uint64_t{0};  // ABSENT
    if (t != tag) throw corrupt("expected the " + std::string(what) + " list", count_at - 4);
    fits(n, min_bytes, what);
    return n;
  };
  // A classic file holds types 1-6 (CDF-5: 1-11). libnetcdf 4.9 takes a variable of another type,
  // sizes it 0, and its size check (NC_check_vlen) then divides by that 0: SIGFPE inside nc_open
  // (type 12, NC_STRING, found by fuzz_netcdf).
  auto type = [&](const char* of) {
    const std::uint64_t t = word(4);
    if (t == 0 || t > (wide ? 11u : 6u)) throw corrupt(std::string(of) + " type " + std::to_string(t), pos - 4);
    return t;
  };
  auto attributes = [&] {
    for (std::uint64_t a = list(0x0C, 12, "attributes"); a > 0; --a) {
      name();
      static constexpr std::uint64_t kBytes[] = {0, 1, 1, 2, 4, 4, 8, 1, 2, 4, 8, 8};  // by nc_type
      const std::uint64_t t = type("attribute"), n = count();
      fits(n, kBytes[t], "attribute values");
      skip((n * kBytes[t] + 3) / 4 * 4);
    }
  };
  word(wide ? 8 : 4);  // numrecs (the reader caps it by the file size)
  const std::uint64_t dims = list(0x0A, 8, "dimensions");
  for (std::uint64_t d = 0; d < dims; ++d) name(), count();
  attributes();
  for (std::uint64_t v = list(0x0B, 28, "variables"); v > 0; --v) {
    name();
    const std::uint64_t rank = count();
    fits(rank, wide ? 8 : 4, "dimension ids");
    for (std::uint64_t k = 0; k < rank; ++k)
      if (count() >= dims) throw corrupt("a variable's dimension id beyond the " + std::to_string(dims) + " dimensions", count_at);
    attributes();
    type("variable");
    word(wide ? 8 : 4), word(version == 1 ? 4 : 8);  // vsize, begin
  }
  return size;
}

class NcFile {
 public:
  explicit NcFile(const std::string& path) : path_(path) {
    // A record holds at least its 8-byte time: a corrupted record count must not size a vector.
    if (const auto size = check_classic_header(path)) max_records_ = *size / 8;
    const int rc = nc_open(path.c_str(), NC_NOWRITE, &id_);
    if (rc != NC_NOERR) {
      // A netCDF-4 file is HDF5 underneath, which keeps metadata at both ends: cut short it does not open at all.
      const bool hdf5 = leading_bytes(path, 4) == "\x89HDF";
      throw ReadError(path + ": cannot open as NetCDF (" + nc_strerror(rc) + ")" +
                      (hdf5 ? ": a netCDF-4 (HDF5) file, cut short or corrupt" : ""));
    }
  }
  ~NcFile() { nc_close(id_); }
  NcFile(const NcFile&) = delete;
  NcFile& operator=(const NcFile&) = delete;

  const std::string& path() const { return path_; }
  /// The records of the record variable `v` that the file can hold.
  std::size_t records(int v) const {
    const auto sh = shape(v);
    return sh.empty() ? 0 : static_cast<std::size_t>(std::min<std::uint64_t>(sh[0], max_records_));
  }
  std::optional<int> var(const std::string& name) const {
    int v = 0;
    if (nc_inq_varid(id_, name.c_str(), &v) != NC_NOERR) return std::nullopt;
    return v;
  }
  int require(const std::string& name, const std::string& why) const {
    const auto v = var(name);
    if (!v) throw ReadError(path_ + ": no variable '" + name + "' (" + why + ")");
    return *v;
  }
  bool first_dimension_is_unlimited(int v) const {
    int nd = 0, unlimited = -1;
    if (nc_inq_varndims(id_, v, &nd) != NC_NOERR || nd < 1 || nc_inq_unlimdim(id_, &unlimited) != NC_NOERR) return false;
    std::vector<int> dims(static_cast<std::size_t>(nd));
    nc_inq_vardimid(id_, v, dims.data());
    return unlimited >= 0 && dims[0] == unlimited;
  }
  std::vector<std::size_t> shape(int v) const {
    int nd = 0;
    nc_inq_varndims(id_, v, &nd);
    std::vector<int> dims(static_cast<std::size_t>(nd));
    nc_inq_vardimid(id_, v, dims.data());
    std::vector<std::size_t> out;
    for (int d : dims) {
      std::size_t len = 0;
      nc_inq_dimlen(id_, d, &len);
      out.push_back(len);
    }
    return out;
  }
  /// Component `comp` of a (time[, n]) or (time, n1, n2) variable, first `n` records; in the
  /// latter `comp` counts in storage order (comp = n2 * i + j for element [i][j]: MBDyn's .R).
  /// With `fill_tail_cut`, records at the end that hold the fill value are left out (the vector is
  /// shorter) rather than an error.
  std::vector<double> column(int v, std::size_t comp, std::size_t n, const std::string& name, bool fill_tail_cut = false) const {
    const auto sh = shape(v);
    std::vector<double> out(n);
    if (n == 0) return out;
    std::size_t width = 1;
    for (std::size_t d = 1; d < sh.size(); ++d) width *= sh[d];
    if (sh.empty() || sh.size() > 3 || comp >= width)
      throw ReadError(path_ + ": variable '" + name + "' has no component " + std::to_string(comp + 1));
    std::size_t start[3] = {0, comp, 0}, count[3] = {n, 1, 1};
    if (sh.size() == 3) start[1] = comp / sh[2], start[2] = comp % sh[2];
    const int rc = nc_get_vara_double(id_, v, start, count, out.data());
    if (rc != NC_NOERR) throw ReadError(path_ + ": reading '" + name + "': " + nc_strerror(rc));
    // A record the solver never wrote holds the fill value (the variable's _FillValue, else the
    // library's default): a finite number (9.97e36) that must not pass for data. MBDyn 1.7.3
    // declares some variables it never writes (revolute hinge, forces: format doc section 11).
    const double fill = fill_value(v);
    if (fill_tail_cut) {
      while (!out.empty() && out.back() == fill) out.pop_back();
      n = out.size();
    }
    for (std::size_t k = 0; k < n; ++k) {
      if (out[k] == fill)
        throw ReadError(path_ + ": '" + name + "' record " + std::to_string(k) +
                        ": holds the NetCDF fill value (never written by the solver)");
      if (!std::isfinite(out[k]))
        throw ReadError(path_ + ": '" + name + "' record " + std::to_string(k) + ": expected a finite number (did the run diverge? the records before it can be read alone)");
    }
    return out;
  }
  /// The variable's _FillValue, else the library's default: what a number the solver never wrote reads as.
  double fill_value(int v) const {
    double fill = NC_FILL_DOUBLE, declared = 0;
    if (nc_get_att_double(id_, v, "_FillValue", &declared) == NC_NOERR) fill = declared;
    return fill;
  }
  /// Every number of `v` as stored (row-major; fill values and all), its record dimension capped by the
  /// file's size. At most as many numbers as the file's bytes can hold (classic format), and never more
  /// than 3 x kLargestEigenanalysisMatrix^2 (a compressed netCDF-4 file).
  std::vector<double> values(int v, const std::string& name) const {
    auto sh = shape(v);
    if (!sh.empty() && first_dimension_is_unlimited(v)) sh[0] = records(v);
    constexpr std::uint64_t kMost = 3ULL * kLargestEigenanalysisMatrix * kLargestEigenanalysisMatrix;
    std::uint64_t total = 1;
    for (const std::size_t d : sh) {
      if (d != 0 && total > std::min(kMost, max_records_) / d)
        throw ReadError(path_ + ": '" + name + "' holds more numbers than " +
                        (max_records_ < kMost ? "the file's bytes can (a corrupt header)" : "this reader takes"));
      total *= d;
    }
    std::vector<double> out(static_cast<std::size_t>(total));
    if (total == 0) return out;
    const std::vector<std::size_t> start(sh.size(), 0);
    const int rc = nc_get_vara_double(id_, v, start.data(), sh.data(), out.data());
    if (rc != NC_NOERR) throw ReadError(path_ + ": reading '" + name + "': " + nc_strerror(rc));
    return out;
  }
  /// Records first .. first + count - 1 of the record variable `v` of shape (time, w), row-major, as stored.
  std::vector<double> records_of(int v, std::size_t first, std::size_t count, const std::string& name) const {
    const auto sh = shape(v);
    std::vector<double> out(count * (sh.size() == 2 ? sh[1] : 1));
    if (out.empty()) return out;
    const std::size_t start[2] = {first, 0}, counts[2] = {count, sh.size() == 2 ? sh[1] : 1};
    const int rc = nc_get_vara_double(id_, v, start, counts, out.data());
    if (rc != NC_NOERR) throw ReadError(path_ + ": reading '" + name + "': " + nc_strerror(rc));
    return out;
  }
  /// The length of dimension `name`, 0 when the file has none.
  std::size_t dimension_length(const char* name) const {
    int d = 0;
    std::size_t len = 0;
    if (nc_inq_dimid(id_, name, &d) != NC_NOERR || nc_inq_dimlen(id_, d, &len) != NC_NOERR) return 0;
    return len;
  }
  std::string text_attribute(int v, const char* att) const {
    std::size_t len = 0;
    if (nc_inq_attlen(id_, v, att, &len) != NC_NOERR) return {};
    std::string s(len, '\0');
    if (nc_get_att_text(id_, v, att, s.data()) != NC_NOERR) return {};
    while (!s.empty() && s.back() == '\0') s.pop_back();
    return s;
  }
  std::vector<std::string> variable_names() const {
    int n = 0;
    nc_inq_nvars(id_, &n);
    std::vector<std::string> out;
    char name[NC_MAX_NAME + 1];
    for (int v = 0; v < n; ++v)
      if (nc_inq_varname(id_, v, name) == NC_NOERR) out.emplace_back(name);
    return out;
  }
  std::vector<long> labels(const std::string& var_name) const {
    const auto v = var(var_name);
    if (!v) return {};
    const auto sh = shape(*v);
    if (sh.size() != 1) return {};
    std::vector<int> l(sh[0]);
    if (!l.empty() && nc_get_var_int(id_, *v, l.data()) != NC_NOERR) return {};
    return {l.begin(), l.end()};
  }

 private:
  std::string path_;
  int id_ = -1;
  std::uint64_t max_records_ = std::numeric_limits<std::uint64_t>::max();
};

/// What a channel of a node or joint (`what`: "structural node", "joint") of `group` ("node.struct",
/// "elem.joint") that writes no `group.L<data_suffix>` variable gets: the file's label list may hold
/// it with its output off (MBDyn lists every element, outputs some), or not at all; either way the
/// labels that do write output are named, as the text reader names a block's labels.
[[noreturn]] void no_output(const NcFile& nc, const std::string& what, const std::string& group, long label,
                            const std::string& data_suffix) {
  const auto listed = nc.labels(group);
  std::string message = nc.path() + ": ";
  const std::string id = what + ' ' + std::to_string(label);
  if (std::find(listed.begin(), listed.end(), label) != listed.end())
    message.append(id).append(" writes no output in this file (listed in '").append(group).append("', no '")
        .append(group).append(".").append(std::to_string(label)).append(data_suffix).append("')");
  else
    message.append("no ").append(id);
  std::string with_output;
  for (long l : listed)
    if (nc.var(group + '.' + std::to_string(l) + data_suffix)) with_output.append(" ").append(std::to_string(l));
  message.append(with_output.empty() ? std::string("; none writes output") : "; with output:" + with_output);
  throw ReadError(message);
}

struct NodeOrientation {
  Orientation kind;
  std::string var;  ///< full variable name
};

NodeOrientation node_orientation(const NcFile& nc, long label) {
  const std::string base = "node.struct." + std::to_string(label);
  if (auto v = nc.var(base + ".E")) {
    const std::string d = nc.text_attribute(*v, "description");
    Orientation o = Orientation::euler123;
    if (d.find("313") != std::string::npos) o = Orientation::euler313;
    else if (d.find("321") != std::string::npos) o = Orientation::euler321;
    return {o, base + ".E"};
  }
  if (nc.var(base + ".Phi")) return {Orientation::phi, base + ".Phi"};
  if (nc.var(base + ".R")) return {Orientation::mat, base + ".R"};
  if (!nc.var(base + ".X")) no_output(nc, "structural node", "node.struct", label, ".X");
  return {Orientation::none, ""};
}

/// Storage index of the r-th (0-based) number of a 3x3 matrix as a text file writes it: row by
/// row there, column-major in NetCDF (format doc section 11: R11, R21, R31, R12, ...), so R(i,j),
/// text number 3i+j, is stored at 3j+i.
constexpr std::size_t matrix_storage_index(std::size_t r) { return 3 * (r % 3) + r / 3; }

/// Values per record of a variable of shape `sh` (time first).
std::size_t components(const std::vector<std::size_t>& sh) {
  std::size_t width = 1;
  for (std::size_t d = 1; d < sh.size(); ++d) width *= sh[d];
  return width;
}

/// A variable along the record (unlimited) dimension, of at most two more: a time history.
bool is_record_variable(const NcFile& nc, int v) {
  const auto sh = nc.shape(v);
  return !sh.empty() && sh.size() <= 3 && nc.first_dimension_is_unlimited(v);
}

/// Orientation number `r` (0-based) of every record as the text file would write it.
std::vector<double> orientation_column(const NcFile& nc, const NodeOrientation& o, std::size_t r, std::size_t n) {
  const std::size_t comp = o.kind == Orientation::mat ? matrix_storage_index(r) : r;
  return nc.column(nc.require(o.var, "orientation"), comp, n, o.var);
}

std::vector<std::vector<double>> orientation_columns(const NcFile& nc, const NodeOrientation& o, std::size_t n) {
  std::vector<std::vector<double>> cols;
  for (std::size_t r = 0; r < orientation_size(o.kind); ++r) cols.push_back(orientation_column(nc, o, r, n));
  return cols;
}

/// (variable, storage component) of column K (1-based) of a joint row as the .jnt file would hold
/// it; a matrix variable (time, 3, 3), e.g. a revolute hinge's .R, is written row by row there.
std::pair<std::string, std::size_t> joint_column(const NcFile& nc, long label, std::size_t K) {
  const std::string base = "elem.joint." + std::to_string(label);
  if (!nc.var(base + ".f")) no_output(nc, "joint", "elem.joint", label, ".f");
  std::vector<std::string> order = {base + ".f", base + ".m", base + ".F", base + ".M"};
  const std::string prefix = base + ".";
  for (const auto& name : nc.variable_names())
    if (name.rfind(prefix, 0) == 0 && std::find(order.begin(), order.end(), name) == order.end() &&
        name.find('.', prefix.size()) == std::string::npos)
      order.push_back(name);
  std::size_t col = 2;
  for (const auto& name : order) {
    const auto sh = nc.shape(*nc.var(name));
    std::size_t width = 1;
    for (std::size_t d = 1; d < sh.size(); ++d) width *= sh[d];
    const bool matrix = sh.size() == 3 && sh[1] == 3 && sh[2] == 3;
    if (K < col + width) return {name, matrix ? matrix_storage_index(K - col) : K - col};
    col += width;
  }
  throw ReadError(nc.path() + ": joint " + std::to_string(label) + " has " + std::to_string(col - 1) +
                  " columns, column " + std::to_string(K) + " requested");
}

const char* node_group_suffix(detail::NodeGroup g) {
  switch (g) {
    case detail::NodeGroup::position: return ".X";
    case detail::NodeGroup::velocity: return ".XP";
    case detail::NodeGroup::angular_velocity: return ".Omega";
    case detail::NodeGroup::acceleration: return ".XPP";
    case detail::NodeGroup::angular_acceleration: return ".OmegaP";
    default: return "";
  }
}

/// The time of every record the run wrote. MBDyn's sparse eigenanalysis matrices are (time, 3)
/// variables (DataManager::OutputEigSparseMatrices) whose triplets can outnumber the output steps: they
/// grow the record dimension past the run's last output, and those records' time holds the fill value.
/// They are left out, with a warning; a fill value before a written time stays an error.
std::vector<double> record_times(const NcFile& nc, int tv, std::size_t records, std::vector<std::string>& warnings) {
  auto time = nc.column(tv, 0, records, "time", true);
  if (time.size() < records)
    warnings.push_back(nc.path() + ": records " + std::to_string(time.size()) + ".." + std::to_string(records - 1) +
                       " hold no time (never written: the record dimension grown by another variable, e.g. an "
                       "eigenanalysis's sparse matrices); read the " + std::to_string(time.size()) + " before them");
  return time;
}

/// Records a truncated file really holds. The header's record count survives a copy or a disk that
/// was cut short, and the classic format reads the missing records as zeros: a time that falls back
/// to 0 and stays there marks them. The last record with a time is dropped too, because the
/// variables stored after `time` in it may be missing. Returns n when nothing is missing.
std::size_t records_written(const std::vector<double>& time, const std::string& path, std::vector<std::string>& warnings) {
  const std::size_t n = time.size();
  std::size_t k = n;
  while (k > 1 && time[k - 1] == 0.0) --k;
  if (k == n || !(time[k - 1] > 0.0)) return n;  // no zero tail, or a run that ends at t = 0
  char last_time[32];
  std::snprintf(last_time, sizeof last_time, "%.10g", time[k - 1]);
  warnings.push_back(path + ": records " + std::to_string(k) + ".." + std::to_string(n - 1) +
                     " have time 0 after t = " + last_time +
                     " (file truncated, or the run killed before its records were written): read the first " +
                     std::to_string(k - 1) + " records, the last one with a time left out as possibly incomplete");
  return k - 1;
}

/// Seconds the child reading a netCDF-4 file may take (MLCE_NETCDF4_TIME_LIMIT, else 60 s plus 1 s per
/// 10 MB: a sound file reads in a fraction of that).
double netcdf4_time_limit(const std::string& path) {
  if (const char* text = std::getenv("MLCE_NETCDF4_TIME_LIMIT")) {
    char* end = nullptr;
    const double s = std::strtod(text, &end);
    if (end == text || *end != '\0' || !(s > 0.0) || !std::isfinite(s))
      throw ReadError(std::string("MLCE_NETCDF4_TIME_LIMIT: expected seconds > 0, got '") + text + "'");
    return s;
  }
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  return 60.0 + (ec ? 0.0 : std::floor(static_cast<double>(size) / 1e7));  // whole seconds: a message says it
}

/// A ChannelSet or an Inventory as bytes and back (byte_codec.hpp), for the child's result.
std::string encode(const ChannelSet& set) {
  detail::ByteWriter w;
  w.str(set.source);
  w.doubles(set.time);
  w.strings(set.names);
  w.u64(set.values.size());
  for (const auto& v : set.values) w.doubles(v);
  w.strings(set.warnings);
  return w.take();
}

ChannelSet decode_channel_set(std::string_view bytes) {
  detail::ByteReader r(bytes);
  ChannelSet set;
  set.source = r.str();
  set.time = r.doubles();
  set.names = r.strings();
  set.values.resize(r.count(sizeof(std::uint64_t)));
  for (auto& v : set.values) v = r.doubles();
  set.warnings = r.strings();
  r.expect_end();
  return set;
}

std::string encode(const Inventory& inv) {
  detail::ByteWriter w;
  w.str(inv.source);
  w.str(inv.format);
  w.u64(inv.nodes.size());
  for (const auto& n : inv.nodes) w.i64(n.label), w.str(n.kind), w.str(n.orientation), w.u64(n.columns);
  w.u64(inv.entities.size());
  for (const auto& e : inv.entities) w.str(e.file), w.i64(e.label), w.str(e.type), w.u64(e.columns);
  w.u64(inv.blocks);
  w.f64(inv.t_first);
  w.f64(inv.t_last);
  w.u64(inv.variables.size());
  for (const auto& v : inv.variables) w.str(v.name), w.u64(v.components);
  w.strings(inv.columns);
  w.u64(inv.eigenanalyses);
  w.strings(inv.warnings);
  return w.take();
}

Inventory decode_inventory(std::string_view bytes) {
  detail::ByteReader r(bytes);
  Inventory inv;
  inv.source = r.str();
  inv.format = r.str();
  inv.nodes.resize(r.count(4 * sizeof(std::uint64_t)));
  for (auto& n : inv.nodes) {
    n.label = static_cast<long>(r.i64());
    n.kind = r.str();
    n.orientation = r.str();
    n.columns = static_cast<std::size_t>(r.u64());
  }
  inv.entities.resize(r.count(4 * sizeof(std::uint64_t)));
  for (auto& e : inv.entities) {
    e.file = r.str();
    e.label = static_cast<long>(r.i64());
    e.type = r.str();
    e.columns = static_cast<std::size_t>(r.u64());
  }
  inv.blocks = static_cast<std::size_t>(r.u64());
  inv.t_first = r.f64();
  inv.t_last = r.f64();
  inv.variables.resize(r.count(2 * sizeof(std::uint64_t)));
  for (auto& v : inv.variables) {
    v.name = r.str();
    v.components = static_cast<std::size_t>(r.u64());
  }
  inv.columns = r.strings();
  inv.eigenanalyses = static_cast<std::size_t>(r.u64());
  inv.warnings = r.strings();
  r.expect_end();
  return inv;
}

std::string encode(const MbdynNetcdfEigenanalyses& r) {
  detail::ByteWriter w;
  w.u64(r.analyses.size());
  for (const auto& e : r.analyses) {
    w.str(e.source);
    w.f64(*e.time);
    w.f64(*e.coefficient);
    std::vector<double> alpha;
    for (const auto& a : e.alpha) alpha.insert(alpha.end(), a.begin(), a.end());
    w.doubles(alpha);
    w.u64(e.size);
    w.doubles(e.aplus);
    w.doubles(e.aminus);
    w.u64(e.sparse ? 1 : 0);
  }
  w.strings(r.warnings);
  return w.take();
}

MbdynNetcdfEigenanalyses decode_eigenanalyses(std::string_view bytes) {
  detail::ByteReader r(bytes);
  MbdynNetcdfEigenanalyses out;
  out.analyses.resize(r.count(5 * sizeof(std::uint64_t)));
  for (auto& e : out.analyses) {
    e.source = r.str();
    e.time = r.f64();
    e.coefficient = r.f64();
    const auto alpha = r.doubles();
    for (std::size_t i = 0; i + 2 < alpha.size(); i += 3) e.alpha.push_back({alpha[i], alpha[i + 1], alpha[i + 2]});
    e.size = static_cast<std::size_t>(r.u64());
    e.aplus = r.doubles();
    e.aminus = r.doubles();
    e.sparse = r.u64() != 0;
  }
  out.warnings = r.strings();
  r.expect_end();
  return out;
}

/// `read()` of a file that is not classic NetCDF (netCDF-4 is HDF5 underneath) runs only in a
/// child process, whose result comes back as bytes: libhdf5 trusts the file's metadata and can
/// crash, corrupt its heap or loop on a corrupt one (isolated_run.hpp), and none of it reaches
/// this process. The classic formats are walked by check_classic_header and read by libnetcdf's
/// own code (fuzzed: fuzz_netcdf) here. The price of the child: a fork and one copy of the result
/// through a pipe.
template <class Read, class Decode>
auto read_netcdf4_in_child(const std::string& path, Read read, Decode decode) -> decltype(read()) {
  if (leading_bytes(path, 3) == "CDF") return read();
  const double limit = netcdf4_time_limit(path);
  auto outcome = detail::run_isolated(
      [&] {
        try {
          return encode(read());
        } catch (const ReadError&) {
          throw;  // names the file and what is wrong with it
        } catch (const std::exception& e) {  // e.g. std::bad_alloc: say which file it came from
          throw ReadError(path + ": " + e.what());
        }
      },
      limit);
  using Kind = detail::IsolatedOutcome::Kind;
  switch (outcome.kind) {
    case Kind::finished:
      try {
        return decode(outcome.output);
      } catch (const std::runtime_error& e) {  // our own child's bytes: a bug, said as one
        throw ReadError(path + ": the process that read it handed back a malformed result (" + e.what() + ")");
      }
    case Kind::threw:
      throw ReadError(outcome.message);  // the reader's own error, naming the file
    case Kind::timed_out: {
      char text[64];
      std::snprintf(text, sizeof text, "%g", limit);
      throw ReadError(path + ": reading it as a netCDF-4 (HDF5) file did not end within " + text +
                      " s (a corrupt file can send the HDF5 library into an endless loop; for a slow disk or a huge "
                      "file, set MLCE_NETCDF4_TIME_LIMIT=SECONDS)");
    }
    case Kind::crashed:
      throw ReadError(path + ": a corrupt netCDF-4 (HDF5) file: the HDF5 library crashed reading it (" +
                      (outcome.signal   ? "signal " + std::to_string(outcome.signal) + ": " + strsignal(outcome.signal)
                       : outcome.status ? "exit status " + std::to_string(outcome.status)
                                        : std::string("it ended without handing over its result")) +
                      ", in a separate process; nothing was read)");
    case Kind::not_run:
      break;
  }
  return read();  // no process could be started (pipe or fork failed): read here, unguarded
}

ChannelSet read_channels(const std::string& path, const std::vector<ChannelSpec>& channels, const ReadOptions& options) {
  const NcFile nc(path);
  ChannelSet out;
  out.source = path;
  const int tv = nc.require("time", "the time of each record");
  const std::size_t records = nc.records(tv);
  if (records == 0) throw ReadError(path + ": no records");
  out.time = record_times(nc, tv, records, out.warnings);
  if (out.time.empty()) throw ReadError(path + ": no record holds a time");
  std::size_t n = records_written(out.time, path, out.warnings);
  if (n == 0) throw ReadError(path + ": no complete record");
  out.time.resize(n);
  n = steps_until(out.time, options, path);  // records after `until` are not read
  out.time.resize(n);

  std::optional<MbdynLog> log;
  bool log_tried = false;
  for (const ChannelSpec& s : channels) {
    out.names.push_back(s.text);
    switch (s.kind) {
      case ChannelSpec::Kind::node: {
        const auto f = *detail::parse_node_field(s.field);
        const std::string base = "node.struct." + std::to_string(s.label);
        if (!nc.var(base + ".X")) no_output(nc, "structural node", "node.struct", s.label, ".X");
        if (f.group == detail::NodeGroup::orientation) {
          const auto o = node_orientation(nc, s.label);
          if (o.kind == Orientation::none || f.component >= orientation_size(o.kind))
            throw ReadError(path + ": channel '" + s.text + "': node " + std::to_string(s.label) + " has " +
                            (o.kind == Orientation::none ? std::string("no orientation") :
                             std::to_string(orientation_size(o.kind)) + " orientation numbers"));
          out.values.push_back(orientation_column(nc, o, f.component, n));
        } else {
          const std::string name = base + node_group_suffix(f.group);
          out.values.push_back(nc.column(nc.require(name, "channel '" + s.text + "'"), f.component, n, name));
        }
        break;
      }
      case ChannelSpec::Kind::entity: {
        if (s.label < 0)
          throw ReadError(path + ": channel '" + s.text + "': a label with a sub-index (" + row_label_text(s.label) +
                          ") addresses rows of the text output (.mod, .frc); joints and nodes here have plain labels");
        if (s.extension == "jnt") {
          const auto [name, comp] = joint_column(nc, s.label, s.column);
          out.values.push_back(nc.column(*nc.var(name), comp, n, name));
        } else if (s.extension == "ine") {
          static const char* groups[] = {".B", ".G", ".BP", ".GP"};
          if (s.column > 13) throw ReadError(path + ": channel '" + s.text + "': inertia rows have 13 columns");
          const std::string name = "node.struct." + std::to_string(s.label) + groups[(s.column - 2) / 3];
          out.values.push_back(nc.column(nc.require(name, "channel '" + s.text + "'"), (s.column - 2) % 3, n, name));
        } else {
          throw ReadError(path + ": channel '" + s.text + "': the NetCDF file has no ." + s.extension +
                          " rows; its other time histories are var:NAME[:K] channels (`mlce channels " + path +
                          "` lists them)");
        }
        break;
      }
      case ChannelSpec::Kind::relative: {
        const auto oa = node_orientation(nc, s.label), ob = node_orientation(nc, s.reference);
        if (oa.kind == Orientation::none || ob.kind == Orientation::none)
          throw ReadError(path + ": channel '" + s.text + "': both nodes need an orientation");
        const auto ca = orientation_columns(nc, oa, n), cb = orientation_columns(nc, ob, n);
        auto first = [](const std::vector<std::vector<double>>& c) {
          std::vector<double> v;
          for (const auto& col : c) v.push_back(col[0]);
          return v;
        };
        // Initial configuration from the .log beside the file, else the first record.
        if (!log_tried) {
          log_tried = true;
          std::filesystem::path lp(path);
          lp.replace_extension(".log");
          const std::string log_path = detail::stored_file(lp.string());  // the .log, or its .log.gz
          std::error_code ec;
          if (std::filesystem::is_regular_file(log_path, ec)) log = read_mbdyn_log(log_path);
        }
        Matrix3 RA0 = rotation_matrix(oa.kind, first(ca)), RB0 = rotation_matrix(ob.kind, first(cb));
        const auto* la = log ? log->node(s.label) : nullptr;
        const auto* lb = log ? log->node(s.reference) : nullptr;
        if (la && lb && la->orientation != Orientation::none && lb->orientation != Orientation::none) {
          RA0 = rotation_matrix(la->orientation, la->values);
          RB0 = rotation_matrix(lb->orientation, lb->values);
        } else {
          out.warnings.push_back(path + ": channel '" + s.text +
                                 "': no .log beside the file with both nodes; angle measured from the first record");
        }
        const std::vector<std::span<const double>> sa(ca.begin(), ca.end()), sb(cb.begin(), cb.end());
        out.values.push_back(relative_angle_series(oa.kind, sa, ob.kind, sb, RA0, RB0, s.axis, n));
        break;
      }
      case ChannelSpec::Kind::column:
        throw ReadError(path + ": channel '" + s.text + "' addresses a column file; NetCDF takes node:, joint:, ine:, rel: or var:");
      case ChannelSpec::Kind::variable: {
        const int v = nc.require(s.field, "channel '" + s.text + "'; mlce channels lists the file's time histories");
        const auto sh = nc.shape(v);
        if (s.field.rfind("eig.", 0) == 0)
          throw ReadError(path + ": channel '" + s.text + "': '" + s.field +
                          "' is MBDyn eigenanalysis output, no time history (`mlce eigenanalysis " + path + "` reads it)");
        if (!is_record_variable(nc, v))
          throw ReadError(path + ": channel '" + s.text + "': '" + s.field + "' is no time history (its first dimension is "
                          "not the record dimension 'time')");
        const std::size_t width = components(sh);
        if (s.column > width)
          throw ReadError(path + ": channel '" + s.text + "': '" + s.field + "' has " + std::to_string(width) +
                          " component(s) per record, component " + std::to_string(s.column) + " requested");
        const bool matrix = sh.size() == 3 && sh[1] == 3 && sh[2] == 3;  // row by row, as the text files write it
        out.values.push_back(nc.column(v, matrix ? matrix_storage_index(s.column - 1) : s.column - 1, n, s.field));
        break;
      }
    }
  }
  return out;
}

Inventory describe(const std::string& path) {
  const NcFile nc(path);
  Inventory inv;
  inv.source = path;
  inv.format = "mbdyn-netcdf";
  const int tv = nc.require("time", "the time of each record");
  inv.blocks = nc.records(tv);
  if (inv.blocks > 0) {
    auto t = record_times(nc, tv, inv.blocks, inv.warnings);
    inv.blocks = t.empty() ? 0 : records_written(t, path, inv.warnings);
    t.resize(std::max<std::size_t>(inv.blocks, 1));
    inv.t_first = t.front();
    inv.t_last = t.back();
  }
  for (long l : nc.labels("node.struct")) {
    const auto v = nc.var("node.struct." + std::to_string(l));
    if (!nc.var("node.struct." + std::to_string(l) + ".X")) {
      inv.nodes.push_back({l, "output off", "none", 0});
      continue;
    }
    const auto o = node_orientation(nc, l);
    inv.nodes.push_back({l, v ? nc.text_attribute(*v, "type") : "unknown", orientation_name(o.kind), 0});
  }
  for (long l : nc.labels("elem.joint")) {
    const std::string base = "elem.joint." + std::to_string(l);
    const auto v = nc.var(base);
    inv.entities.push_back({"jnt", l, !nc.var(base + ".f") ? "output off" : v ? nc.text_attribute(*v, "type") : "", 0});
  }
  // The time histories no node:, joint: or ine: channel reaches: beams, forces, aerodynamic
  // elements, the run's own (run.step, run.timestep), ...
  const auto reached = [](const std::string& name) {
    for (const char* group : {"node.struct.", "elem.joint."})
      if (name.rfind(group, 0) == 0) return true;
    return name == "time" || name.rfind("eig.", 0) == 0;  // eigenanalysis triplets are no time history
  };
  for (const auto& name : nc.variable_names()) {
    const int v = *nc.var(name);
    if (!reached(name) && is_record_variable(nc, v)) inv.variables.push_back({name, components(nc.shape(v))});
  }
  if (const auto eig_time = nc.var("eig.time")) {
    try {  // the time histories are listed whatever the eigenanalysis variables hold
      const auto times = nc.values(*eig_time, "eig.time");
      const double fill = nc.fill_value(*eig_time);
      inv.eigenanalyses = static_cast<std::size_t>(std::count_if(times.begin(), times.end(), [fill](double t) { return t != fill; }));
    } catch (const ReadError& e) {
      inv.warnings.push_back(std::string(e.what()) + " (the eigenanalyses are not counted)");
    }
  }
  return inv;
}

/// Every number of `values` (of variable `name`) finite and written, else one error naming the entry.
void require_written(const NcFile& nc, int v, const std::vector<double>& values, std::size_t count, const std::string& name) {
  const double fill = nc.fill_value(v);
  for (std::size_t i = 0; i < count; ++i)
    if (values[i] == fill || !std::isfinite(values[i]))
      throw ReadError(nc.path() + ": '" + name + "' number " + std::to_string(i) +
                      (values[i] == fill ? ": holds the NetCDF fill value (never written)" : ": expected a finite number"));
}

/// eig.<k>.Aplus or eig.<k>.Aminus as a row-major n x n matrix (layout: mbdyn_netcdf.hpp).
std::vector<double> eigenanalysis_matrix(const NcFile& nc, int v, const std::string& name, std::size_t& n, bool& sparse) {
  const auto sh = nc.shape(v);
  const std::string where = nc.path() + ": " + name;
  sparse = nc.first_dimension_is_unlimited(v);
  if (sparse) {
    if (sh.size() != 2 || sh[1] != 3) throw ReadError(where + ": a sparse matrix is records of (row, column, value)");
    // The triplets come first; the records after them were never written (a long run has many more
    // records than a model has nonzeros): read in blocks up to the first record without a row index.
    const double fill = nc.fill_value(v);
    const std::size_t records = nc.records(v);
    constexpr std::size_t kBlock = 1 << 16, kMostTriplets = kLargestEigenanalysisMatrix * kLargestEigenanalysisMatrix;
    std::vector<double> t;
    std::size_t count = 0;
    bool ended = false;
    for (std::size_t first = 0; first < records && !ended; first += kBlock) {
      const auto block = nc.records_of(v, first, std::min(kBlock, records - first), name);
      for (std::size_t i = 0; i < block.size() / 3 && !ended; ++i) {
        ended = block[3 * i] == fill;
        if (ended) break;
        if (++count > kMostTriplets)
          throw ReadError(where + ": more than " + std::to_string(kMostTriplets) + " triplets (an n x n matrix has at most n^2 entries)");
        t.insert(t.end(), block.begin() + static_cast<std::ptrdiff_t>(3 * i), block.begin() + static_cast<std::ptrdiff_t>(3 * i + 3));
      }
    }
    require_written(nc, v, t, t.size(), name);
    return detail::matrix_from_triplets(t.data(), count, nc.dimension_length("eig_iSize"), where, n);
  }
  if (sh.size() != 2 || sh[0] != sh[1] || sh[0] == 0)
    throw ReadError(where + ": expected a square matrix (eig_iSize, eig_iSize) or (record, 3) triplets");
  n = sh[0];
  detail::check_matrix_size(where, n);
  const auto stored = nc.values(v, name);
  require_written(nc, v, stored, stored.size(), name);
  std::vector<double> a(n * n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) a[i * n + j] = stored[j * n + i];  // stored column by column
  return a;
}

MbdynNetcdfEigenanalyses read_eigenanalyses(const std::string& path) {
  const NcFile nc(path);
  MbdynNetcdfEigenanalyses out;
  const auto tv = nc.var("eig.time");
  if (!tv) return out;
  const int cv = nc.require("eig.dCoef", "the coefficient of each eigenanalysis, written beside eig.time");
  const auto times = nc.values(*tv, "eig.time"), coefficients = nc.values(cv, "eig.dCoef");
  if (nc.shape(*tv).size() != 1 || coefficients.size() != times.size())
    throw ReadError(path + ": 'eig.time' and 'eig.dCoef' are not one number each per eigenanalysis (dimension 'eigensolutions')");
  const double time_fill = nc.fill_value(*tv);
  for (std::size_t k = 0; k < times.size(); ++k) {
    const std::string group = "eig." + std::to_string(k);
    MbdynEigenanalysis e;
    e.source = path + ":" + group;
    if (times[k] == time_fill) {
      out.warnings.push_back(e.source + ": planned but not performed ('eig.time' holds the fill value: the run ended "
                                        "before that time?)");
      continue;
    }
    if (!std::isfinite(times[k])) throw ReadError(e.source + ": 'eig.time' is no finite number");
    if (!(coefficients[k] > 0.0) || !std::isfinite(coefficients[k]) || coefficients[k] == nc.fill_value(cv))
      throw ReadError(e.source + ": 'eig.dCoef' = " + std::to_string(coefficients[k]) +
                      ": expected a positive number (half a time step)");
    e.time = times[k];
    e.coefficient = coefficients[k];
    if (const auto av = nc.var(group + ".alpha")) {
      const auto sh = nc.shape(*av);
      if (sh.size() != 2 || sh[1] != 3)
        throw ReadError(e.source + ".alpha: expected (eigenvalue, 3): alphar, alphai, beta of each eigenvalue");
      const auto a = nc.values(*av, group + ".alpha");
      require_written(nc, *av, a, a.size(), group + ".alpha");
      for (std::size_t i = 0; i + 2 < a.size(); i += 3) e.alpha.push_back({a[i], a[i + 1], a[i + 2]});
    }
    const auto pv = nc.var(group + ".Aplus"), mv = nc.var(group + ".Aminus");
    if (pv.has_value() != mv.has_value())
      throw ReadError(e.source + ": holds " + (pv ? "Aplus but not Aminus" : "Aminus but not Aplus") + "; MBDyn writes both");
    if (pv) {
      std::size_t n_plus = 0, n_minus = 0;
      bool sparse_plus = false, sparse_minus = false;
      e.aplus = eigenanalysis_matrix(nc, *pv, group + ".Aplus", n_plus, sparse_plus);
      e.aminus = eigenanalysis_matrix(nc, *mv, group + ".Aminus", n_minus, sparse_minus);
      if (n_plus != n_minus)
        throw ReadError(e.source + ": Aplus is " + std::to_string(n_plus) + " x " + std::to_string(n_plus) + ", Aminus " +
                        std::to_string(n_minus) + " x " + std::to_string(n_minus) + "; they are the same size");
      e.size = n_plus;
      e.sparse = sparse_plus || sparse_minus;
    }
    if (e.alpha.empty() && e.size == 0)
      throw ReadError(e.source + ": holds neither the eigenvalues (" + group + ".alpha: `output eigenvectors`) nor the "
                      "matrices (" + group + ".Aplus, .Aminus: `output matrices` or `output sparse matrices`)");
    out.analyses.push_back(std::move(e));
  }
  return out;
}

}  // namespace

ChannelSet read_mbdyn_netcdf(const std::string& path, const std::vector<ChannelSpec>& channels,
                             const ReadOptions& options) {
  if (channels.empty()) throw ReadError(path + ": no channel requested (give --channel SPEC)");
  return read_netcdf4_in_child(path, [&] { return read_channels(path, channels, options); }, decode_channel_set);
}

Inventory describe_mbdyn_netcdf(const std::string& path) {
  return read_netcdf4_in_child(path, [&] { return describe(path); }, decode_inventory);
}

MbdynNetcdfEigenanalyses read_mbdyn_netcdf_eigenanalyses(const std::string& path) {
  return read_netcdf4_in_child(path, [&] { return read_eigenanalyses(path); }, decode_eigenanalyses);
}

}  // namespace mlce::reader
