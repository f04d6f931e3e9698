#pragma once
// What every format reader produces: named numeric columns, with where each row came from.
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace mlce::reader {

/// A malformed or unreadable file. The message names the file, the line when there is one, and
/// what was expected.
class ReadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Table {
  std::string source;                     ///< file name, for messages
  std::vector<std::string> names;         ///< one per column ("column 1", ... when the file has none)
  bool has_header = false;                ///< names come from a header line of the file
  std::vector<std::vector<double>> columns;
  std::vector<std::size_t> line;          ///< 1-based file line of each row
  std::vector<std::string> warnings;

  std::size_t rows() const { return line.size(); }
  /// "file:line" for row `row` (or "file" when out of range).
  std::string where(std::size_t row) const;
};

}  // namespace mlce::reader
