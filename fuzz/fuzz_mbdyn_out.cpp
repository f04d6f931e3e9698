// libFuzzer: the .out parsers (Step lines, output flags; the eigenvalue tables) on arbitrary bytes.
#include <cstdint>
#include <string_view>

#include "mlce/reader/mbdyn_eigenanalysis.hpp"
#include "mlce/reader/mbdyn_text.hpp"
#include "mlce/reader/table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  for (std::size_t frequency : {0u, 1u, 5u}) {
    try {
      (void)mlce::reader::parse_mbdyn_out(text, "fuzz.out", frequency);
    } catch (const mlce::reader::ReadError&) {
    }
  }
  try {
    (void)mlce::reader::parse_mbdyn_out_eigenanalyses(text, "fuzz.out");
  } catch (const mlce::reader::ReadError&) {
  }
  return 0;
}
