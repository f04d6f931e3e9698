// MBDyn readers against the files' own numbers read another way, synthetic sets in every
// orientation parametrization, and interrupted runs.
#include <gtest/gtest.h>

#include <bit>
#include <chrono>
#include <csignal>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <sstream>
#include <thread>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "byte_codec.hpp"    // reader/src: the child's result as bytes
#include "isolated_run.hpp"  // reader/src: the child-process guard of the netCDF-4 reads
#include "mlce/reader/column_file.hpp"
#include "mlce/reader/format.hpp"
#include "mlce/reader/mbdyn_netcdf.hpp"
#include "mlce/reader/mbdyn_text.hpp"
#include "mlce/reader/orientation.hpp"
#include "mlce/reader/table.hpp"

#include <netcdf.h>
#include <zlib.h>

namespace fs = std::filesystem;
using namespace mlce::reader;

namespace {

const std::string kIso = std::string(MLCE_DATA_DIR) + "/mbdyn/iso_200rpm_1s/iso_200rpm";
const std::string kC3 = std::string(MLCE_DATA_DIR) + "/mbdyn/c3zero_242rpm_cyhalf_10s/c3zero_242rpm_cyhalf";

std::vector<ChannelSpec> specs(std::initializer_list<const char*> s) {
  std::vector<ChannelSpec> out;
  for (const char* t : s) out.push_back(parse_channel_spec(t));
  return out;
}

/// The .mov read by a test that knows the layout: rows of `per_block` lines, whitespace fields.
std::vector<std::vector<double>> mov_rows_of(const std::string& path, long label) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    long l = 0;
    s >> l;
    if (l != label) continue;
    std::vector<double> v{static_cast<double>(l)};
    double x = 0;
    while (s >> x) v.push_back(x);
    rows.push_back(v);
  }
  return rows;
}

/// Output times read another way: the last field of each Step line is the output flag.
std::vector<double> out_times(const std::string& path) {
  std::ifstream in(path);
  std::string line, word;
  std::vector<double> t;
  while (std::getline(in, line)) {
    if (line.rfind("Step ", 0) != 0) continue;
    std::istringstream s(line);
    std::vector<std::string> f;
    while (s >> word) f.push_back(word);
    if (f.back() == "1") t.push_back(std::stod(f[2]));
  }
  return t;
}

double wrap_pi(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }

/// The message of the ReadError `read` throws ("" and a test failure when it throws none).
template <class F>
std::string read_error_of(F read) {
  try {
    read();
  } catch (const ReadError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a ReadError";
  return "";
}

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// y of a record the solver never wrote (write_node_x_records leaves its X at the fill value).
constexpr double kUnwritten = std::numeric_limits<double>::max();

/// A minimal MBDyn NetCDF file: record k at time 0.1 k with node.struct.1.X = (1, y[k], 3), or
/// with X never written when y[k] is kUnwritten.
void write_node_x_records(const fs::path& path, const std::vector<double>& y) {
  int id = 0, time_dim = 0, vec3 = 0, t_var = 0, x_var = 0;
  ASSERT_EQ(nc_create(path.c_str(), NC_CLOBBER, &id), NC_NOERR);
  ASSERT_EQ(nc_def_dim(id, "time", NC_UNLIMITED, &time_dim), NC_NOERR);
  ASSERT_EQ(nc_def_dim(id, "vec3", 3, &vec3), NC_NOERR);
  const int dims[2] = {time_dim, vec3};
  ASSERT_EQ(nc_def_var(id, "time", NC_DOUBLE, 1, &time_dim, &t_var), NC_NOERR);
  ASSERT_EQ(nc_def_var(id, "node.struct.1.X", NC_DOUBLE, 2, dims, &x_var), NC_NOERR);
  ASSERT_EQ(nc_enddef(id), NC_NOERR);
  for (std::size_t k = 0; k < y.size(); ++k) {
    const double t = 0.1 * static_cast<double>(k), x[3] = {1.0, y[k], 3.0};
    const std::size_t start[2] = {k, 0}, one[1] = {1}, row[2] = {1, 3};
    ASSERT_EQ(nc_put_vara_double(id, t_var, start, one, &t), NC_NOERR);
    if (y[k] != kUnwritten) {
      ASSERT_EQ(nc_put_vara_double(id, x_var, start, row, x), NC_NOERR);
    }
  }
  ASSERT_EQ(nc_close(id), NC_NOERR);
}

}  // namespace

// A number beyond the double range reads as strtod reads it: 1e-400 underflows to 0, 1e400 overflows to
// inf and is refused as not finite. (std::from_chars leaves its output unchanged there, and the value
// read as the 0.0 it was initialised to.)
TEST(MbdynText, NumbersBeyondTheDoubleRangeReadAsStrtodReadsThem) {
  const auto r = parse_mbdyn_blocks("1 1e-400 2\n1 -1e-400 4\n1 3 4\n", "u.mov", {{1, 2}}, {});
  ASSERT_EQ(r.values.size(), 1U);
  EXPECT_EQ(r.values[0], (std::vector<double>{0.0, 0.0, 3.0}));
  EXPECT_TRUE(std::signbit(r.values[0][1]));
  const std::string what = read_error_of([] { parse_mbdyn_blocks("1 1 2\n1 1e400 4\n", "o.mov", {{1, 2}}, {}); });
  EXPECT_NE(what.find("o.mov:2: column 2: '1e400': expected a finite number"), std::string::npos) << what;
}

TEST(MbdynText, TimesComeFromTheOutputFlagOfStepLines) {
  const auto cs = read_mbdyn_text(kIso, specs({"node:2:x"}));
  const auto t = out_times(kIso + ".out");
  ASSERT_EQ(cs.time.size(), 201u);
  ASSERT_EQ(t.size(), cs.time.size());
  for (std::size_t k = 0; k < t.size(); ++k) EXPECT_EQ(cs.time[k], t[k]);
  EXPECT_DOUBLE_EQ(cs.time[1], 0.005);  // output every 5 steps of 1 ms
  EXPECT_TRUE(cs.warnings.empty());
}

TEST(MbdynText, NodeFieldsAreTheFileColumns) {
  const auto cs = read_mbdyn_text(kIso + ".mov", specs({"node:2:x", "node:13:r3", "node:13:vy", "node:4:wz"}));
  const auto hub = mov_rows_of(kIso + ".mov", 4), blade = mov_rows_of(kIso + ".mov", 13), x = mov_rows_of(kIso + ".mov", 2);
  ASSERT_EQ(x.size(), cs.time.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    EXPECT_EQ(cs.values[0][k], x[k][1]);
    EXPECT_EQ(cs.values[1][k], blade[k][6]);
    EXPECT_EQ(cs.values[2][k], blade[k][8]);
    EXPECT_EQ(cs.values[3][k], hub[k][12]);
  }
}

TEST(MbdynText, LagAngleFromAbsoluteBodiesMatchesTheDamperAndTheEulerFormula) {
  // rel:13:4:z is blade 3's lag; the damper joint 33 writes the same angle in column 14; the
  // data README's formula is zeta = wrap(E3(blade) - E3(hub) - 180 deg).
  const auto cs = read_mbdyn_text(kC3, specs({"rel:13:4:z"}));
  const auto hub = mov_rows_of(kC3 + ".mov", 4), blade = mov_rows_of(kC3 + ".mov", 13);
  ASSERT_EQ(cs.time.size(), 2001u);
  double early = 0.0, late = 0.0;
  for (std::size_t k = 0; k < hub.size(); ++k) {
    const double euler = wrap_pi((blade[k][6] - hub[k][6] - 180.0) * std::numbers::pi / 180.0);
    EXPECT_NEAR(cs.values[0][k], euler, 1e-9) << "block " << k;
    (k < 400 ? early : late) = std::max(k < 400 ? early : late, std::abs(cs.values[0][k]));
  }
  EXPECT_GT(late, 3.0 * early);  // without blade 3's damper the lag motion grows towards its limit cycle

  const auto both = read_mbdyn_text(kIso, specs({"rel:13:4:z", "joint:33:14", "rel:11:4:z", "joint:31:14"}));
  for (std::size_t k = 0; k < both.time.size(); ++k) {
    // Two angles rounded to 7 significant digits in degrees: 2 x 0.5e-4 deg ~ 1.8e-6 rad.
    EXPECT_NEAR(both.values[0][k], both.values[1][k], 2e-6) << "block " << k;
    EXPECT_NEAR(both.values[2][k], both.values[3][k], 2e-6) << "block " << k;
  }
}

TEST(MbdynNetcdf, SameChannelsAsTheTextSetToPrintedPrecision) {
  const auto spec = specs({"joint:33:14", "node:2:x", "node:13:r3", "node:3:vy", "joint:2:14", "ine:11:3"});
  const auto text = read_mbdyn_text(kIso, spec);
  const auto nc = read_mbdyn_netcdf(kIso + ".nc", spec);
  ASSERT_EQ(text.time.size(), nc.time.size());
  for (std::size_t k = 0; k < text.time.size(); ++k) {
    EXPECT_NEAR(text.time[k], nc.time[k], 1e-9);
    for (std::size_t c = 0; c < spec.size(); ++c)  // %.6e in the text files: 7 significant digits
      EXPECT_NEAR(text.values[c][k], nc.values[c][k], 5e-7 * std::abs(nc.values[c][k]) + 1e-300)
          << spec[c].text << " block " << k;
  }
  // The lag from the absolute bodies in the NetCDF file equals the damper's own angle.
  const auto rel = read_mbdyn_netcdf(kIso + ".nc", specs({"rel:13:4:z", "joint:33:14"}));
  for (std::size_t k = 0; k < rel.time.size(); ++k) EXPECT_NEAR(rel.values[0][k], rel.values[1][k], 1e-9);
  EXPECT_TRUE(rel.warnings.empty());  // the .log beside the file gives the initial configuration
}

