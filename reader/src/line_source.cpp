#include "line_source.hpp"

#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <climits>
#include <cstring>
#include <filesystem>

#include "mlce/reader/table.hpp"

namespace mlce::reader::detail {

void LineSource::GzCloser::operator()(void* gz) const {
  if (gz) gzclose(static_cast<gzFile>(gz));
}

LineSource::LineSource(std::FILE* f, std::string name) : file_(f), name_(std::move(name)) {}

namespace {

/// What a file is when its first bytes say it is not text, as the clause after "NAME: " (empty for
/// text). A binary file read as rows of numbers failed on some line with a column count that meant
/// nothing ("bin.dat:2: 7 column(s), but the header on line 1 names 1").
std::string not_text(std::string_view head, const std::string& name) {
  if (head.starts_with("\xFF\xFE") || head.starts_with("\xFE\xFF"))
    return "UTF-16 text (a spreadsheet's \"Unicode text\"): save it as \"CSV UTF-8\", or convert it: iconv -f UTF-16 -t UTF-8 " +
           name + " > " + std::filesystem::path(name).stem().string() + "-utf8.txt";
  if (starts_like_netcdf(head))
    return "NetCDF (or HDF5) data where text was expected: the NetCDF reader takes it as a file of its own "
           "(name the file, not a pipe or a member of a text output set)";
  if (head.starts_with("MATLAB 5.0 MAT-file") || head.starts_with("MATLAB 7.3 MAT-file"))
    return "a MATLAB MAT-file (binary): write the series as text, e.g. writematrix([t x], 'series.csv')";
  if (const auto nul = head.find('\0'); nul != std::string_view::npos)
    return "binary data, not text (a zero byte at offset " + std::to_string(nul) +
           "; UTF-16 text without a byte-order mark looks so too)";
  return "";
}

}  // namespace

LineSource LineSource::open(const std::string& path) {
  // "-" is the standard input (a pipe: `cat series.txt | mlce estimate -`), read through a
  // descriptor of its own so that closing it leaves stdin open.
  const bool standard_input = path == "-";
  const int fd = standard_input ? ::dup(STDIN_FILENO) : -1;
  std::FILE* f = standard_input ? (fd >= 0 ? ::fdopen(fd, "rb") : nullptr) : std::fopen(path.c_str(), "rb");
  if (!f) {
    if (fd >= 0) ::close(fd);
    throw ReadError(path + ": cannot open the file (missing or unreadable)");
  }
  LineSource s(f, standard_input ? "stdin" : path);
  s.buf_.resize(std::size_t{1} << 20);
  // The first chunk decides: gzip's magic bytes (RFC 1952) switch to zlib, which reopens the file;
  // otherwise the chunk is the text's start (no seek: a pipe reads as a file does).
  s.end_ = s.read_more();
  if (s.end_ >= 2 && static_cast<unsigned char>(s.buf_[0]) == 0x1f && static_cast<unsigned char>(s.buf_[1]) == 0x8b) {
    std::error_code ec;
    if (standard_input || !std::filesystem::is_regular_file(path, ec))
      throw ReadError(s.name_ + ": gzip-compressed data from a pipe: decompress it into the pipe instead "
                                "('zcat FILE.gz | mlce ...') or name the .gz file");
    s.file_.reset();
    s.gz_.reset(gzopen(path.c_str(), "rb"));
    if (!s.gz_) throw ReadError(path + ": cannot open the gzip-compressed file");
    s.eof_ = false;
    s.end_ = 0;
    s.end_ = s.read_more();
  }
  if (const std::string what = not_text(std::string_view(s.buf_.data(), s.end_), s.name_); !what.empty())
    throw ReadError(s.name_ + ": " + what);
  return s;
}

std::size_t LineSource::read_more() {
  char* at = buf_.data() + end_;
  const std::size_t room = buf_.size() - end_;
  if (!gz_) {
    const std::size_t got = std::fread(at, 1, room, file_.get());
    if (got == 0) {
      if (std::ferror(file_.get())) throw ReadError(name_ + ": read error");
      eof_ = true;
    }
    return got;
  }
  const auto gz = static_cast<gzFile>(gz_.get());
  const int got = gzread(gz, at, static_cast<unsigned>(std::min<std::size_t>(room, INT_MAX)));
  int code = Z_OK;
  const char* message = gzerror(gz, &code);
  if (got < 0 || (code != Z_OK && code != Z_BUF_ERROR)) {
    std::string why = message ? message : "unknown error";
    if (why.starts_with(name_ + ": ")) why.erase(0, name_.size() + 2);  // zlib names the file too
    throw ReadError(name_ + ": corrupt gzip data (zlib: " + why + "); 'gzip -t " + name_ + "' checks the file");
  }
  if (got == 0) {
    // Z_BUF_ERROR at the end: the input stopped inside a gzip stream (zlib.h, gzread).
    if (code == Z_BUF_ERROR)
      throw ReadError(name_ + ": the gzip data end early (the file was cut short in copying?); 'gzip -t " + name_ +
                      "' checks the file");
    eof_ = true;
  }
  return static_cast<std::size_t>(got);
}

LineSource LineSource::from_memory(std::string_view text, std::string name) {
  LineSource s(nullptr, std::move(name));
  s.from_memory_ = true;
  s.memory_ = text;
  return s;
}

bool LineSource::next(std::string_view& line) {
  if (from_memory_) {
    if (begin_ >= memory_.size()) return false;
    const std::size_t nl = memory_.find('\n', begin_);
    if (nl == std::string_view::npos) {
      const std::size_t first = begin_;
      begin_ = memory_.size();
      if (!keep_tail_) {
        partial_tail_ = true;
        return false;
      }
      line = memory_.substr(first);
      unterminated_ = true;
    } else {
      line = memory_.substr(begin_, nl - begin_);
      begin_ = nl + 1;
    }
  } else {
    while (true) {
      const char* p = begin_ < end_ ? static_cast<const char*>(std::memchr(buf_.data() + begin_, '\n', end_ - begin_))
                                    : nullptr;
      if (p) {
        const std::size_t nl = static_cast<std::size_t>(p - buf_.data());
        line = std::string_view(buf_.data() + begin_, nl - begin_);
        begin_ = nl + 1;
        break;
      }
      if (eof_) {
        if (end_ == begin_) return false;
        const std::size_t first = begin_;
        begin_ = end_;
        if (!keep_tail_) {
          partial_tail_ = true;
          return false;
        }
        line = std::string_view(buf_.data() + first, end_ - first);
        unterminated_ = true;
        break;
      }
      // Keep the unfinished line, grow the buffer only for a line longer than it.
      const std::size_t rest = end_ - begin_;
      if (rest > 0 && begin_ > 0) std::memmove(buf_.data(), buf_.data() + begin_, rest);
      begin_ = 0;
      end_ = rest;
      if (end_ == buf_.size()) {
        // A line this long is no table of numbers (nor MBDyn output), and a few kB of gzip can
        // expand to gigabytes of one line: refuse it rather than grow without bound.
        if (buf_.size() >= kLongestLine)
          throw ReadError(name_ + ":" + std::to_string(line_no_ + 1) + ": a line longer than " +
                          std::to_string(kLongestLine >> 20) + " MiB: not a text file of rows of numbers");
        buf_.resize(buf_.size() * 2);
      }
      end_ += read_more();
    }
  }
  // A UTF-8 byte-order mark (files saved by Windows editors) is not part of the first line.
  if (line_no_ == 0 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);
  ++line_no_;
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);  // CRLF from Windows builds
  return true;
}

bool starts_like_netcdf(std::string_view head) {
  return head.starts_with("CDF\x01") || head.starts_with("CDF\x02") || head.starts_with("CDF\x05") ||
         head.starts_with(std::string_view("\x89HDF\r\n\x1A\n", 8));
}

std::string stored_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::exists(path, ec)) return path;
  const std::string gz = path + ".gz";
  return std::filesystem::is_regular_file(gz, ec) ? gz : path;
}

std::string without_gz(const std::string& path) {
  return path.size() > 3 && path.compare(path.size() - 3, 3, ".gz") == 0 ? path.substr(0, path.size() - 3) : path;
}

}  // namespace mlce::reader::detail
