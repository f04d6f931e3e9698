// libFuzzer: the eigenanalysis .m parser must return or throw ReadError on any bytes, never crash or
// hang; what it returns is consistent (alpha rows of 3, square matrices of the stated size).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "mlce/reader/mbdyn_eigenanalysis.hpp"
#include "mlce/reader/table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto e = mlce::reader::parse_mbdyn_eigenanalysis(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.m");
    if (e.aplus.size() != e.size * e.size || e.aminus.size() != e.size * e.size || (e.alpha.empty() && e.size == 0) ||
        !e.coefficient || !(*e.coefficient > 0.0)) {
      (void)std::fprintf(stderr, "fuzz_mbdyn_eigenanalysis: an inconsistent result\n");
      std::abort();
    }
  } catch (const mlce::reader::ReadError&) {
  }
  return 0;
}
