// Parse throughput of the MBDyn text reader: reads channels from an output set and reports the
// bytes of the entity files scanned per second (one pass, fixed buffer).
//   read_channel PREFIX SPEC [SPEC...]
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <set>

#include "mlce/reader/mbdyn_text.hpp"
#include "mlce/reader/table.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: read_channel PREFIX SPEC [SPEC...]\n");
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
    double bytes = 0;
    for (const auto& e : files) bytes += static_cast<double>(std::filesystem::file_size(std::string(argv[1]) + e));
    const auto t0 = std::chrono::steady_clock::now();
    const ChannelSet cs = read_mbdyn_text(argv[1], specs);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("blocks %zu  bytes %.0f  seconds %.3f  throughput %.0f MB/s\n", cs.time.size(), bytes, s,
                bytes / s / 1e6);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "read_channel: %s\n", e.what());
    return 1;
  }
  return 0;
}