/// `from` rewritten in another on-disk format (NC_NETCDF4: HDF5 underneath, what MBDyn builds
/// against netCDF-4 may write): every dimension, attribute and variable with its values.
void copy_netcdf(const std::string& from, const fs::path& to, int format) {
  int in = 0, out = 0, ndims = 0, nvars = 0, ngatts = 0, unlimited = -1;
  ASSERT_EQ(nc_open(from.c_str(), NC_NOWRITE, &in), NC_NOERR);
  ASSERT_EQ(nc_create(to.c_str(), NC_CLOBBER | format, &out), NC_NOERR);
  ASSERT_EQ(nc_inq(in, &ndims, &nvars, &ngatts, &unlimited), NC_NOERR);
  for (int d = 0; d < ndims; ++d) {
    char name[NC_MAX_NAME + 1];
    std::size_t len = 0;
    int id = 0;
    ASSERT_EQ(nc_inq_dim(in, d, name, &len), NC_NOERR);
    ASSERT_EQ(nc_def_dim(out, name, d == unlimited ? NC_UNLIMITED : len, &id), NC_NOERR);
    ASSERT_EQ(id, d);
  }
  for (int a = 0; a < ngatts; ++a) {
    char name[NC_MAX_NAME + 1];
    ASSERT_EQ(nc_inq_attname(in, NC_GLOBAL, a, name), NC_NOERR);
    ASSERT_EQ(nc_copy_att(in, NC_GLOBAL, name, out, NC_GLOBAL), NC_NOERR);
  }
  for (int v = 0; v < nvars; ++v) {
    char name[NC_MAX_NAME + 1];
    nc_type type{};
    int vdims = 0, natts = 0, id = 0, dimids[NC_MAX_VAR_DIMS];
    ASSERT_EQ(nc_inq_var(in, v, name, &type, &vdims, dimids, &natts), NC_NOERR);
    ASSERT_EQ(nc_def_var(out, name, type, vdims, dimids, &id), NC_NOERR);
    for (int a = 0; a < natts; ++a) {
      char att[NC_MAX_NAME + 1];
      ASSERT_EQ(nc_inq_attname(in, v, a, att), NC_NOERR);
      ASSERT_EQ(nc_copy_att(in, v, att, out, id), NC_NOERR);
    }
  }
  ASSERT_EQ(nc_enddef(out), NC_NOERR);
  for (int v = 0; v < nvars; ++v) {
    nc_type type{};
    int vdims = 0, dimids[NC_MAX_VAR_DIMS];
    ASSERT_EQ(nc_inq_var(in, v, nullptr, &type, &vdims, dimids, nullptr), NC_NOERR);
    std::size_t size = 0, count = 1;
    ASSERT_EQ(nc_inq_type(in, type, nullptr, &size), NC_NOERR);
    for (int d = 0; d < vdims; ++d) {
      std::size_t len = 0;
      ASSERT_EQ(nc_inq_dimlen(in, dimids[d], &len), NC_NOERR);
      count *= len;
    }
    if (count == 0) continue;
    std::vector<unsigned char> values(count * size);
    ASSERT_EQ(nc_get_var(in, v, values.data()), NC_NOERR);
    if (vdims > 0 && dimids[0] == unlimited) {  // a record variable takes its extent from the records written
      std::vector<std::size_t> start(static_cast<std::size_t>(vdims), 0), shape(static_cast<std::size_t>(vdims));
      for (int d = 0; d < vdims; ++d) ASSERT_EQ(nc_inq_dimlen(in, dimids[d], &shape[static_cast<std::size_t>(d)]), NC_NOERR);
      ASSERT_EQ(nc_put_vara(out, v, start.data(), shape.data(), values.data()), NC_NOERR);
    } else {
      ASSERT_EQ(nc_put_var(out, v, values.data()), NC_NOERR);
    }
  }
  ASSERT_EQ(nc_close(out), NC_NOERR);
  ASSERT_EQ(nc_close(in), NC_NOERR);
}

TEST(MbdynNetcdf, Netcdf4HdfFileReadsLikeTheClassicOne) {
  // The reader's own header walk covers the classic formats; a netCDF-4 (HDF5) file goes to
  // libnetcdf directly and must give the same channels, bit for bit.
  const fs::path nc4 = fs::path(::testing::TempDir()) / "iso_200rpm_nc4.nc";
  copy_netcdf(kIso + ".nc", nc4, NC_NETCDF4);
  fs::copy_file(kIso + ".log", fs::path(nc4).replace_extension(".log"), fs::copy_options::overwrite_existing);  // rel: reads it
  if (HasFatalFailure()) return;
  {
    std::ifstream f(nc4, std::ios::binary);
    char magic[4] = {};
    f.read(magic, 4);
    ASSERT_EQ(std::string(magic + 1, 3), "HDF");
  }
  const auto spec = specs({"joint:33:14", "node:2:x", "node:13:r3", "node:3:vy", "ine:11:3", "rel:13:4:z"});
  const auto classic = read_mbdyn_netcdf(kIso + ".nc", spec);
  const auto hdf = read_mbdyn_netcdf(nc4.string(), spec);
  ASSERT_EQ(hdf.time, classic.time);
  ASSERT_EQ(hdf.values.size(), classic.values.size());
  for (std::size_t c = 0; c < spec.size(); ++c) EXPECT_EQ(hdf.values[c], classic.values[c]) << spec[c].text;
  EXPECT_EQ(hdf.warnings, classic.warnings);
  EXPECT_EQ(hdf.names, classic.names);
  EXPECT_EQ(hdf.source, nc4.string());
  EXPECT_EQ(default_registry().for_path(nc4.string()).name(), "mbdyn-netcdf");
  // Read in a child process (isolated_run.hpp), the result crosses a pipe: the inventory, and an
  // error of the reader's own, arrive as the classic file's do here.
  const auto inv4 = describe_mbdyn_netcdf(nc4.string()), inv = describe_mbdyn_netcdf(kIso + ".nc");
  ASSERT_EQ(inv4.nodes.size(), inv.nodes.size());
  for (std::size_t k = 0; k < inv.nodes.size(); ++k) {
    EXPECT_EQ(inv4.nodes[k].label, inv.nodes[k].label);
    EXPECT_EQ(inv4.nodes[k].kind, inv.nodes[k].kind);
    EXPECT_EQ(inv4.nodes[k].orientation, inv.nodes[k].orientation);
  }
  ASSERT_EQ(inv4.entities.size(), inv.entities.size());
  for (std::size_t k = 0; k < inv.entities.size(); ++k) {
    EXPECT_EQ(inv4.entities[k].label, inv.entities[k].label);
    EXPECT_EQ(inv4.entities[k].type, inv.entities[k].type);
  }
  EXPECT_EQ(inv4.blocks, inv.blocks);
  EXPECT_EQ(inv4.t_first, inv.t_first);
  EXPECT_EQ(inv4.t_last, inv.t_last);
  EXPECT_EQ(inv4.warnings, inv.warnings);
  auto error_of = [&](const std::string& file) -> std::string {
    try {
      (void)read_mbdyn_netcdf(file, specs({"node:99:x"}));
    } catch (const ReadError& e) {
      std::string text = e.what();
      if (const auto at = text.find(file); at != std::string::npos) text.replace(at, file.size(), "FILE");
      return text;
    }
    return "(read)";
  };
  EXPECT_EQ(error_of(nc4.string()), error_of(kIso + ".nc"));
  EXPECT_NE(error_of(nc4.string()).find("99"), std::string::npos) << error_of(nc4.string());
  // Cut short, it is one error naming the file (HDF5 keeps metadata at both ends: no partial read).
  const fs::path cut = fs::path(::testing::TempDir()) / "iso_200rpm_nc4_cut.nc";
  {
    const auto bytes = bytes_of(nc4);
    std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
  }
  try {
    read_mbdyn_netcdf(cut.string(), spec);
    FAIL() << "a netCDF-4 file cut in half was read";
  } catch (const ReadError& e) {
    EXPECT_NE(std::string(e.what()).find(cut.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("netCDF-4 (HDF5) file, cut short or corrupt"), std::string::npos) << e.what();
  }
}

// A corrupt netCDF-4 file can make libhdf5 loop or free a wild pointer (isolated_run.hpp); both
// files of data/corrupt were found by fuzz_netcdf from a netCDF-4 copy of the bundled run.
TEST(MbdynNetcdf, CorruptNetcdf4FilesAreOneErrorNotAHangOrACrash) {
  const std::string loops = std::string(MLCE_DATA_DIR) + "/corrupt/netcdf4_hdf5_loops.nc";
  const std::string bad_free = std::string(MLCE_DATA_DIR) + "/corrupt/netcdf4_hdf5_bad_free.nc";
  const auto spec = specs({"node:2:x"});
  // The error of read_mbdyn_netcdf, or of describe_mbdyn_netcdf, on `file` ("(read)" if none).
  auto error_of = [&](const std::string& file, bool describe) -> std::string {
    try {
      if (describe) (void)describe_mbdyn_netcdf(file);
      else (void)read_mbdyn_netcdf(file, spec);
    } catch (const ReadError& e) {
      return e.what();
    }
    return "(read)";
  };
  ::setenv("MLCE_NETCDF4_TIME_LIMIT", "1.5", 1);
  const auto start = std::chrono::steady_clock::now();
  for (const bool describe : {false, true})
    EXPECT_EQ(error_of(loops, describe),
              loops + ": reading it as a netCDF-4 (HDF5) file did not end within 1.5 s (a corrupt file can send the "
                      "HDF5 library into an endless loop; for a slow disk or a huge file, set "
                      "MLCE_NETCDF4_TIME_LIMIT=SECONDS)");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 30.0);
  // Under AddressSanitizer the child's report ends it ("crashed"); a release build may not notice
  // the bad free, and libnetcdf then refuses the file: one error naming the file either way.
  for (const bool describe : {false, true}) {
    const std::string e = error_of(bad_free, describe);
    EXPECT_EQ(e.rfind(bad_free + ": ", 0), 0u) << e;
    EXPECT_NE(e.find("netCDF-4 (HDF5) file"), std::string::npos) << e;
  }
  ::setenv("MLCE_NETCDF4_TIME_LIMIT", "soon", 1);
  EXPECT_EQ(error_of(loops, false), "MLCE_NETCDF4_TIME_LIMIT: expected seconds > 0, got 'soon'");
  ::unsetenv("MLCE_NETCDF4_TIME_LIMIT");
  // A sound netCDF-4 file passes the child and reads as before (Netcdf4HdfFileReadsLikeTheClassicOne).
}

