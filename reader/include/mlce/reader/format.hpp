#pragma once
// Format readers are plug-ins: each implements FormatReader and registers under a name and the
// file extensions it owns. Adding another solver's format is one new file plus one add() call.
#include <memory>
#include <string>
#include <vector>

#include "mlce/reader/channel_set.hpp"
#include "mlce/reader/channel_spec.hpp"

namespace mlce::reader {

class FormatReader {
 public:
  virtual ~FormatReader() = default;
  virtual std::string name() const = 0;
  /// Extensions (without the dot) this format owns; "" = an output prefix with no extension.
  virtual std::vector<std::string> extensions() const = 0;
  /// True when `path` (a file or an output prefix) looks like this format.
  virtual bool recognizes(const std::string& path) const = 0;
  /// True when the file's own first bytes say it is this format, whatever its name (a binary format
  /// with a magic number: a NetCDF file named run.dat or run.cdf). Asked before any extension
  /// decides; text formats have no such mark and keep the default.
  virtual bool recognizes_content(const std::string& /*path*/) const { return false; }
  virtual Inventory describe(const std::string& path) const = 0;
  /// The channels; `options.until` limits a set with a time axis (solver output) to its earlier
  /// steps. A column file has no time axis of its own (which column is time is the caller's
  /// choice), so its reader reads every row.
  virtual ChannelSet read(const std::string& path, const std::vector<ChannelSpec>& channels,
                          const ReadOptions& options) const = 0;
  ChannelSet read(const std::string& path, const std::vector<ChannelSpec>& channels) const {
    return read(path, channels, ReadOptions{});
  }
};

class FormatRegistry {
 public:
  void add(std::unique_ptr<FormatReader> reader);
  /// By name ("column", "mbdyn-text", "mbdyn-netcdf"); nullptr when unknown.
  const FormatReader* by_name(const std::string& name) const;
  /// The reader for a path: by extension first, then by asking each reader. Throws ReadError
  /// naming the path when no reader takes it.
  const FormatReader& for_path(const std::string& path) const;
  std::vector<std::string> names() const;

 private:
  std::vector<std::unique_ptr<FormatReader>> readers_;
};

/// A registry holding the built-in formats: column files, MBDyn text output, MBDyn NetCDF.
const FormatRegistry& default_registry();

/// For a file that is read as columns but whose extension says MBDyn output (.mov .jnt .ine .frc
/// .act .aer .prm .drv .log) and whose set has no PREFIX.out: why its node, joint and rel channels
/// are not available and what to do, as a clause to append to a message ("; ..."). Empty otherwise.
std::string missing_mbdyn_out_hint(const std::string& path);

std::unique_ptr<FormatReader> make_column_format();
std::unique_ptr<FormatReader> make_mbdyn_text_format();
std::unique_ptr<FormatReader> make_mbdyn_netcdf_format();

}  // namespace mlce::reader
