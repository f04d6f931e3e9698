#pragma once
// MBDyn text output addressed by its prefix (run/hammond -> .out .log .mov .jnt .ine ...).
// Layouts: ../shared/docs/mbdyn-output-format.md (copied rules are cited by section there).
#include <cstddef>
#include <limits>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "mlce/reader/channel_set.hpp"
#include "mlce/reader/channel_spec.hpp"
#include "mlce/reader/orientation.hpp"

namespace mlce::reader {

/// What the .log says about the model (format doc section 9).
struct MbdynLog {
  struct Node {
    long label = 0;
    double position[3] = {0, 0, 0};
    Orientation orientation = Orientation::euler123;
    std::vector<double> values;  ///< initial orientation as written (3 or 9 numbers)
    bool relative_frame = false;
  };
  std::size_t output_frequency = 0;  ///< every N steps; 0 = custom or not stated
  std::vector<Node> nodes;           ///< definition order
  std::multimap<long, std::string> elements;  ///< label -> keyword of `keyword: label ...` lines
  const Node* node(long label) const;
};

/// The time of every output block: the `Step` lines of the .out whose output flag is set
/// (format doc section 2). 7-field lines (MBDyn before 2011) use the .log output frequency.
struct MbdynTimes {
  std::vector<double> time;
  std::vector<long> step;
  bool seven_fields = false;
  std::size_t step_lines = 0;  ///< every Step line read, written or not
  /// Lines that open an eigenvalue table ("Mode n. ..."; read_mbdyn_out_eigenanalyses reads them)
  std::size_t eigenvalue_tables = 0;
  /// Non-empty when the printed times could not resolve the output step (6 significant digits at
  /// late times) and were rebuilt from the Step indices and time steps: the warning that says so.
  std::string rebuilt;
};

/// Rows of one per-entity file, streamed in one pass. Requests name (label, 1-based column).
struct BlockRequest {
  long label;
  std::size_t column;
};
struct BlockRead {
  std::string source;
  std::vector<long> labels;          ///< row labels of one block, in file order
  std::vector<std::size_t> columns;  ///< columns of each row (first block)
  std::size_t blocks = 0;            ///< complete blocks
  std::vector<std::vector<double>> values;  ///< per request, one value per complete block
  std::vector<std::string> warnings;
};
struct BlockOptions {
  /// Stop after this many complete blocks; the rest of the file is not read (ReadOptions::until).
  std::size_t max_blocks = std::numeric_limits<std::size_t>::max();
  /// Time of each block (from the .out), only to say where a run that diverged stops being finite.
  std::span<const double> times;
};

MbdynLog parse_mbdyn_log(std::string_view text, const std::string& source);
MbdynLog read_mbdyn_log(const std::string& path);
MbdynTimes parse_mbdyn_out(std::string_view text, const std::string& source, std::size_t output_frequency = 0);
MbdynTimes read_mbdyn_out(const std::string& path, std::size_t output_frequency = 0);
BlockRead parse_mbdyn_blocks(std::string_view text, const std::string& source, const std::vector<BlockRequest>& requests,
                             const BlockOptions& options = {});
BlockRead read_mbdyn_blocks(const std::string& path, const std::vector<BlockRequest>& requests,
                            const BlockOptions& options = {});

/// "run/hammond.mov" (or "run/hammond.mov.gz") -> "run/hammond"; a path with no MBDyn extension is
/// returned unchanged.
std::string mbdyn_prefix(const std::string& path);

/// Whether the text set at `prefix` holds entity rows: one of its per-entity files (.mov .jnt .ine
/// .frc .act .aer .prm .drv .mod and the scalar nodes' .abs .ele .prs .hyd, .gen .usr .rot)
/// exists and is not empty. A run with `output results: netcdf, no text` leaves
/// only .out, .log and empty (or no) entity files; its channels are in PREFIX.nc.
bool mbdyn_text_has_entity_rows(const std::string& prefix);

/// Reads the channels from the text set at `prefix`. Throws ReadError (file, line, expectation).
ChannelSet read_mbdyn_text(const std::string& prefix, const std::vector<ChannelSpec>& channels,
                           const ReadOptions& options = {});
Inventory describe_mbdyn_text(const std::string& prefix);

}  // namespace mlce::reader
