// libFuzzer: channel-spec parsing (node:L:F, joint:L:K, rel:A:B:AXIS, EXT:L:K, col:K).
#include <cstdint>
#include <string_view>

#include "mlce/reader/channel_spec.hpp"
#include "mlce/reader/table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)mlce::reader::parse_channel_spec(std::string_view(reinterpret_cast<const char*>(data), size));
  } catch (const mlce::reader::ReadError&) {
  }
  return 0;
}