TEST(IsolatedRun, TellsWorkThatEndsFromWorkThatCrashesOrNeverEnds) {
  using mlce::reader::detail::IsolatedOutcome;
  using mlce::reader::detail::run_isolated;
  int touched = 0;
  auto r = run_isolated([&] { touched = 1; return std::string("done"); }, 10.0);
  EXPECT_EQ(r.kind, IsolatedOutcome::Kind::finished);
  EXPECT_EQ(r.output, "done");
  EXPECT_EQ(touched, 0);  // the child's copy of it
  r = run_isolated([] { return std::string(); }, 10.0);
  EXPECT_EQ(r.kind, IsolatedOutcome::Kind::finished);
  EXPECT_EQ(r.output, "");
  // A result far larger than a pipe's buffer (64 kB) arrives whole, every byte in its place.
  std::string big;
  big.resize(20'000'000);
  for (std::size_t i = 0; i < big.size(); ++i) big[i] = static_cast<char>((i * 2654435761u) >> 13);
  r = run_isolated([&] { return big; }, 60.0);
  EXPECT_EQ(r.kind, IsolatedOutcome::Kind::finished);
  EXPECT_TRUE(r.output == big) << r.output.size() << " bytes";
  r = run_isolated([]() -> std::string { throw ReadError("file.nc: what the reader says"); }, 10.0);
  EXPECT_EQ(r.kind, IsolatedOutcome::Kind::threw);
  EXPECT_EQ(r.message, "file.nc: what the reader says");
  r = run_isolated([]() -> std::string { std::raise(SIGTERM); return "x"; }, 10.0);  // a signal that dumps no core
  EXPECT_EQ(r.kind, IsolatedOutcome::Kind::crashed);
  EXPECT_EQ(r.signal, SIGTERM);
  r = run_isolated([]() -> std::string { std::_Exit(3); }, 10.0);
  EXPECT_EQ(r.kind, IsolatedOutcome::Kind::crashed);
  EXPECT_EQ(r.signal, 0);
  EXPECT_EQ(r.status, 3);
  // A frame cut short is a crash, not a short result, even when the child then exits with status 0.
  // The work below writes frames itself and leaves by _exit(0), as a child killed while writing
  // would leave the pipe. The pipe is the one descriptor the child has that this process did not
  // have before the call (its read end is closed in the child); another may be a pipe of the test
  // runner's whose reader is gone (SIGPIPE).
  std::vector<bool> open_before(1024);
  for (int fd = 0; fd < 1024; ++fd) open_before[static_cast<std::size_t>(fd)] = ::fcntl(fd, F_GETFD) != -1;
  auto writes_then_exits = [&](const std::string& frame) {
    return [&open_before, frame]() -> std::string {
      for (int fd = 0; fd < 1024; ++fd)
        if (!open_before[static_cast<std::size_t>(fd)] && ::fcntl(fd, F_GETFD) != -1)
          (void)!::write(fd, frame.data(), frame.size());
      ::_exit(0);
    };
  };
  const std::string whole("R\x03\0\0\0\0\0\0\0abc", 12), cut("R\x40\0\0\0\0\0\0\0abc", 12);  // 3 and 64 bytes announced
  r = run_isolated(writes_then_exits(whole), 10.0);  // the pipe was found: a frame written by hand arrives
  EXPECT_EQ(r.kind, IsolatedOutcome::Kind::finished);
  EXPECT_EQ(r.output, "abc");
  r = run_isolated(writes_then_exits(cut), 10.0);
  EXPECT_EQ(r.kind, IsolatedOutcome::Kind::crashed);
  EXPECT_EQ(r.signal, 0);
  EXPECT_EQ(r.status, 0);
  const auto start = std::chrono::steady_clock::now();
  r = run_isolated([]() -> std::string { for (;;) std::this_thread::sleep_for(std::chrono::seconds(1)); }, 0.3);
  EXPECT_EQ(r.kind, IsolatedOutcome::Kind::timed_out);
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GE(waited, 0.3);
  EXPECT_LT(waited, 5.0);
}

TEST(ByteCodec, CarriesValuesBitForBitAndRefusesToReadPastItsBytes) {
  using mlce::reader::detail::ByteReader;
  using mlce::reader::detail::ByteWriter;
  using namespace std::string_literals;  // "...\0..."s keeps the embedded NUL
  const std::vector<double> values{0.0, -0.0, 1e-310, -1e308, std::numeric_limits<double>::infinity(),
                                   std::numeric_limits<double>::quiet_NaN(), 1.0 / 3.0};
  ByteWriter w;
  w.str("node:2:x");
  w.doubles(values);
  w.strings({"", "a warning", "with a \0 inside"s});
  w.i64(-42);
  w.f64(-0.0);
  const std::string bytes = w.take();
  ByteReader r(bytes);
  EXPECT_EQ(r.str(), "node:2:x");
  const auto back = r.doubles();
  ASSERT_EQ(back.size(), values.size());
  for (std::size_t k = 0; k < values.size(); ++k)
    EXPECT_EQ(std::bit_cast<std::uint64_t>(back[k]), std::bit_cast<std::uint64_t>(values[k])) << k;  // nan, -0 and subnormals too
  EXPECT_EQ(r.strings(), (std::vector<std::string>{"", "a warning", "with a \0 inside"s}));
  EXPECT_EQ(r.i64(), -42);
  EXPECT_TRUE(std::signbit(r.f64()));
  EXPECT_NO_THROW(r.expect_end());
  // Cut anywhere, it throws instead of reading past the end; a count larger than the bytes left
  // is refused before anything is allocated for it.
  for (std::size_t cut = 0; cut < bytes.size(); ++cut) {
    ByteReader part(std::string_view(bytes).substr(0, cut));
    EXPECT_THROW(
        {
          (void)part.str();
          (void)part.doubles();
          (void)part.strings();
          (void)part.i64();
          (void)part.f64();
        },
        std::runtime_error)
        << cut;
  }
  ByteWriter huge;
  huge.u64(std::uint64_t{1} << 60);
  const std::string h = huge.take();
  ByteReader hr(h);
  EXPECT_THROW((void)hr.doubles(), std::runtime_error);
  const std::string longer = bytes + "x";
  ByteReader extra(longer);
  (void)extra.str(), (void)extra.doubles(), (void)extra.strings(), (void)extra.i64(), (void)extra.f64();
  EXPECT_THROW(extra.expect_end(), std::runtime_error);
}

TEST(FormatRegistry, PicksTheReaderByExtensionOrPrefix) {
  const auto& reg = default_registry();
  EXPECT_EQ(reg.for_path(kIso).name(), "mbdyn-text");
  EXPECT_EQ(reg.for_path(kIso + ".mov").name(), "mbdyn-text");
  EXPECT_EQ(reg.for_path(kIso + ".nc").name(), "mbdyn-netcdf");
  EXPECT_EQ(reg.for_path(std::string(MLCE_DATA_DIR) + "/lorenz_x.txt").name(), "column");
  EXPECT_THROW(reg.for_path("/nonexistent/run"), ReadError);
  const auto inv = reg.for_path(kIso).describe(kIso);
  EXPECT_EQ(inv.blocks, 201u);
  EXPECT_EQ(inv.nodes.size(), 7u);
  EXPECT_EQ(inv.nodes[3].label, 11);
  EXPECT_EQ(inv.nodes[3].kind, "dynamic");
  EXPECT_EQ(inv.nodes[2].kind, "static/dummy");  // the massless hub has no .ine rows
}

TEST(FormatRegistry, AnotherSolversFormatIsOneReaderAndOneAdd) {
  // The extension point the readers are built on: a format of a solver the project does not know
  // (here: "t x" pairs of a .toy file, for the test), registered beside the built-in ones, is found
  // by name and by its extension, and reads through the same interface; the built-ins are unchanged.
  struct ToyFormat final : FormatReader {
    std::string name() const override { return "toy"; }
    std::vector<std::string> extensions() const override { return {"toy"}; }
    bool recognizes(const std::string& path) const override { return fs::is_regular_file(path); }
    Inventory describe(const std::string& path) const override {
      Inventory inv;
      inv.source = path, inv.format = name(), inv.columns = {"x"};
      return inv;
    }
    ChannelSet read(const std::string& path, const std::vector<ChannelSpec>& channels, const ReadOptions&) const override {
      ChannelSet set;
      set.source = path;
      std::ifstream in(path);
      set.values.resize(channels.size());
      for (double t = 0.0, x = 0.0; in >> t >> x;) {
        set.time.push_back(t);
        for (auto& v : set.values) v.push_back(x);
      }
      for (const auto& c : channels) set.names.push_back(c.text);
      return set;
    }
  };
  FormatRegistry registry;
  registry.add(std::make_unique<ToyFormat>());
  registry.add(make_column_format());
  EXPECT_EQ(registry.names(), (std::vector<std::string>{"toy", "column"}));
  ASSERT_NE(registry.by_name("toy"), nullptr);
  EXPECT_EQ(registry.by_name("toy")->name(), "toy");
  EXPECT_EQ(registry.by_name("mbdyn-text"), nullptr);  // not in this registry
  const fs::path toy = fs::temp_directory_path() / ("mlce_" + std::to_string(::getpid()) + ".toy");
  std::ofstream(toy) << "0 1.5\n0.1 2.5\n";
  const FormatReader& reader = registry.for_path(toy.string());
  EXPECT_EQ(reader.name(), "toy");
  const ChannelSet set = reader.read(toy.string(), specs({"col:1"}));
  EXPECT_EQ(set.time, (std::vector<double>{0.0, 0.1}));
  EXPECT_EQ(set.values.at(0), (std::vector<double>{1.5, 2.5}));
  EXPECT_EQ(registry.for_path(std::string(MLCE_DATA_DIR) + "/lorenz_x.txt").name(), "column");
  fs::remove(toy);
  EXPECT_EQ(default_registry().names(), (std::vector<std::string>{"mbdyn-netcdf", "mbdyn-text", "column"}));
}

TEST(FormatRegistry, ANetcdfFileIsKnownByItsBytesWhateverItsName) {
  // run.cdf, run.nc4, run.dat (which the column reader owns by extension): the magic number decides,
  // and the channels are those of the same file named .nc.
  const std::string nc = kIso + ".nc";
  const auto want = read_mbdyn_netcdf(nc, specs({"joint:33:14", "rel:13:4:z"}));
  for (const char* name : {"run.cdf", "run.nc4", "run.dat"}) {
    const fs::path copy = fs::temp_directory_path() / (std::to_string(::getpid()) + name);
    fs::copy_file(nc, copy, fs::copy_options::overwrite_existing);
    const FormatReader& reader = default_registry().for_path(copy.string());
    EXPECT_EQ(reader.name(), "mbdyn-netcdf") << name;
    const auto got = reader.read(copy.string(), specs({"joint:33:14", "rel:13:4:z"}));
    EXPECT_EQ(got.time, want.time) << name;
    EXPECT_EQ(got.values, want.values) << name;
    EXPECT_EQ(reader.describe(copy.string()).blocks, 201u) << name;
    fs::remove(copy);
  }
  // A text file is still read by its name.
  EXPECT_EQ(default_registry().for_path(std::string(MLCE_DATA_DIR) + "/lorenz_x.txt").name(), "column");
}

TEST(FormatRegistry, PrefixOfARunWithNetcdfOutputOnlyReadsItsNcFile) {
  // `output results: netcdf, no text`: MBDyn writes .out, .log and .nc, and no (or empty) entity
  // files. By prefix such a run was read as a text set with no channel at all.
  const fs::path dir = fs::path(::testing::TempDir()) / "netcdf_only";
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const char* ext : {".out", ".log", ".nc"}) fs::copy_file(kIso + ext, dir / (std::string("iso_200rpm") + ext));
  const std::string prefix = (dir / "iso_200rpm").string();
  const auto& reg = default_registry();
  const auto spec = specs({"rel:13:4:z", "node:2:x"});
  auto expect_reads_the_nc = [&] {
    ASSERT_EQ(reg.for_path(prefix).name(), "mbdyn-netcdf");
    const auto by_prefix = reg.for_path(prefix).read(prefix, spec, {});
    const auto direct = read_mbdyn_netcdf(kIso + ".nc", spec);  // independent: the bundled file itself
    ASSERT_EQ(by_prefix.time.size(), 201u);
    EXPECT_EQ(by_prefix.values, direct.values);
    EXPECT_EQ(reg.for_path(prefix).describe(prefix).nodes.size(), 8u);  // node 1 (output off) too
  };
  expect_reads_the_nc();
  // The .out named explicitly is the text set: it says where the channels are.
  const auto inv = reg.for_path(prefix + ".out").describe(prefix + ".out");
  EXPECT_TRUE(inv.nodes.empty());
  ASSERT_EQ(inv.warnings.size(), 1u);
  EXPECT_NE(inv.warnings[0].find("no entity rows"), std::string::npos) << inv.warnings[0];
  EXPECT_NE(inv.warnings[0].find("read " + prefix + ".nc"), std::string::npos) << inv.warnings[0];
  std::ofstream(prefix + ".mov").close();  // an empty .mov, as `no text` leaves it
  expect_reads_the_nc();
  try {
    reg.for_path(prefix + ".out").describe(prefix + ".out");
    ADD_FAILURE() << "no error";
  } catch (const ReadError& e) {
    EXPECT_NE(std::string(e.what()).find("no rows (empty file"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("read " + prefix + ".nc"), std::string::npos) << e.what();
  }
  // A text set with rows stays a text set, .nc beside it or not.
  fs::copy_file(kIso + ".mov", prefix + ".mov", fs::copy_options::overwrite_existing);
  EXPECT_EQ(reg.for_path(prefix).name(), "mbdyn-text");
  EXPECT_TRUE(reg.for_path(prefix).describe(prefix).warnings.empty());
}

