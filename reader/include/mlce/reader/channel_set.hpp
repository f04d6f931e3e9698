#pragma once
// What a format reader hands to the rest of the toolchain: a time axis and named channels on it.
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace mlce::reader {

/// What to read of a result set with a time axis.
struct ReadOptions {
  /// Read only the output steps at times <= until; later ones are not parsed at all. A run that
  /// diverged (nan/inf printed) after the stretch of interest is then readable, and a long run
  /// analysed over its start is read in proportion to that start. +inf = everything.
  double until = std::numeric_limits<double>::infinity();
};

/// How many of the leading output steps `time` holds at t <= options.until (within a millionth of
/// the mean step); all of them when until is +inf. A nan time does not end the count (the caller
/// refuses it with its line); a time that goes back does (a run restarted from an earlier time, two
/// runs joined: `--to` just before it reads the first run). Throws ReadError naming `source` when
/// not one.
std::size_t steps_until(const std::vector<double>& time, const ReadOptions& options, const std::string& source);

struct ChannelSet {
  std::string source;                        ///< file or output prefix, for messages
  std::vector<double> time;                  ///< one per sample; empty when the format has none
  std::vector<std::string> names;            ///< one per channel (the spec text)
  std::vector<std::vector<double>> values;   ///< values[c][k]: channel c at sample k
  std::vector<std::string> warnings;
};

/// What `mlce channels` lists: the entities a result set holds and its time span.
struct Inventory {
  std::string source;
  std::string format;
  struct Node {
    long label;
    std::string kind;         ///< dynamic, static, modal, dummy, ... or "unknown"
    std::string orientation;  ///< euler123, euler313, euler321, phi, mat, none
    std::size_t columns;      ///< columns of its rows (text) or 0
  };
  struct Entity {
    std::string file;  ///< jnt, ine, frc, ...
    long label;
    std::string type;  ///< element type when the set says it, else ""
    std::size_t columns;
  };
  /// NetCDF: the other time histories (beams, forces, aerodynamic elements, run.*), var:NAME:K.
  struct Variable {
    std::string name;
    std::size_t components;  ///< per record (3 for a vector, 9 for a matrix)
  };
  std::vector<Node> nodes;
  std::vector<Entity> entities;
  std::vector<Variable> variables;
  std::size_t blocks = 0;
  double t_first = 0.0, t_last = 0.0;
  std::vector<std::string> columns;  ///< column files: the column names
  /// MBDyn's own eigenanalyses beside the time histories (the set's .m files, or where there is none the
  /// eigenvalue tables of its .out; in NetCDF those eig.time holds, never-reached ones left out):
  /// `mlce eigenanalysis SET` reads them.
  std::size_t eigenanalyses = 0;
  std::vector<std::string> warnings;
};

}  // namespace mlce::reader
