#pragma once
// Plain values to bytes and back, for a result handed from a child process to its parent
// (isolated_run.hpp): same machine, same build, so numbers travel in their native representation
// (doubles bit for bit, nan and inf included). The reader checks every length against the bytes
// left and throws std::runtime_error rather than read past them.
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace mlce::reader::detail {

class ByteWriter {
 public:
  void u64(std::uint64_t v) { raw(&v, sizeof v); }
  void i64(std::int64_t v) { raw(&v, sizeof v); }
  void f64(double v) { raw(&v, sizeof v); }
  void str(std::string_view s) {
    u64(s.size());
    bytes_.append(s);
  }
  void doubles(const std::vector<double>& v) {
    u64(v.size());
    raw(v.data(), v.size() * sizeof(double));
  }
  void strings(const std::vector<std::string>& v) {
    u64(v.size());
    for (const auto& s : v) str(s);
  }
  std::string take() { return std::move(bytes_); }

 private:
  void raw(const void* p, std::size_t n) { bytes_.append(static_cast<const char*>(p), n); }
  std::string bytes_;
};

class ByteReader {
 public:
  explicit ByteReader(std::string_view bytes) : bytes_(bytes) {}  ///< reads them in place: they must outlive it
  explicit ByteReader(std::string&&) = delete;                     // a temporary would leave it dangling
  std::uint64_t u64() {
    std::uint64_t v = 0;
    raw(&v, sizeof v);
    return v;
  }
  std::int64_t i64() {
    std::int64_t v = 0;
    raw(&v, sizeof v);
    return v;
  }
  double f64() {
    double v = 0.0;
    raw(&v, sizeof v);
    return v;
  }
  std::string str() {
    const std::size_t n = count(1);
    std::string s(bytes_.substr(at_, n));
    at_ += n;
    return s;
  }
  std::vector<double> doubles() {
    std::vector<double> v(count(sizeof(double)));
    raw(v.data(), v.size() * sizeof(double));
    return v;
  }
  std::vector<std::string> strings() {
    std::vector<std::string> v(count(sizeof(std::uint64_t)));  // each string carries at least its length
    for (auto& s : v) s = str();
    return v;
  }
  /// A count of items of at least `item_bytes` each, checked against the bytes left.
  std::size_t count(std::size_t item_bytes) {
    const std::uint64_t n = u64();
    if (n > (bytes_.size() - at_) / item_bytes) throw std::runtime_error("a count beyond the bytes left");
    return static_cast<std::size_t>(n);
  }
  void expect_end() const {
    if (at_ != bytes_.size()) throw std::runtime_error("bytes left over");
  }

 private:
  void raw(void* p, std::size_t n) {
    if (n > bytes_.size() - at_) throw std::runtime_error("the bytes end early");
    if (n > 0) std::memcpy(p, bytes_.data() + at_, n);
    at_ += n;
  }
  std::string_view bytes_;
  std::size_t at_ = 0;
};

}  // namespace mlce::reader::detail