// ---- synthetic sets: every orientation parametrization, unwrapping, interruption ----------

namespace {

Matrix3 mul(const Matrix3& a, const Matrix3& b) {
  Matrix3 c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[3 * i + j] += a[3 * i + k] * b[3 * k + j];
  return c;
}
Matrix3 axis_rot(int axis, double a) {
  const double c = std::cos(a), s = std::sin(a);
  const int i = (axis + 1) % 3, j = (axis + 2) % 3;
  Matrix3 r{};
  r[3 * axis + axis] = 1;
  r[3 * i + i] = c, r[3 * i + j] = -s, r[3 * j + i] = s, r[3 * j + j] = c;
  return r;
}

struct SyntheticSet {
  fs::path dir;
  std::string prefix;
  std::vector<double> zeta;
  std::vector<double> r12;  ///< make_netcdf_set: R12 of node 2, as joint 7's .R holds it
};

/// The synthetic motion: node 1 (B) turns about a tilted axis; node 2 (A) = B * R_axis(zeta) * R_rel0.
Matrix3 node1_pose(double t) { return mul(axis_rot(0, 0.2), axis_rot(2, 3.0 * t)); }
Matrix3 node2_pose(double t, double zeta, int axis) {
  return mul(mul(node1_pose(t), axis_rot(axis, zeta)), axis_rot(2, 0.5 * std::numbers::pi));
}

/// Node 1 and node 2 as above, zeta sweeping beyond +-pi, written in parametrization `o` with 16
/// digits.
SyntheticSet make_set(Orientation o, int axis, const std::string& name) {
  SyntheticSet s;
  s.dir = fs::temp_directory_path() / ("mlce_syn_" + std::to_string(::getpid()) + "_" + name);
  fs::create_directories(s.dir);
  s.prefix = (s.dir / "run").string();
  auto B = [](double t) { return node1_pose(t); };
  auto A = [&](double t, double z) { return node2_pose(t, z, axis); };
  auto values = [&](const Matrix3& R) {
    std::string out;
    char buf[40];
    for (double v : orientation_values(o, R)) std::snprintf(buf, sizeof buf, " %.16e", v), out += buf;
    return out;
  };
  std::ofstream log(s.prefix + ".log"), out(s.prefix + ".out"), mov(s.prefix + ".mov");
  log << "output frequency: 1\n";
  log << "structural node: 1 0 0 0 " << orientation_name(o) << values(B(0)) << "\n";
  log << "structural node: 2 1 0 0 " << orientation_name(o) << values(A(0, 0)) << "\n";
  out << "# Step Time TStep NIter ResErr SolErr SolConv Out\n";
  const std::size_t n = 400;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = 0.05 * static_cast<double>(k), z = 5.0 * std::sin(0.7 * t);
    s.zeta.push_back(z);
    out << "Step " << k << " " << t << " 0.05 1 0 0 0 1\n";
    for (int node = 1; node <= 2; ++node) {
      mov << "       " << node << " 0 0 0" << values(node == 1 ? B(t) : A(t, z)) << " 0 0 0 0 0 0\n";
    }
  }
  return s;
}

/// The same motion as make_set as MBDyn writes it to NetCDF (format doc section 11): records
/// along the unlimited dimension `time`, node.struct.<L>.X, and one orientation variable per
/// node: .E (degrees, the sequence named in its `description`), .Phi, or .R stored column-major
/// (R11 R21 R31 R12 ..., the transpose of the text files' row order). A .log beside it gives the
/// initial configuration, as MBDyn's would. Joint 7 (a revolute hinge's variables: .f .m .F .M,
/// then its relative rotation .R and .Omega) holds node 2's matrix in its .R.
SyntheticSet make_netcdf_set(Orientation o, int axis, const std::string& name) {
  SyntheticSet s = make_set(o, axis, "nc_" + name);  // the text set gives zeta and the .log
  const fs::path nc_path = s.dir / "run.nc";
  auto column_major = [](const Matrix3& R) {  // R11 R21 R31 R12 ...: how MBDyn stores .R
    std::vector<double> v(9);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) v[3 * j + i] = R[3 * i + j];
    return v;
  };
  auto ok = [](int status) { ASSERT_EQ(status, NC_NOERR) << nc_strerror(status); };
  int id = 0, time_dim = 0, vec3 = 0, time_var = 0;
  ok(nc_create(nc_path.c_str(), NC_CLOBBER, &id));
  ok(nc_def_dim(id, "time", NC_UNLIMITED, &time_dim));
  ok(nc_def_dim(id, "Vec3", 3, &vec3));  // Z's spelling; M writes vec3: the reader must not care
  ok(nc_def_var(id, "time", NC_DOUBLE, 1, &time_dim, &time_var));
  const char* suffix = o == Orientation::mat ? ".R" : o == Orientation::phi ? ".Phi" : ".E";
  const char* sequence = o == Orientation::euler313 ? "(313)" : o == Orientation::euler321 ? "(321)" : "(123)";
  int X[2] = {0, 0}, R[2] = {0, 0};
  for (int node = 1; node <= 2; ++node) {
    const std::string base = "node.struct." + std::to_string(node);
    const int dims2[2] = {time_dim, vec3}, dims3[3] = {time_dim, vec3, vec3};
    ok(nc_def_var(id, (base + ".X").c_str(), NC_DOUBLE, 2, dims2, &X[node - 1]));
    ok(nc_def_var(id, (base + suffix).c_str(), NC_DOUBLE, o == Orientation::mat ? 3 : 2,
                  o == Orientation::mat ? dims3 : dims2, &R[node - 1]));
    const std::string description = o == Orientation::mat ? "global orientation matrix (R11, R21, R31, R12, ...)"
                                    : o == Orientation::phi ? "global orientation vector"
                                    : std::string("global orientation Euler angles ") + sequence;
    ok(nc_put_att_text(id, R[node - 1], "description", description.size(), description.c_str()));
  }
  int joint[6] = {};
  const char* joint_vars[6] = {".f", ".m", ".F", ".M", ".R", ".Omega"};
  for (int v = 0; v < 6; ++v) {
    const int dims2[2] = {time_dim, vec3}, dims3[3] = {time_dim, vec3, vec3};
    ok(nc_def_var(id, (std::string("elem.joint.7") + joint_vars[v]).c_str(), NC_DOUBLE, v == 4 ? 3 : 2,
                  v == 4 ? dims3 : dims2, &joint[v]));
  }
  ok(nc_enddef(id));
  for (std::size_t k = 0; k < s.zeta.size(); ++k) {
    const double t = 0.05 * static_cast<double>(k);
    const std::size_t start[3] = {k, 0, 0}, one[1] = {1}, row[2] = {1, 3}, block[3] = {1, 3, 3};
    ok(nc_put_vara_double(id, time_var, start, one, &t));
    for (int node = 1; node <= 2; ++node) {
      const Matrix3 Rk = node == 1 ? node1_pose(t) : node2_pose(t, s.zeta[k], axis);
      const double x[3] = {static_cast<double>(node - 1), 0, 0};
      ok(nc_put_vara_double(id, X[node - 1], start, row, x));
      const std::vector<double> v = o == Orientation::mat ? column_major(Rk) : orientation_values(o, Rk);
      ok(nc_put_vara_double(id, R[node - 1], start, o == Orientation::mat ? block : row, v.data()));
    }
    const Matrix3 Rk = node2_pose(t, s.zeta[k], axis);
    const double w[3] = {-1.0, -2.0, -3.0};
    for (int v = 0; v < 4; ++v) ok(nc_put_vara_double(id, joint[v], start, row, w));
    ok(nc_put_vara_double(id, joint[4], start, block, column_major(Rk).data()));
    ok(nc_put_vara_double(id, joint[5], start, row, w));
    s.r12.push_back(Rk[1]);
  }
  ok(nc_close(id));
  s.prefix = nc_path.string();
  return s;
}

}  // namespace

// The library's single-sample form of rel:A:B:AXIS (public API, reader/orientation.hpp): a known
// rotation zeta about each axis of B's frame, on top of an initial relative pose of a quarter turn
// and B turning and tilted, reads zeta, wrapped to (-pi, pi].
TEST(Orientation, RelativeTwistOfOneSampleIsTheKnownAngle) {
  for (int axis = 0; axis < 3; ++axis)
    for (double zeta : {-3.0, -1.2, 0.0, 0.4, 2.9, 3.5}) {
      const double t = 0.7, wrapped = std::remainder(zeta, 2.0 * std::numbers::pi);
      EXPECT_NEAR(relative_twist(node2_pose(t, zeta, axis), node1_pose(t), node2_pose(0.0, 0.0, axis), node1_pose(0.0), axis),
                  wrapped, 1e-12)
          << "axis " << axis << ", zeta " << zeta;
    }
}

class OrientationRoundTrip : public ::testing::TestWithParam<std::tuple<Orientation, int>> {};

TEST_P(OrientationRoundTrip, KnownRelativeRotationReadsBackUnwrapped) {
  const auto [o, axis] = GetParam();
  const std::string axis_name(1, static_cast<char>('x' + axis));
  const auto set = make_set(o, axis, std::string(orientation_name(o)) + axis_name);
  const auto cs = read_mbdyn_text(set.prefix, specs({("rel:2:1:" + axis_name).c_str()}));
  ASSERT_EQ(cs.values[0].size(), set.zeta.size());
  for (std::size_t k = 0; k < set.zeta.size(); ++k)
    ASSERT_NEAR(cs.values[0][k], set.zeta[k], 1e-9) << orientation_name(o) << " sample " << k;
  fs::remove_all(set.dir);
}

