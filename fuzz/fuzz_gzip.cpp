// libFuzzer: the readers' file path (LineSource::open) on arbitrary bytes written to a file. From
// a gzip seed (fuzz/run.sh) the mutations are corrupt, cut short, multi-member and bomb-like
// deflate streams: each must read as its text or end in one ReadError, never a crash, a leak or
// memory without bound (a line is capped at LineSource::kLongestLine).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "mlce/reader/column_file.hpp"
#include "mlce/reader/mbdyn_text.hpp"
#include "mlce/reader/table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const struct Scratch {
    std::string path = "/tmp/mlce_fuzz_" + std::to_string(::getpid()) + ".gz";
    ~Scratch() { std::remove(path.c_str()); }
  } scratch;
  const std::string& path = scratch.path;
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  } else {
    return 0;
  }
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
