#pragma once
// Fields of MBDyn's text output lines (the .out, .log, entity files and the .out's eigenvalue tables):
// whitespace-separated tokens and the numbers iostream prints, shared by mbdyn_text.cpp and
// mbdyn_eigenanalysis.cpp.
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace mlce::reader::detail {

inline bool is_blank(char c) { return c == ' ' || c == '\t'; }

/// Next whitespace-separated token of `s` from `pos` (empty at the end).
inline std::string_view next_token(std::string_view s, std::size_t& pos) {
  while (pos < s.size() && is_blank(s[pos])) ++pos;
  const std::size_t start = pos;
  while (pos < s.size() && !is_blank(s[pos])) ++pos;
  return s.substr(start, pos - start);
}

inline std::vector<std::string_view> tokens(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t pos = 0;
  for (auto t = next_token(s, pos); !t.empty(); t = next_token(s, pos)) out.push_back(t);
  return out;
}

inline bool parse_long(std::string_view t, long& v) {
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  return ec == std::errc() && p == t.data() + t.size();
}

/// strtod-compatible numbers (MBDyn writes `-0.000000e+00`, `inf`, `nan`, `-nan`). A number beyond the
/// double range reads as strtod reads it (+-inf, or 0 / a subnormal below it): from_chars leaves `v`
/// as it was there.
inline bool parse_double(std::string_view t, double& v) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  if (t == "-nan" || t == "nan") {
    v = std::nan("");
    return true;
  }
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (p != t.data() + t.size()) return false;
  if (ec == std::errc::result_out_of_range) v = std::strtod(std::string(t).c_str(), nullptr);
  return ec == std::errc() || ec == std::errc::result_out_of_range;
}

}  // namespace mlce::reader::detail