// The same known motion through the NetCDF reader: a matrix stored column-major read row-major
// would turn the other way (zeta -> -zeta), an Euler sequence ignored would give another axis.
TEST_P(OrientationRoundTrip, NetcdfKnownRelativeRotationReadsBackUnwrapped) {
  const auto [o, axis] = GetParam();
  const std::string axis_name(1, static_cast<char>('x' + axis));
  const auto set = make_netcdf_set(o, axis, std::string(orientation_name(o)) + axis_name);
  const auto cs = read_mbdyn_netcdf(set.prefix, specs({("rel:2:1:" + axis_name).c_str(), "node:2:x", "node:2:r2"}));
  ASSERT_EQ(cs.values[0].size(), set.zeta.size());
  EXPECT_TRUE(cs.warnings.empty());  // the .log beside the file gave the initial configuration
  const auto text = read_mbdyn_text((set.dir / "run").string(), specs({"node:2:r2"}));
  // Joint columns as the .jnt would number them: 2-13 f m F M, 14-22 R row by row, 23-25 Omega.
  const auto jnt = read_mbdyn_netcdf(set.prefix, specs({"joint:7:15", "joint:7:23"}));
  for (std::size_t k = 0; k < set.zeta.size(); ++k) {
    ASSERT_EQ(jnt.values[0][k], set.r12[k]) << "record " << k;
    ASSERT_EQ(jnt.values[1][k], -1.0);
  }
  for (std::size_t k = 0; k < set.zeta.size(); ++k) {
    ASSERT_NEAR(cs.values[0][k], set.zeta[k], 1e-9) << orientation_name(o) << " record " << k;
    ASSERT_EQ(cs.values[1][k], 1.0);
    // The second orientation number as the text file writes it (R12 for a matrix, row by row).
    ASSERT_NEAR(cs.values[2][k], text.values[0][k], 1e-12) << orientation_name(o) << " record " << k;
  }
  fs::remove_all(set.dir);
}

// A record that the solver never wrote holds the NetCDF fill value (9.97e36, finite): an error
// naming the variable and the record, never a number passed on to the estimator.
TEST(MbdynNetcdf, AnyTimeHistoryIsAVarChannelAndTheInventoryListsThoseNoOtherChannelReaches) {
  // Beams, forces and aerodynamic elements write only to NetCDF their richer data (format doc
  // section 11): var:NAME:K reads component K of any record variable, a 3x3 matrix row by row
  // (MBDyn stores it column-major). Truth: the values written. Classic and netCDF-4 files alike
  // (the latter read in a child process, the inventory crossing a pipe).
  for (const int format : {NC_CLOBBER, NC_CLOBBER | NC_NETCDF4}) {
    const fs::path path = fs::temp_directory_path() / ("mlce_var_" + std::to_string(::getpid()) + ".nc");
    auto ok = [](int status) { ASSERT_EQ(status, NC_NOERR) << nc_strerror(status); };
    int id = 0, time_dim = 0, vec3 = 0, labels_dim = 0, time_var = 0, force = 0, rotation = 0, labels = 0;
    ok(nc_create(path.c_str(), format, &id));
    ok(nc_def_dim(id, "time", NC_UNLIMITED, &time_dim));
    ok(nc_def_dim(id, "vec3", 3, &vec3));
    ok(nc_def_dim(id, "beam_elem_labels_dim", 1, &labels_dim));
    ok(nc_def_var(id, "time", NC_DOUBLE, 1, &time_dim, &time_var));
    ok(nc_def_var(id, "elem.beam", NC_INT, 1, &labels_dim, &labels));
    const int dims2[2] = {time_dim, vec3}, dims3[3] = {time_dim, vec3, vec3};
    ok(nc_def_var(id, "elem.beam.100.F_I", NC_DOUBLE, 2, dims2, &force));
    ok(nc_def_var(id, "elem.beam.100.R_I", NC_DOUBLE, 3, dims3, &rotation));
    ok(nc_enddef(id));
    const int label = 100;
    ok(nc_put_var_int(id, labels, &label));
    auto row_major = [](std::size_t k, std::size_t r) { return 100.0 * static_cast<double>(k) + static_cast<double>(r); };
    for (std::size_t k = 0; k < 20; ++k) {
      const double t = 0.1 * static_cast<double>(k), f[3] = {1.0 * k, 2.0 * k, 3.0 * k};
      double stored[9];
      for (std::size_t i = 0; i < 3; ++i)
        for (std::size_t j = 0; j < 3; ++j) stored[3 * j + i] = row_major(k, 3 * i + j);  // column-major, as MBDyn
      const std::size_t start[3] = {k, 0, 0}, one[1] = {1}, row[2] = {1, 3}, block[3] = {1, 3, 3};
      ok(nc_put_vara_double(id, time_var, start, one, &t));
      ok(nc_put_vara_double(id, force, start, row, f));
      ok(nc_put_vara_double(id, rotation, start, block, stored));
    }
    ok(nc_close(id));
    const auto set = read_mbdyn_netcdf(path.string(), specs({"var:elem.beam.100.F_I:2", "var:elem.beam.100.R_I:2",
                                                             "var:elem.beam.100.R_I:4", "var:elem.beam.100.F_I"}));
    ASSERT_EQ(set.time.size(), 20u);
    for (std::size_t k = 0; k < 20; ++k) {
      EXPECT_EQ(set.values[0][k], 2.0 * static_cast<double>(k));
      EXPECT_EQ(set.values[1][k], row_major(k, 1));  // R12
      EXPECT_EQ(set.values[2][k], row_major(k, 3));  // R21
      EXPECT_EQ(set.values[3][k], 1.0 * static_cast<double>(k));  // no K: the first component
    }
    const auto inv = describe_mbdyn_netcdf(path.string());
    ASSERT_EQ(inv.variables.size(), 2u);
    EXPECT_EQ(inv.variables[0].name, "elem.beam.100.F_I");
    EXPECT_EQ(inv.variables[0].components, 3u);
    EXPECT_EQ(inv.variables[1].name, "elem.beam.100.R_I");
    EXPECT_EQ(inv.variables[1].components, 9u);
    EXPECT_EQ(read_error_of([&] { read_mbdyn_netcdf(path.string(), specs({"var:elem.beam.100.F_I:4"})); }),
              path.string() + ": channel 'var:elem.beam.100.F_I:4': 'elem.beam.100.F_I' has 3 component(s) per record, "
                              "component 4 requested");
    EXPECT_NE(read_error_of([&] { read_mbdyn_netcdf(path.string(), specs({"var:elem.beam:1"})); }).find("is no time history"),
              std::string::npos);
    fs::remove(path);
  }
  EXPECT_THROW(parse_channel_spec("var:"), ReadError);
  EXPECT_THROW(parse_channel_spec("var:x:0"), ReadError);
  EXPECT_THROW(parse_channel_spec("var:x:1:2"), ReadError);
  EXPECT_NE(read_error_of([&] { read_mbdyn_text(kIso, specs({"var:run.step"})); }).find("addresses a NetCDF variable"),
            std::string::npos);
}

TEST(MbdynNetcdf, ChannelsTheFileDoesNotHoldAreOneErrorEachSayingWhatItHolds) {
  // The run's .nc holds 15 columns per deformable axial joint (label + 14), Euler angles (3 numbers)
  // per node, plain labels, no .frc rows and no columns: each request beyond that is one error.
  const std::string nc = kIso + ".nc";
  auto error = [&](const char* spec) { return read_error_of([&] { read_mbdyn_netcdf(nc, specs({spec})); }); };
  EXPECT_EQ(error("joint:33:16"), nc + ": joint 33 has 15 columns, column 16 requested");
  EXPECT_EQ(error("node:2:r9"), nc + ": channel 'node:2:r9': node 2 has 3 orientation numbers");
  EXPECT_EQ(error("joint:33.2:2"), nc + ": channel 'joint:33.2:2': a label with a sub-index (33.2) addresses rows of the "
                                        "text output (.mod, .frc); joints and nodes here have plain labels");
  EXPECT_EQ(error("frc:5:2"), nc + ": channel 'frc:5:2': the NetCDF file has no .frc rows; its other time histories are "
                                   "var:NAME[:K] channels (`mlce channels " + nc + "` lists them)");
  EXPECT_EQ(error("col:2"), nc + ": channel 'col:2' addresses a column file; NetCDF takes node:, joint:, ine:, rel: or var:");
  EXPECT_EQ(error("var:time:2"), nc + ": channel 'var:time:2': 'time' has 1 component(s) per record, component 2 requested");
  EXPECT_EQ(error("node:99:x"), nc + ": no structural node 99; with output: 2 3 4 11 12 13 14");
  // The last column of each group reads (the bounds are the groups' own, not one off).
  EXPECT_EQ(read_mbdyn_netcdf(nc, specs({"joint:33:15", "node:2:r3"})).values.size(), 2u);
}

TEST(MbdynNetcdf, TruncatedFileReadsItsCompleteRecordsWithAWarning) {
  // A copy cut short keeps the header's record count (201); the classic format reads the missing
  // records as zeros. The records before the cut must equal the whole file's, and the set ends
  // before the zeros.
  const fs::path cut = fs::temp_directory_path() / ("mlce_cut_" + std::to_string(::getpid()) + ".nc");
  fs::copy_file(kIso + ".nc", cut, fs::copy_options::overwrite_existing);
  fs::resize_file(cut, fs::file_size(cut) * 6 / 10);
  const auto spec = specs({"node:2:x", "joint:33:14"});
  const auto whole = read_mbdyn_netcdf(kIso + ".nc", spec);
  const auto part = read_mbdyn_netcdf(cut.string(), spec);
  const auto inventory = default_registry().for_path(cut.string()).describe(cut.string());
  fs::remove(cut);
  ASSERT_EQ(whole.time.size(), 201u);
  ASSERT_GT(part.time.size(), 50u);
  ASSERT_LT(part.time.size(), 201u * 6 / 10);
  EXPECT_EQ(inventory.blocks, part.time.size());
  EXPECT_EQ(inventory.t_last, part.time.back());
  for (std::size_t k = 0; k < part.time.size(); ++k) {
    EXPECT_EQ(part.time[k], whole.time[k]) << k;
    for (std::size_t c = 0; c < spec.size(); ++c) EXPECT_EQ(part.values[c][k], whole.values[c][k]) << k;
  }
  ASSERT_FALSE(part.warnings.empty());
  // The time of the record left out, to its digits (std::to_string printed six decimals).
  char left_out[64];
  std::snprintf(left_out, sizeof left_out, "have time 0 after t = %.10g ", whole.time[part.time.size()]);
  EXPECT_NE(part.warnings[0].find(left_out), std::string::npos) << part.warnings[0];
  EXPECT_NE(part.warnings[0].find("read the first " + std::to_string(part.time.size()) + " records"), std::string::npos)
      << part.warnings[0];
}

