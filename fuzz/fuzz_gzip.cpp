// libFuzzer: the readers' file path (LineSource::open) on arbitrary bytes written to a file. From
// a gzip seed (fuzz/run.sh) the mutations are corrupt, cut short, multi-member and bomb-like
// deflate streams: each must read as its text or end in one ReadError, never a crash, a leak or
// memory without bound (a line is capped at LineSource::kLongestLine).
#include <cstdint>
#include <string>

#include "mlce/reader/column_file.hpp"
#include "mlce/reader/mbdyn_text.hpp"
#include "mlce/reader/table.hpp"
#include "scratch_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string* file = fuzz_input_as_file(data, size, ".gz");
  if (!file) return 0;
  const std::string& path = *file;
  try {
    (void)mlce::reader::read_column_file(path);
  } catch (const mlce::reader::ReadError&) {
  }
  try {
    (void)mlce::reader::read_mbdyn_blocks(path, {{2, 3}});
  } catch (const mlce::reader::ReadError&) {
  }
  return 0;
}
