// libFuzzer: the MBDyn NetCDF reader on arbitrary bytes written to a file (libnetcdf opens paths).
// What it guards: the classic-header walk before nc_open, and the record cap by file size, so
// that no header makes libnetcdf allocate or loop without bound (-rss_limit_mb, -timeout). From a
// netCDF-4 seed (fuzz/run.sh), the child process that reads such a file and the pipe its result
// comes back through: whatever libhdf5 does there (crash, endless loop), this process must get
// the channels or one ReadError. The eigenanalysis variables (eig.*) are read too: their sizes come
// from the header, and a dense matrix or a triplet list must stay within what the file's bytes hold.
#include <cstdint>
#include <string>

#include "mlce/reader/channel_spec.hpp"
#include "mlce/reader/mbdyn_netcdf.hpp"
#include "mlce/reader/table.hpp"
#include "scratch_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string* file = fuzz_input_as_file(data, size, ".nc");
  if (!file) return 0;
  const std::string& path = *file;
  try {
    (void)mlce::reader::describe_mbdyn_netcdf(path);
  } catch (const mlce::reader::ReadError&) {
  }
  try {
    (void)mlce::reader::read_mbdyn_netcdf(path, {mlce::reader::parse_channel_spec("node:1:y")});
  } catch (const mlce::reader::ReadError&) {
  }
  try {
    (void)mlce::reader::read_mbdyn_netcdf_eigenanalyses(path);
  } catch (const mlce::reader::ReadError&) {
  }
  return 0;
}
