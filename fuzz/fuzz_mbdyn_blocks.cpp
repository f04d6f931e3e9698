// libFuzzer: the per-entity block parser (.mov/.jnt/.ine rows) with a few column requests.
#include <cstdint>
#include <string_view>
#include <vector>

#include "mlce/reader/mbdyn_text.hpp"
#include "mlce/reader/table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  using mlce::reader::BlockRequest;
  const std::vector<std::vector<BlockRequest>> requests = {{}, {{2, 2}}, {{2, 2}, {13, 7}, {4, 13}}, {{1, 0}}};
  // Also cut after a few blocks (ReadOptions::until), with block times to name in messages.
  const std::vector<double> times = {0.0, 0.1, 0.2};
  mlce::reader::BlockOptions cut;
  cut.max_blocks = 1 + size % 3;
  cut.times = times;
  for (const auto& r : requests) {
    for (const auto& options : {mlce::reader::BlockOptions{}, cut}) {
      try {
        (void)mlce::reader::parse_mbdyn_blocks(text, "fuzz.mov", r, options);
      } catch (const mlce::reader::ReadError&) {
      }
    }
  }
  return 0;
}
