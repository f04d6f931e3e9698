#include "line_source.hpp"

#include <cstring>

#include "mlce/reader/table.hpp"

namespace mlce::reader::detail {

LineSource::LineSource(std::FILE* f, std::string name) : file_(f), name_(std::move(name)) {}

LineSource LineSource::open(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw ReadError(path + ": cannot open the file (missing or unreadable)");
  LineSource s(f, path);
  s.buf_.resize(std::size_t{1} << 20);
  return s;
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
        break;
      }
      // Keep the unfinished line, grow the buffer only for a line longer than it.
      const std::size_t rest = end_ - begin_;
      if (rest > 0 && begin_ > 0) std::memmove(buf_.data(), buf_.data() + begin_, rest);
      begin_ = 0;
      end_ = rest;
      if (end_ == buf_.size()) buf_.resize(buf_.size() * 2);
      const std::size_t got = std::fread(buf_.data() + end_, 1, buf_.size() - end_, file_.get());
      if (got == 0) {
        if (std::ferror(file_.get())) throw ReadError(name_ + ": read error");
        eof_ = true;
      }
      end_ += got;
    }
  }
  // A UTF-8 byte-order mark (files saved by Windows editors) is not part of the first line.
  if (line_no_ == 0 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);
  ++line_no_;
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);  // CRLF from Windows builds
  return true;
}

}  // namespace mlce::reader::detail
