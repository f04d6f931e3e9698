#include "mlce/reader/channel_spec.hpp"

#include <charconv>
#include <string>
#include <vector>

#include "mlce/reader/table.hpp"
#include "node_fields.hpp"

namespace mlce::reader {
namespace detail {

std::optional<NodeField> parse_node_field(std::string_view f) {
  auto xyz = [](char c) -> std::optional<std::size_t> {
    if (c == 'x') return 0;
    if (c == 'y') return 1;
    if (c == 'z') return 2;
    return std::nullopt;
  };
  if (f.size() == 1 && xyz(f[0])) return NodeField{NodeGroup::position, *xyz(f[0])};
  if (f.size() == 2 && f[0] == 'r' && f[1] >= '1' && f[1] <= '9')
    return NodeField{NodeGroup::orientation, static_cast<std::size_t>(f[1] - '1')};
  if (f.size() == 2 && xyz(f[1])) {
    if (f[0] == 'v') return NodeField{NodeGroup::velocity, *xyz(f[1])};
    if (f[0] == 'w') return NodeField{NodeGroup::angular_velocity, *xyz(f[1])};
    if (f[0] == 'a') return NodeField{NodeGroup::acceleration, *xyz(f[1])};
  }
  if (f.size() == 6 && f.substr(0, 5) == "alpha" && xyz(f[5])) return NodeField{NodeGroup::angular_acceleration, *xyz(f[5])};
  return std::nullopt;
}

}  // namespace detail

namespace {

std::vector<std::string_view> split(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t pos = 0;
  while (true) {
    const std::size_t c = s.find(':', pos);
    out.push_back(s.substr(pos, c == std::string_view::npos ? std::string_view::npos : c - pos));
    if (c == std::string_view::npos) return out;
    pos = c + 1;
  }
}

template <class T>
bool to_number(std::string_view s, T& v) {
  if (s.empty()) return false;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && p == s.data() + s.size();
}

constexpr char kSeparators[] = {'.', '@', '#'};
constexpr long kSubBits = 20, kKindBits = 2;
/// Labels at most this large fit parse_row_label's code beside a sub-index (MBDyn labels are unsigned).
constexpr long kLabelLimit = 1L << 40;

}  // namespace

std::optional<long> parse_row_label(std::string_view text) {
  long label = 0;
  if (to_number(text, label)) return label >= 0 ? std::optional<long>(label) : std::nullopt;
  const std::size_t at = text.find_first_of(".@#");
  long sub = 0;
  if (at == std::string_view::npos || !to_number(text.substr(0, at), label) || !to_number(text.substr(at + 1), sub) ||
      label < 0 || label >= kLabelLimit || sub < 0 || sub >= (1L << kSubBits))
    return std::nullopt;
  const long kind = text[at] == '.' ? 0 : text[at] == '@' ? 1 : 2;
  return -1 - ((label << (kSubBits + kKindBits)) | (kind << kSubBits) | sub);
}

std::string row_label_text(long key) {
  if (key >= 0) return std::to_string(key);
  const long code = -1 - key;
  return std::to_string(code >> (kSubBits + kKindBits)) + kSeparators[(code >> kSubBits) & 3] +
         std::to_string(code & ((1L << kSubBits) - 1));
}

ChannelSpec parse_channel_spec(std::string_view text) {
  ChannelSpec c;
  c.text = std::string(text);
  const auto fail = [&](const std::string& expected) {
    return ReadError("channel '" + c.text + "': expected " + expected);
  };
  const auto parts = split(text);
  const std::string_view kind = parts[0];
  if (kind == "node") {
    if (parts.size() != 3 || !to_number(parts[1], c.label))
      throw fail("node:LABEL:FIELD (FIELD one of x y z r1..r9 vx vy vz wx wy wz ax ay az alphax alphay alphaz)");
    if (!detail::parse_node_field(parts[2]))
      throw fail("a node field among x y z r1..r9 vx vy vz wx wy wz ax ay az alphax alphay alphaz, not '" +
                 std::string(parts[2]) + "'");
    c.kind = ChannelSpec::Kind::node;
    c.field = std::string(parts[2]);
  } else if (kind == "rel") {
    if (parts.size() != 4 || !to_number(parts[1], c.label) || !to_number(parts[2], c.reference) ||
        parts[3].size() != 1 || parts[3][0] < 'x' || parts[3][0] > 'z')
      throw fail("rel:NODE_A:NODE_B:AXIS with AXIS one of x y z");
    c.kind = ChannelSpec::Kind::relative;
    c.axis = parts[3][0] - 'x';
  } else if (kind == "var") {
    // var:NAME or var:NAME:K; NAME may hold no ':' (MBDyn's never do).
    if (parts.size() < 2 || parts.size() > 3 || parts[1].empty() ||
        (parts.size() == 3 && (!to_number(parts[2], c.column) || c.column == 0)))
      throw fail("var:NAME or var:NAME:K with K >= 1 (a NetCDF variable and its component)");
    c.kind = ChannelSpec::Kind::variable;
    c.field = std::string(parts[1]);
    if (parts.size() == 2) c.column = 1;
  } else if (kind == "col") {
    if (parts.size() != 2 || !to_number(parts[1], c.column) || c.column == 0) throw fail("col:K with K >= 1");
    c.kind = ChannelSpec::Kind::column;
  } else if (!kind.empty() && parts.size() == 3) {
    // joint:L:K or any per-entity file EXT:L:K.
    for (char ch : kind)
      if (!(ch >= 'a' && ch <= 'z')) throw fail("node:, joint:, rel:, col: or EXT:LABEL:COLUMN");
    const auto label = parse_row_label(parts[1]);
    if (!label || !to_number(parts[2], c.column) || c.column < 2)
      throw fail(std::string(kind) + ":LABEL:COLUMN with COLUMN >= 2 (column 1 is the label: 7, or 12.3, 5@2, 5#2 as "
                                     "the file writes it)");
    c.label = *label;
    c.kind = ChannelSpec::Kind::entity;
    c.extension = kind == "joint" ? "jnt" : std::string(kind);
    if (c.extension == "mov") throw fail("node:LABEL:FIELD for .mov rows");
  } else {
    throw fail("node:L:F, joint:L:K, rel:A:B:AXIS, EXT:L:K, var:NAME:K or col:K");
  }
  return c;
}

std::vector<std::string> expand_channel_ranges(std::string_view spec) {
  const auto fail = [&](const std::string& what) { return ReadError("channel '" + std::string(spec) + "': " + what); };
  const auto parts = split(spec);
  struct Range {
    std::size_t field;
    long first, last;
  };
  std::vector<Range> ranges;
  std::size_t count = 1;
  for (std::size_t f = 1; f < parts.size(); ++f) {
    const std::size_t dots = parts[f].find("..");
    long first = 0, last = 0;
    if (dots == std::string_view::npos || !to_number(parts[f].substr(0, dots), first) ||
        !to_number(parts[f].substr(dots + 2), last))
      continue;  // no range: the field as written
    const std::string range = std::string(parts[f]);
    if (first < 0 || last >= kLabelLimit) throw fail("range " + range + ": expected non-negative bounds below 2^40");
    if (first > last) throw fail("range " + range + ": expected FIRST <= LAST");
    const auto size = static_cast<std::size_t>(last - first) + 1;
    if (size > kMaxChannelsOfARange || count * size > kMaxChannelsOfARange)
      throw fail("expected at most " + std::to_string(kMaxChannelsOfARange) + " channels from one spec");
    count *= size;
    ranges.push_back({f, first, last});
  }
  if (ranges.empty()) return {std::string(spec)};
  std::vector<std::string> out;
  out.reserve(count);
  std::vector<long> at(ranges.size());
  for (std::size_t r = 0; r < ranges.size(); ++r) at[r] = ranges[r].first;
  while (true) {
    std::string s(parts[0]);
    for (std::size_t f = 1, r = 0; f < parts.size(); ++f) {
      s += ':';
      if (r < ranges.size() && ranges[r].field == f) s += std::to_string(at[r++]);
      else s += parts[f];
    }
    out.push_back(std::move(s));
    // The last range varies fastest (nested loops, the first outermost).
    std::size_t r = ranges.size();
    while (r > 0 && at[r - 1] == ranges[r - 1].last) at[r - 1] = ranges[r - 1].first, --r;
    if (r == 0) return out;
    ++at[r - 1];
  }
}

}  // namespace mlce::reader