TEST(MbdynNetcdf, CorruptedHeaderCountIsOneErrorNotAMinuteOfAllocation) {
  // libnetcdf trusts a classic header's counts: a flipped byte had nc_open run 50 s in 15 GB.
  const fs::path path = fs::temp_directory_path() / ("mlce_hdr_" + std::to_string(::getpid()) + ".nc");
  write_node_x_records(path, {0.0, 1.0, 2.0});
  const auto patched = [&](std::size_t at, std::uint32_t value) {  // a big-endian word of the header
    std::string bytes = bytes_of(path);
    for (int k = 0; k < 4; ++k) bytes[at + k] = static_cast<char>(value >> (24 - 8 * k) & 0xff);
    const fs::path p = path.string() + ".patched.nc";
    std::ofstream(p, std::ios::binary) << bytes;
    return p.string();
  };
  // Classic layout: magic, numrecs at 4, dimensions "time" and "vec3" at 8..39, no global
  // attributes at 40, then NC_VARIABLE (0x0B) at 48 and the variable count at 52.
  const std::string bytes = bytes_of(path);
  ASSERT_EQ(bytes.substr(0, 4), std::string("CDF\x01", 4));
  ASSERT_EQ(bytes.substr(48, 8), std::string("\0\0\0\x0b\0\0\0\x02", 8));
  EXPECT_EQ(read_error_of([&] { read_mbdyn_netcdf(patched(52, 0x7fffffff), specs({"node:1:y"})); }),
            path.string() + ".patched.nc: corrupt NetCDF header at byte 52: 2147483647 variables cannot fit in the "
            "file's " + std::to_string(bytes.size()) + " bytes");
  // The first variable's dimension id (at 68) beyond the two dimensions.
  EXPECT_NE(read_error_of([&] { describe_mbdyn_netcdf(patched(68, 7)); })
                .find("corrupt NetCDF header at byte 68: a variable's dimension id beyond the 2 dimensions"),
            std::string::npos);
  // A record count of 2^31 - 1: read up to what the file holds (the zero-time tail dropped with a
  // warning), not 2^31 records into memory.
  const auto many = read_mbdyn_netcdf(patched(4, 0x7fffffff), specs({"node:1:y"}));
  EXPECT_EQ(many.values[0], (std::vector<double>{0.0, 1.0}));
  EXPECT_FALSE(many.warnings.empty());
  fs::remove(path);
  fs::remove(path.string() + ".patched.nc");
}

TEST(MbdynNetcdf, HeaderThatWouldCrashLibnetcdfIsOneError) {
  // libnetcdf 4.9's nc_open sizes a variable of a type beyond the classic ones (here 12, NC_STRING)
  // as 0 bytes, and its size check (NC_check_vlen) divides by that size: SIGFPE, a crash of the
  // whole program (fuzz_netcdf found it). A classic file with dimensions "time" (unlimited) and
  // "vec3" (3) and one variable "cube" of type double (6) over (vec3, vec3, vec3), its type made 12:
  // one error naming the byte. A dimension id made the record dimension's (not allowed after the
  // first) is libnetcdf's own error.
  const fs::path path = fs::temp_directory_path() / ("mlce_vlen_" + std::to_string(::getpid()) + ".nc");
  {
    int id = 0, time_dim = 0, vec3 = 0, v = 0;
    ASSERT_EQ(nc_create(path.c_str(), NC_CLOBBER, &id), NC_NOERR);
    ASSERT_EQ(nc_def_dim(id, "time", NC_UNLIMITED, &time_dim), NC_NOERR);
    ASSERT_EQ(nc_def_dim(id, "vec3", 3, &vec3), NC_NOERR);
    const int dims[3] = {vec3, vec3, vec3};
    ASSERT_EQ(nc_def_var(id, "cube", NC_DOUBLE, 3, dims, &v), NC_NOERR);
    ASSERT_EQ(nc_close(id), NC_NOERR);
  }
  // magic, numrecs, the two dimensions (8..39), no global attributes (40..47), NC_VARIABLE and
  // the count (48..55), then "cube": name length and name (56..63), rank at 64, dimension ids at
  // 68, 72, 76, no attributes (80..87), type at 88.
  const std::string bytes = bytes_of(path);
  ASSERT_EQ(bytes.substr(64, 16), std::string("\0\0\0\x03\0\0\0\x01\0\0\0\x01\0\0\0\x01", 16));
  ASSERT_EQ(bytes.substr(88, 4), std::string("\0\0\0\x06", 4));
  const auto patched = [&](std::size_t at, char value) {
    std::string b = bytes;
    b[at + 3] = value;
    const fs::path p = path.string() + ".patched.nc";
    std::ofstream(p, std::ios::binary) << b;
    return p.string();
  };
  EXPECT_NE(read_error_of([&] { describe_mbdyn_netcdf(patched(72, 0)); }).find("NC_UNLIMITED in the wrong index"),
            std::string::npos);
  EXPECT_EQ(read_error_of([&] { describe_mbdyn_netcdf(patched(88, 12)); }),
            path.string() + ".patched.nc: corrupt NetCDF header at byte 88: variable type 12");
  // The file as written passes the header walk and nc_open; it is no MBDyn output, which is said next.
  EXPECT_NE(read_error_of([&] { describe_mbdyn_netcdf(path.string()); }).find("no variable 'time'"), std::string::npos);
  fs::remove(path);
  fs::remove(path.string() + ".patched.nc");
}

TEST(MbdynNetcdf, RecordNeverWrittenIsAnErrorNotAHugeNumber) {
  const fs::path path = fs::temp_directory_path() / ("mlce_fill_" + std::to_string(::getpid()) + ".nc");
  write_node_x_records(path, {2.0, 2.0, kUnwritten});  // record 2 left unwritten
  if (::testing::Test::HasFatalFailure()) return;
  const std::string what = read_error_of([&] { read_mbdyn_netcdf(path.string(), specs({"node:1:y"})); });
  EXPECT_NE(what.find("'node.struct.1.X' record 2: holds the NetCDF fill value"), std::string::npos) << what;
  fs::remove(path);
}

INSTANTIATE_TEST_SUITE_P(EveryParametrization, OrientationRoundTrip,
                         ::testing::Combine(::testing::Values(Orientation::euler123, Orientation::euler313,
                                                              Orientation::euler321, Orientation::phi,
                                                              Orientation::mat),
                                            ::testing::Values(0, 2)));

TEST(Orientation, ParametrizationsRoundTrip) {
  const Matrix3 R = mul(mul(axis_rot(2, 0.4), axis_rot(0, -0.7)), axis_rot(1, 1.1));
  for (auto o : {Orientation::euler123, Orientation::euler313, Orientation::euler321, Orientation::phi, Orientation::mat}) {
    const Matrix3 back = rotation_matrix(o, orientation_values(o, R));
    for (int i = 0; i < 9; ++i) EXPECT_NEAR(back[i], R[i], 1e-12) << orientation_name(o);
  }
}

