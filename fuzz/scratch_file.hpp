#pragma once
// The fuzz input written to a file of this process's own (readers that open paths: libnetcdf,
// the text readers' LineSource), removed when the fuzzer ends. nullptr when it cannot be written.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

inline const std::string* fuzz_input_as_file(const std::uint8_t* data, std::size_t size, const char* suffix) {
  static const struct Scratch {
    std::string path;
    ~Scratch() { std::remove(path.c_str()); }
  } scratch{"/tmp/mlce_fuzz_" + std::to_string(::getpid()) + suffix};
  FILE* f = std::fopen(scratch.path.c_str(), "wb");
  if (!f) return nullptr;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  return &scratch.path;
}
