// Parse throughput of the readers: reads channels from an MBDyn text output set (PREFIX) or from
// one file (a column file, a NetCDF file: the format the registry picks for it) and reports the
// bytes scanned per second (one pass, fixed buffer; for gzipped files, compressed bytes).
//   read_channel PREFIX|FILE SPEC [SPEC...]
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <set>

#include "mlce/reader/format.hpp"
#include "mlce/reader/mbdyn_text.hpp"
#include "mlce/reader/table.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: read_channel PREFIX|FILE SPEC [SPEC...]\n");
    return 2;
  }
  using namespace mlce::reader;
  try {
    std::vector<ChannelSpec> specs;
    std::set<std::string> files = {".out"};
    for (int k = 2; k < argc; ++k) {
      specs.push_back(parse_channel_spec(argv[k]));
      files.insert(specs.back().kind == ChannelSpec::Kind::entity ? "." + specs.back().extension : ".mov");
    }
    const std::string path = argv[1];
    const bool one_file = std::filesystem::is_regular_file(path);
    // Bytes as stored: a set gzipped file by file (PREFIX.ext.gz) counts its compressed bytes.
    auto stored = [](const std::string& p) { return std::filesystem::exists(p) ? p : p + ".gz"; };
    double bytes = 0;
    if (one_file) bytes = static_cast<double>(std::filesystem::file_size(path));
    else
      for (const auto& e : files) bytes += static_cast<double>(std::filesystem::file_size(stored(path + e)));
    const auto t0 = std::chrono::steady_clock::now();
    const ChannelSet cs = one_file ? default_registry().for_path(path).read(path, specs, {}) : read_mbdyn_text(path, specs);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::size_t rows = cs.values.empty() ? cs.time.size() : cs.values.front().size();
    std::printf("blocks %zu  bytes %.0f  seconds %.3f  throughput %.0f MB/s\n", rows, bytes, s, bytes / s / 1e6);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "read_channel: %s\n", e.what());
    return 1;
  }
  return 0;
}
