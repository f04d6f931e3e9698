#pragma once
// One channel-spec syntax for every input format:
//   node:L:F       F = x y z | r1 r2 r3 (r1..r9 for a matrix node) | vx vy vz | wx wy wz
//                  | ax ay az | alphax alphay alphaz   (structural node L, as the file writes it)
//   joint:L:K      K-th column (1-based, as in the .jnt file) of joint L's rows
//   EXT:L:K        K-th column of entity L's rows in any other per-entity file (ine:11:2, frc:7:3);
//                  L may be a row label with a sub-index as the file writes it: mod:12.3:2 (modal
//                  joint 12, mode 3, its q), frc:5@2:3 / frc:5#2:3 (external elements)
//   rel:A:B:AXIS   rotation of node A relative to node B about AXIS (x|y|z of B's frame), rad,
//                  from the initial configuration, unwrapped in time
//   col:K          K-th column of a plain column file
//   var:NAME[:K]   component K (default 1) of the NetCDF time history NAME, e.g.
//                  var:elem.beam.100.F_I:2; a 3x3 matrix's K counts row by row, as text files do
// Any integer field may be a range FIRST..LAST, which stands for one channel per integer
// (expand_channel_ranges; the command line expands every --channel): rel:11..14:4:z, col:2..5.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mlce::reader {

struct ChannelSpec {
  enum class Kind { node, entity, relative, column, variable };
  Kind kind = Kind::column;
  std::string text;       ///< the spec as the user wrote it (used as the channel name)
  std::string extension;  ///< entity: "jnt", "ine", "frc", ...
  long label = 0;         ///< node / entity label (a row label, see parse_row_label); rel: node A
  long reference = 0;     ///< rel: node B
  std::string field;      ///< node: x, r1, vx, ...; variable: the NetCDF variable's name
  int axis = 2;           ///< rel: 0 x, 1 y, 2 z
  std::size_t column = 0; ///< entity / column / variable component: 1-based
};

/// Throws ReadError("channel 'SPEC': expected ...") for a malformed spec.
ChannelSpec parse_channel_spec(std::string_view spec);

/// At most this many channels from one spec with ranges (expand_channel_ranges).
inline constexpr std::size_t kMaxChannelsOfARange = 10000;

/// The specs a spec with ranges stands for, in order: every `:`-separated field after the first of the
/// form FIRST..LAST (non-negative integers, FIRST <= LAST) takes each integer from FIRST to LAST, and
/// several such fields vary as nested loops, the first outermost. `rel:11..14:4:z` is the four blades'
/// lags (rel:11:4:z .. rel:14:4:z), `node:11..14:y` the four hinges' y, `col:2..5` four columns,
/// `joint:33:2..4` three of a joint's columns. A field that is no such range stays as written (12.3,
/// a sub-index; x..z, which parse_channel_spec then names as no node field).
/// A spec without a range is itself. Throws ReadError("channel 'SPEC': ...") for a reversed range, a
/// bound beyond a label's range, or more than kMaxChannelsOfARange channels.
std::vector<std::string> expand_channel_ranges(std::string_view spec);

/// The first field of an MBDyn entity row as one `long` key: a plain label (`7`) as itself, and a
/// label with a sub-index (`12.3`: mode 3 of modal joint 12 in .mod; `5@2`, `5#2`: external
/// elements' rows per node in .frc; format doc sections 5-6) as a negative code, which no plain
/// label takes (MBDyn labels are unsigned). Labels up to 2^40, sub-indices up to 2^20 - 1.
std::optional<long> parse_row_label(std::string_view text);
/// The row label as the file writes it: "7", "12.3", "5@2".
std::string row_label_text(long key);

}  // namespace mlce::reader