TEST(MbdynText, InterruptedRunReadsEveryCompleteBlockWithWarnings) {
  const fs::path dir = fs::temp_directory_path() / ("mlce_cut_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  for (const char* e : {".log", ".out", ".mov"}) fs::copy_file(kIso + e, dir / (std::string("run") + e));
  // Cut the .mov mid-line in the last block (row 4 of 7, 20 characters in).
  std::ifstream in(kIso + ".mov");
  std::ostringstream keep;
  std::string line;
  std::size_t n = 0;
  const std::size_t stop = 200 * 7 + 3;
  while (std::getline(in, line) && n < stop) keep << line << "\n", ++n;
  std::getline(in, line);
  keep << line.substr(0, 20);
  std::ofstream(dir / "run.mov", std::ios::trunc) << keep.str();
  const auto cs = read_mbdyn_text((dir / "run").string(), specs({"node:2:x", "rel:13:4:z"}));
  EXPECT_EQ(cs.time.size(), 200u);
  std::string all;
  for (const auto& w : cs.warnings) all += w + "\n";
  EXPECT_NE(all.find("no end of line"), std::string::npos) << all;
  EXPECT_NE(all.find("last block is incomplete"), std::string::npos) << all;
  EXPECT_NE(all.find("using the first 200"), std::string::npos) << all;
  fs::remove_all(dir);
}

TEST(MbdynText, RunThatDivergesIsReadUpToUntilAndSaysWhereItStopsBeingFinite) {
  // A run that blew up: every field of every row from output block 150 on printed as nan.
  const fs::path dir = fs::temp_directory_path() / ("mlce_diverged_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  for (const char* e : {".log", ".out"}) fs::copy_file(kIso + e, dir / (std::string("run") + e));
  constexpr std::size_t kRows = 7, kFinite = 150;
  {
    std::ifstream in(kIso + ".mov");
    std::ofstream out(dir / "run.mov");
    std::string line;
    for (std::size_t n = 0; std::getline(in, line); ++n) {
      if (n >= kFinite * kRows) {
        std::istringstream f(line);
        std::string label, field;
        f >> label;
        line = label;
        while (f >> field) line += " nan";
      }
      out << line << "\n";
    }
  }
  const std::string prefix = (dir / "run").string();
  const auto t = out_times(kIso + ".out");
  ASSERT_GT(t.size(), kFinite + 1);
  const auto channels = specs({"node:2:x", "rel:13:4:z"});
  const auto original = read_mbdyn_text(kIso, channels);

  {
    char where[160];
    std::snprintf(where, sizeof where, "This block is at t = %.10g; the %zu before it, to t = %.10g, are finite", t[kFinite],
                  kFinite, t[kFinite - 1]);
    const std::string what = read_error_of([&] { read_mbdyn_text(prefix, channels); });
    EXPECT_NE(what.find("run.mov:" + std::to_string(kFinite * kRows + 1) + ": column "), std::string::npos) << what;
    EXPECT_NE(what.find("'nan': expected a finite number (did the run diverge?"), std::string::npos) << what;
    EXPECT_NE(what.find(where), std::string::npos) << what;
  }
  const double dt = t[1] - t[0];
  for (const double until : {t[kFinite - 1], t[kFinite - 1] + 0.3 * dt}) {
    ReadOptions o;
    o.until = until;
    const auto cs = read_mbdyn_text(prefix, channels, o);
    ASSERT_EQ(cs.time.size(), kFinite);
    EXPECT_TRUE(cs.warnings.empty());
    for (std::size_t c = 0; c < channels.size(); ++c)
      for (std::size_t k = 0; k < kFinite; ++k) ASSERT_EQ(cs.values[c][k], original.values[c][k]) << c << " " << k;
  }
  ReadOptions earlier;
  earlier.until = t[kFinite - 1] - 0.3 * dt;
  EXPECT_EQ(read_mbdyn_text(prefix, channels, earlier).time.size(), kFinite - 1);
  ReadOptions one;  // one block: the layout ends at the second block's first row, which is not parsed
  one.until = t[0];
  EXPECT_EQ(read_mbdyn_text(prefix, channels, one).time.size(), 1u);
  ReadOptions before;
  before.until = t[0] - 1.0;
  EXPECT_THROW(read_mbdyn_text(prefix, channels, before), ReadError);
  fs::remove_all(dir);
}

TEST(MbdynNetcdf, RecordsAfterUntilAreNotRead) {
  const fs::path path = fs::temp_directory_path() / ("mlce_until_" + std::to_string(::getpid()) + ".nc");
  write_node_x_records(path, {0.0, 1.0, 2.0, std::nan(""), std::nan("")});  // records 3 and 4 diverged
  if (::testing::Test::HasFatalFailure()) return;
  const std::string what = read_error_of([&] { read_mbdyn_netcdf(path.string(), specs({"node:1:y"})); });
  EXPECT_NE(what.find("'node.struct.1.X' record 3: expected a finite number"), std::string::npos) << what;
  ReadOptions o;
  o.until = 0.2;
  const auto cs = read_mbdyn_netcdf(path.string(), specs({"node:1:y"}), o);
  ASSERT_EQ(cs.time.size(), 3u);
  EXPECT_EQ(cs.values[0], (std::vector<double>{0.0, 1.0, 2.0}));
  fs::remove(path);
}

TEST(ReadOptions, StepsUntilCountsTheLeadingStepsWithinAMillionthOfTheStep) {
  const std::vector<double> t{0.0, 0.1, 0.2, 0.3};
  auto steps = [&](double until) {
    ReadOptions o;
    o.until = until;
    return steps_until(t, o, "f");
  };
  EXPECT_EQ(steps(std::numeric_limits<double>::infinity()), 4u);
  EXPECT_EQ(steps(0.2), 3u);
  EXPECT_EQ(steps(0.2 - 1e-9), 3u);  // 0.1 + 0.1 prints as 0.2 and may be a rounding above it
  EXPECT_EQ(steps(0.2 - 1e-3), 2u);
  EXPECT_EQ(steps(5.0), 4u);
  EXPECT_EQ(steps(0.0), 1u);
  ReadOptions o;
  o.until = 0.1;
  EXPECT_EQ(steps_until({0.0, std::nan(""), 0.2}, o, "f"), 2u);  // the nan time is kept for the caller to refuse
  EXPECT_EQ(read_error_of([&] { steps(-0.5); }), "f: no output step at t <= -0.5 (the first is at t = 0)");
}

TEST(MbdynText, FilesSavedWithAByteOrderMarkAndCrlfReadTheSame) {
  // The set as a Windows editor saves it: a UTF-8 byte-order mark and CR LF line ends.
  const fs::path dir = fs::temp_directory_path() / ("mlce_bom_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  for (const char* e : {".log", ".out", ".mov"}) {
    std::ifstream in(kIso + e);
    std::ostringstream out;
    out << "\xEF\xBB\xBF";
    for (std::string line; std::getline(in, line);) out << line << "\r\n";
    std::ofstream(dir / (std::string("run") + e), std::ios::binary) << out.str();
  }
  const auto a = read_mbdyn_text(kIso, specs({"node:2:x", "rel:13:4:z"}));
  const auto b = read_mbdyn_text((dir / "run").string(), specs({"node:2:x", "rel:13:4:z"}));
  EXPECT_EQ(b.time, a.time);
  EXPECT_EQ(b.values, a.values);
  fs::remove_all(dir);
}

namespace {

/// `text` written as a gzip file by zlib's deflate (what `gzip` writes); `members` > 1 splits it
/// into that many gzip members, as `cat a.gz b.gz > c.gz` joins them.
void write_gzip(const fs::path& path, const std::string& text, int members = 1) {
  std::ofstream(path, std::ios::binary).close();
  const std::size_t part = text.size() / static_cast<std::size_t>(members) + 1;
  for (int m = 0; m < members; ++m) {
    gzFile gz = gzopen(path.c_str(), "ab");
    ASSERT_NE(gz, nullptr);
    const std::size_t first = std::min(text.size(), part * static_cast<std::size_t>(m));
    const std::size_t n = std::min(part, text.size() - first);
    ASSERT_EQ(gzwrite(gz, text.data() + first, static_cast<unsigned>(n)), static_cast<int>(n));
    ASSERT_EQ(gzclose(gz), Z_OK);
  }
}
std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
}  // namespace

TEST(Compressed, GzippedSetsAndColumnFilesReadAsTheirText) {
  // Analysts gzip long runs; each file of the set may be PREFIX.ext.gz. Truth: the plain set.
  const fs::path dir = fs::temp_directory_path() / ("mlce_gz_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string prefix = (dir / "run").string();
  write_gzip(prefix + ".mov.gz", file_text(kIso + ".mov"), 3);  // three members, as cat joins them
  for (const char* ext : {".jnt", ".ine", ".out"}) write_gzip(prefix + ext + ".gz", file_text(kIso + ext));
  fs::copy_file(kIso + ".log", prefix + ".log");  // a mixed set: the .log left plain
  const auto spec = specs({"node:2:x", "rel:13:4:z", "joint:33:14", "ine:11:2"});
  const auto plain = read_mbdyn_text(kIso, spec);
  ASSERT_EQ(plain.time.size(), 201u);
  for (const std::string& name : {prefix, prefix + ".mov.gz", prefix + ".out"}) {
    const auto& reader = default_registry().for_path(name);
    EXPECT_EQ(reader.name(), "mbdyn-text") << name;
    const auto gz = reader.read(name, spec, {});
    EXPECT_EQ(gz.time, plain.time) << name;
    EXPECT_EQ(gz.values, plain.values) << name;
  }
  EXPECT_EQ(mbdyn_prefix(prefix + ".mov.gz"), prefix);
  EXPECT_EQ(mbdyn_prefix(prefix + ".csv.gz"), prefix + ".csv.gz");
  const auto inv = default_registry().for_path(prefix).describe(prefix);
  EXPECT_EQ(inv.blocks, 201u);
  EXPECT_EQ(inv.nodes.size(), 7u);
  EXPECT_EQ(inv.entities.size(), 15u);  // 9 joints' and 6 dynamic nodes' momentum rows
  EXPECT_EQ(inv.nodes[3].kind, "dynamic");  // known from the .ine.gz

  // A column file, named .csv.gz or with no telling name at all: the magic bytes decide.
  std::string csv = "time,x\n";
  for (int i = 0; i < 5000; ++i) csv += std::to_string(0.01 * i) + "," + std::to_string(std::sin(0.37 * i)) + "\n";
  std::ofstream(dir / "series.csv") << csv;
  write_gzip(dir / "series.csv.gz", csv);
  write_gzip(dir / "series", csv);
  const Table t = read_column_file((dir / "series.csv").string());
  for (const char* name : {"series.csv.gz", "series"}) {
    const Table g = read_column_file((dir / name).string());
    EXPECT_EQ(g.names, t.names) << name;
    EXPECT_EQ(g.columns, t.columns) << name;
  }

  // A copy cut short and a flipped byte are one error naming the file, not a partial read.
  const std::string csv_gz = file_text((dir / "series.csv.gz").string()), jnt_gz = file_text(prefix + ".jnt.gz");
  std::ofstream(dir / "cut.csv.gz", std::ios::binary) << csv_gz.substr(0, csv_gz.size() / 2);
  std::string flipped = csv_gz;
  flipped[flipped.size() / 2] = static_cast<char>(flipped[flipped.size() / 2] ^ 0x55);
  std::ofstream(dir / "flipped.csv.gz", std::ios::binary) << flipped;
  const std::string cut = read_error_of([&] { read_column_file((dir / "cut.csv.gz").string()); });
  EXPECT_EQ(cut.rfind((dir / "cut.csv.gz").string() + ": the gzip data end early", 0), 0u) << cut;
  const std::string bad = read_error_of([&] { read_column_file((dir / "flipped.csv.gz").string()); });
  EXPECT_EQ(bad.rfind((dir / "flipped.csv.gz").string() + ": corrupt gzip data (zlib: ", 0), 0u) << bad;
  std::ofstream(prefix + ".jnt.gz", std::ios::binary) << jnt_gz.substr(0, jnt_gz.size() / 2);
  const std::string in_set = read_error_of([&] { read_mbdyn_text(prefix, spec); });
  EXPECT_EQ(in_set.rfind(prefix + ".jnt.gz: the gzip data end early", 0), 0u) << in_set;

  // A few kB of gzip that expand to one endless line: an error at the buffer's bound, not all memory.
  write_gzip(dir / "one_line.gz", "1 2\n" + std::string(std::size_t{65} << 20, '7'));
  EXPECT_EQ(read_error_of([&] { read_column_file((dir / "one_line.gz").string()); }),
            (dir / "one_line.gz").string() + ":2: a line longer than 64 MiB: not a text file of rows of numbers");

  // NetCDF is read by the netCDF library, from an uncompressed file only: said, not misread.
  write_gzip(dir / "run.nc.gz", file_text(kIso + ".nc"));
  const std::string nc = read_error_of([&] { default_registry().for_path((dir / "run.nc.gz").string()).describe((dir / "run.nc.gz").string()); });
  EXPECT_NE(nc.find("a gzip-compressed NetCDF file cannot be read in place: 'gunzip -k"), std::string::npos) << nc;
  fs::remove_all(dir);
}

TEST(MbdynText, ModalJointsModesAndExternalElementsRowsAreAddressedAsTheFileWritesThem) {
  // A flexible body's modal joint writes .mod rows "label.mode q qdot qddot" (format doc section
  // 5); external elements' .frc rows start "elem@node" or "elem#node" (section 6). Truth: the
  // values the test wrote.
  const fs::path dir = fs::temp_directory_path() / ("mlce_mod_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string prefix = (dir / "flex").string();
  std::ofstream log(prefix + ".log"), out(prefix + ".out"), mod(prefix + ".mod"), frc(prefix + ".frc");
  log << "output frequency: 1\nstructural node: 1 0 0 0 euler123 0 0 0\n";
  out << "# Step Time TStep NIter ResErr SolErr SolConv Out\n";
  auto q = [](long joint, int mode, int k) { return 1000.0 * static_cast<double>(joint) + 10.0 * mode + 0.5 * k; };
  for (int k = 0; k < 50; ++k) {
    out << "Step " << k << " " << 0.01 * k << " 0.01 1 0 0 0 1\n";
    for (long joint : {12L, 3L})
      for (int mode = 1; mode <= 3; ++mode)
        mod << "    " << joint << "." << mode << " " << q(joint, mode, k) << " " << -q(joint, mode, k) << " 0\n";
    frc << "5@2 " << 2.0 * k << " 0 0\n5#7 " << 3.0 * k << " 0 0\n9 " << 4.0 * k << " 1 1 1\n";
  }
  log.close(), out.close(), mod.close(), frc.close();
  const auto set = read_mbdyn_text(prefix, specs({"mod:12.3:2", "mod:3.1:3", "frc:5@2:2", "frc:5#7:2", "frc:9:2"}));
  ASSERT_EQ(set.time.size(), 50u);
  for (std::size_t k = 0; k < 50; ++k) {
    const int i = static_cast<int>(k);
    EXPECT_EQ(set.values[0][k], q(12, 3, i));
    EXPECT_EQ(set.values[1][k], -q(3, 1, i));
    EXPECT_EQ(set.values[2][k], 2.0 * i);
    EXPECT_EQ(set.values[3][k], 3.0 * i);
    EXPECT_EQ(set.values[4][k], 4.0 * i);
  }
  // Listed as the spec takes them, the .mod file's name leads to the set too.
  const auto inv = default_registry().for_path(prefix + ".mod").describe(prefix + ".mod");
  std::vector<std::string> listed;
  for (const auto& e : inv.entities) listed.push_back(e.file + ":" + row_label_text(e.label));
  EXPECT_EQ(listed, (std::vector<std::string>{"frc:5@2", "frc:5#7", "frc:9", "mod:12.1", "mod:12.2", "mod:12.3", "mod:3.1",
                                              "mod:3.2", "mod:3.3"}));
  EXPECT_EQ(read_error_of([&] { read_mbdyn_text(prefix, specs({"mod:12.4:2"})); }),
            prefix + ".mod: no rows of label 12.4 (labels in a block: 12.1 12.2 12.3 3.1 3.2 3.3)");
  // Structural nodes keep integer labels: a .mov written so is malformed, and said to be.
  {
    std::ofstream mov(prefix + ".mov");
    for (int k = 0; k < 50; ++k) mov << "1.5 0 0 0 0 0 0 0 0 0 0 0 0\n";
  }
  EXPECT_EQ(read_error_of([&] { default_registry().for_path(prefix).describe(prefix); }),
            prefix + ".mov: row label 1.5: structural nodes have integer labels");
  fs::remove_all(dir);
}

TEST(ChannelSpec, RowLabelsWithASubIndexRoundTripAndMalformedOnesAreRefused) {
  for (const char* text : {"0", "7", "12.3", "5@2", "5#2", "1099511627775.1048575", "2147483647@0"}) {
    const auto key = parse_row_label(text);
    ASSERT_TRUE(key) << text;
    EXPECT_EQ(row_label_text(*key), text);
  }
  EXPECT_NE(*parse_row_label("12.3"), *parse_row_label("12@3"));
  EXPECT_NE(*parse_row_label("12.3"), *parse_row_label("12.4"));
  for (const char* text : {"", "-1", "12.", ".3", "12.3.4", "12.-3", "1@2#3", "12,3", "1099511627776.1", "1.1048576", "x.1"})
    EXPECT_FALSE(parse_row_label(text)) << text;
  EXPECT_EQ(parse_channel_spec("mod:12.3:2").label, *parse_row_label("12.3"));
  EXPECT_THROW(parse_channel_spec("joint:-5:2"), ReadError);
  EXPECT_THROW(parse_channel_spec("mod:12.:2"), ReadError);
}

TEST(ChannelSpec, ParsesEveryKindAndRejectsMalformedSpecs) {
  EXPECT_EQ(parse_channel_spec("node:12:wz").kind, ChannelSpec::Kind::node);
  const auto j = parse_channel_spec("joint:33:14");
  EXPECT_EQ(j.extension, "jnt");
  EXPECT_EQ(j.column, 14u);
  const auto r = parse_channel_spec("rel:13:4:z");
  EXPECT_EQ(r.label, 13);
  EXPECT_EQ(r.reference, 4);
  EXPECT_EQ(r.axis, 2);
  EXPECT_EQ(parse_channel_spec("ine:11:2").extension, "ine");
  EXPECT_EQ(parse_channel_spec("col:3").column, 3u);
  for (const char* bad : {"", "node:2", "node:x:x", "node:2:q", "rel:1:2:w", "joint:3:1", "joint:3:k", "col:0", "mov:1:2",
                          "Node:1:2"})
    EXPECT_THROW(parse_channel_spec(bad), ReadError) << bad;
}

namespace {
/// A .out as MBDyn prints it by default: times and time steps in %g (6 significant digits).
/// Step k of `steps` advances by h[k]; every `every`-th step is written (Out = 1).
/// `digits` significant digits instead of 6 is what 'output precision' sets.
std::string coarse_out(double t0, const std::vector<double>& h, std::size_t every, int digits = 6) {
  std::string text = "# Step Time TStep NIter ResErr SolErr SolConv Out\n";
  char line[128];
  std::snprintf(line, sizeof line, "Step 0 %.*g 0 1 0 0 0 1\n", digits, t0);
  text += line;
  long double t = t0;
  for (std::size_t k = 1; k <= h.size(); ++k) {
    t += h[k - 1];
    std::snprintf(line, sizeof line, "Step %zu %.*g %.*g 2 1e-08 0 0 %d\n", k, digits, static_cast<double>(t), digits,
                  h[k - 1], k % every == 0 ? 1 : 0);
    text += line;
  }
  return text;
}
}  // namespace

TEST(MbdynOut, TimesPrintedTooCoarselyForTheStepAreRebuiltFromStepsAndTimeSteps) {
  // Default printing at late times: t = 1000.005 prints '1000.01' like 1000.010 (format doc
  // section 2); blocks would repeat a time. Rebuilt: exactly 1000 + 0.005 k.
  const auto late = parse_mbdyn_out(coarse_out(1000.0, std::vector<double>(4000, 0.005), 1), "late.out");
  ASSERT_EQ(late.time.size(), 4001u);
  EXPECT_NEAR(late.time[1], 1000.005, 1e-12);  // printed '1000', like block 0
  for (std::size_t k = 0; k < late.time.size(); ++k) ASSERT_NEAR(late.time[k], 1000.0 + 0.005 * k, 1e-9) << k;
  EXPECT_NE(late.rebuilt.find("late.out: times printed with 6 significant digits, too few"), std::string::npos)
      << late.rebuilt;

  // 'output precision: 4': 100.025 prints '100', 100.05 '100.1'; the digits come from the file.
  const auto four = parse_mbdyn_out(coarse_out(100.0, std::vector<double>(400, 0.025), 1, 4), "four.out");
  for (std::size_t k = 0; k < four.time.size(); ++k) ASSERT_NEAR(four.time[k], 100.0 + 0.025 * k, 1e-9) << k;
  EXPECT_NE(four.rebuilt.find("printed with 4 significant digits"), std::string::npos) << four.rebuilt;

  // A step the 6 digits round unevenly (100.0025 -> '100.003', 100.005, 100.008): the printed steps
  // deviate by 20 %; written every 2nd step of 1.25 ms.
  const auto uneven = parse_mbdyn_out(coarse_out(100.0, std::vector<double>(800, 0.00125), 2), "uneven.out");
  ASSERT_EQ(uneven.time.size(), 401u);
  for (std::size_t k = 0; k < uneven.time.size(); ++k) ASSERT_NEAR(uneven.time[k], 100.0 + 0.0025 * k, 1e-9) << k;
  EXPECT_FALSE(uneven.rebuilt.empty());

  // The step changes mid-run (a step reduction), output every 4th step: rebuilt through the
  // unwritten steps.
  std::vector<double> h(400, 0.001);
  h.insert(h.end(), 400, 0.0005);
  const auto varied = parse_mbdyn_out(coarse_out(2000.0, h, 4), "varied.out");
  ASSERT_EQ(varied.time.size(), 201u);
  EXPECT_NEAR(varied.time[100], 2000.4, 1e-9);
  EXPECT_NEAR(varied.time[200], 2000.6, 1e-9);
  EXPECT_NEAR(varied.time[150], 2000.5, 1e-9);

  // Printed at full precision (the bundled real runs): kept as printed, nothing said.
  const auto fine = parse_mbdyn_out("Step 0 1000 0 1 0 0 0 1\nStep 1 1000.005 0.005 1 0 0 0 1\n"
                                    "Step 2 1000.01 0.005 1 0 0 0 1\n", "fine.out");
  EXPECT_TRUE(fine.rebuilt.empty());
  EXPECT_EQ(fine.time[1], 1000.005);

  // Printed times the time steps cannot explain (TStep 0.004 against steps of 0.005): left as
  // printed, so that the series check reports them, never silently replaced.
  std::string wrong = coarse_out(1000.0, std::vector<double>(50, 0.005), 1);
  for (std::size_t p = 0; (p = wrong.find(" 0.005 2 ", p)) != std::string::npos;) wrong.replace(p, 9, " 0.004 2 ");
  const auto kept = parse_mbdyn_out(wrong, "wrong.out");
  EXPECT_TRUE(kept.rebuilt.empty());
  EXPECT_EQ(kept.time[1], 1000.0);
}

TEST(MbdynOut, SevenFieldStepLinesUseTheOutputFrequency) {
  const auto t = parse_mbdyn_out("Step 0 0 0 1 0 0 0\nStep 1 0.1 0.1 1 0 0 0\nStep 2 0.2 0.1 1 0 0 0\n", "x.out", 2);
  ASSERT_EQ(t.time.size(), 2u);
  EXPECT_DOUBLE_EQ(t.time[1], 0.2);
  EXPECT_THROW(parse_mbdyn_out("Step 0 0 0 1 0 0 0\n", "x.out", 0), ReadError);
}

// A range FIRST..LAST in a spec's number is one channel per integer, the first range outermost; what is
// no such range (a sub-index, a field name) stays as written; a reversed, negative or too large range is
// one error naming the spec.
TEST(ChannelRanges, ExpandToOneSpecPerInteger) {
  using mlce::reader::expand_channel_ranges;
  using V = std::vector<std::string>;
  EXPECT_EQ(expand_channel_ranges("rel:11..14:4:z"), (V{"rel:11:4:z", "rel:12:4:z", "rel:13:4:z", "rel:14:4:z"}));
  EXPECT_EQ(expand_channel_ranges("node:2:x"), (V{"node:2:x"}));
  EXPECT_EQ(expand_channel_ranges("col:3..3"), (V{"col:3"}));
  EXPECT_EQ(expand_channel_ranges("joint:1..2:2..3"), (V{"joint:1:2", "joint:1:3", "joint:2:2", "joint:2:3"}));
  EXPECT_EQ(expand_channel_ranges("mod:12.3:2"), (V{"mod:12.3:2"}));      // a sub-index, no range
  EXPECT_EQ(expand_channel_ranges("node:2:x..z"), (V{"node:2:x..z"}));    // no integers: left to the parser
  EXPECT_THROW(parse_channel_spec("node:2:x..z"), ReadError);
  EXPECT_EQ(expand_channel_ranges("var:elem.beam.100.F_I:1..3").size(), 3U);
  for (const auto& spec : expand_channel_ranges("rel:11..14:4:z")) EXPECT_NO_THROW(parse_channel_spec(spec)) << spec;
  const auto error = [](const char* spec) {
    try {
      expand_channel_ranges(spec);
    } catch (const ReadError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error("rel:14..11:4:z"), "channel 'rel:14..11:4:z': range 14..11: expected FIRST <= LAST");
  EXPECT_EQ(error("node:-1..3:x"), "channel 'node:-1..3:x': range -1..3: expected non-negative bounds below 2^40");
  EXPECT_EQ(error("node:0..99999:y"), "channel 'node:0..99999:y': expected at most 10000 channels from one spec");
  EXPECT_EQ(error("joint:1..200:1..100"), "channel 'joint:1..200:1..100': expected at most 10000 channels from one spec");
  // A bound beyond long is no range: left as written, and the parser names the spec.
  EXPECT_EQ(expand_channel_ranges("node:0..99999999999999999999:y"), (V{"node:0..99999999999999999999:y"}));
  EXPECT_THROW(parse_channel_spec("node:0..99999999999999999999:y"), ReadError);
}
