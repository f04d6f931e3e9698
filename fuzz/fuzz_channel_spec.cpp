// libFuzzer: channel-spec parsing (node:L:F, joint:L:K, rel:A:B:AXIS, EXT:L:K, col:K) and range expansion.
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "mlce/reader/channel_spec.hpp"
#include "mlce/reader/table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view spec(reinterpret_cast<const char*>(data), size);
  try {
    (void)mlce::reader::parse_channel_spec(spec);
  } catch (const mlce::reader::ReadError&) {
  }
  // Ranges (rel:11..14:4:z): at most kMaxChannelsOfARange specs, each parsed or refused by one error.
  try {
    const auto specs = mlce::reader::expand_channel_ranges(spec);
    if (specs.empty() || specs.size() > mlce::reader::kMaxChannelsOfARange) std::abort();
    for (const auto& one : specs) {
      try {
        (void)mlce::reader::parse_channel_spec(one);
      } catch (const mlce::reader::ReadError&) {
      }
    }
  } catch (const mlce::reader::ReadError&) {
  }
  return 0;
}
