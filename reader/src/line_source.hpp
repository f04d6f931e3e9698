#pragma once
// Streams the lines of a file in one pass with a fixed buffer (memory independent of file size).
// A gzip-compressed file (recognised by its magic bytes 1f 8b, whatever its name) is read through
// zlib as its decompressed text: analysts gzip long MBDyn runs, whose text output is ~10x its gzip.
// Lines are views into the buffer, valid until the next call. A final line without '\n' (a run
// killed mid-write) is not returned: partial_tail() reports it, unless keep_unterminated_tail()
// asks for it (a column file saved without a final newline is complete).
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace mlce::reader::detail {

class LineSource {
 public:
  /// Throws ReadError naming the path when it cannot be opened (or its gzip stream is corrupt or
  /// cut short: that is a broken copy, not an interrupted run, so it is not read as far as it goes).
  static LineSource open(const std::string& path);
  /// Reads from memory (tests, fuzzers).
  static LineSource from_memory(std::string_view text, std::string name);

  /// Longest line read from a file (the buffer's bound); a longer one is a ReadError.
  static constexpr std::size_t kLongestLine = std::size_t{64} << 20;

  bool next(std::string_view& line);
  /// Return a final line that has no '\n' as a line (partial_tail() then stays false).
  void keep_unterminated_tail() { keep_tail_ = true; }
  std::size_t line_number() const { return line_no_; }  ///< 1-based number of the last line returned
  bool partial_tail() const { return partial_tail_; }
  /// The line last returned is the final line without '\n' (kept by keep_unterminated_tail()).
  bool line_unterminated() const { return unterminated_; }
  const std::string& name() const { return name_; }
  std::string where() const { return name_ + ":" + std::to_string(line_no_); }

 private:
  LineSource(std::FILE* f, std::string name);
  /// Fills buf_[end_, size) from the file or the gzip stream; 0 at the end.
  std::size_t read_more();
  struct Closer {
    void operator()(std::FILE* f) const { if (f) std::fclose(f); }
  };
  struct GzCloser {
    void operator()(void* gz) const;
  };
  std::unique_ptr<std::FILE, Closer> file_;
  std::unique_ptr<void, GzCloser> gz_;  // a gzFile (zlib.h is kept out of this header)
  std::string_view memory_;
  bool from_memory_ = false;
  std::string name_;
  std::vector<char> buf_;
  std::size_t begin_ = 0, end_ = 0;
  bool eof_ = false;
  bool partial_tail_ = false;
  bool keep_tail_ = false;
  bool unterminated_ = false;
  std::size_t line_no_ = 0;
};

/// Whether a file's first bytes are NetCDF's magic number: classic (CDF 1, 2, 5) or netCDF-4 (HDF5).
bool starts_like_netcdf(std::string_view head);

/// The file a set names as `path`: `path` itself, else `path.gz` when only that is there (a set
/// whose files were gzipped one by one), else `path` (for the caller's "cannot open" message).
std::string stored_file(const std::string& path);
/// `path` without a final ".gz" (what the name says the content is).
std::string without_gz(const std::string& path);

}  // namespace mlce::reader::detail
