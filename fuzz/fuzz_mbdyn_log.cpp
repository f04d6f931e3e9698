// libFuzzer: the .log parser must return or throw ReadError on any bytes, never crash or hang.
#include <cstdint>
#include <string_view>

#include "mlce/reader/mbdyn_text.hpp"
#include "mlce/reader/table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)mlce::reader::parse_mbdyn_log(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.log");
  } catch (const mlce::reader::ReadError&) {
  }
  return 0;
}
