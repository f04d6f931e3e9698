// The format registry and the built-in plug-ins.
#include "mlce/reader/format.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string_view>

#include "mlce/reader/column_file.hpp"
#include "mlce/reader/mbdyn_netcdf.hpp"
#include "mlce/reader/mbdyn_text.hpp"
#include "mlce/reader/table.hpp"
#include "line_source.hpp"

namespace mlce::reader {

std::size_t steps_until(const std::vector<double>& time, const ReadOptions& options, const std::string& source) {
  const double until = options.until;
  if (!(until < std::numeric_limits<double>::infinity()) || time.empty()) return time.size();
  const double step = time.size() > 1 ? (time.back() - time.front()) / static_cast<double>(time.size() - 1) : 0.0;
  const double limit = until + 1e-6 * std::abs(step);
  std::size_t n = 0;
  // A nan time is kept, for the caller to refuse. Time that goes back (a run restarted from an
  // earlier time, two runs joined) ends the steps read: what follows repeats times already read.
  while (n < time.size() && !(time[n] > limit) && !(n > 0 && time[n] < time[n - 1])) ++n;
  if (n == 0) {
    char text[160];
    std::snprintf(text, sizeof text, ": no output step at t <= %.10g (the first is at t = %.10g)", until, time.front());
    throw ReadError(source + text);
  }
  return n;
}


namespace {

bool is_file(const std::string& p) {
  std::error_code ec;
  return std::filesystem::is_regular_file(p, ec);
}

/// "-" (the standard input), a pipe or a character device (/dev/stdin, `<(command)`): read once,
/// front to back, as a column file.
bool is_stream(const std::string& p) {
  if (p == "-") return true;
  std::error_code ec;
  const auto st = std::filesystem::status(p, ec);
  return !ec && (std::filesystem::is_fifo(st) || std::filesystem::is_character_file(st));
}

/// The extension of what the file holds: `run.mov.gz` is a .mov (read through zlib).
std::string extension_of(const std::string& compressed_or_not) {
  const std::string path = detail::without_gz(compressed_or_not);
  const auto dot = path.rfind('.');
  const auto slash = path.rfind('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  return path.substr(dot + 1);
}

}  // namespace

std::string missing_mbdyn_out_hint(const std::string& path) {
  const std::string ext = extension_of(path);
  static const char* const entity_files[] = {"mov", "jnt", "ine", "frc", "act", "aer", "prm", "drv", "mod",
                                             "abs", "ele", "prs", "hyd", "gen", "usr", "rot", "log"};
  if (std::find(std::begin(entity_files), std::end(entity_files), ext) == std::end(entity_files)) return "";
  const std::string out = mbdyn_prefix(path) + ".out";
  if (is_file(detail::stored_file(out))) return "";
  return "; its name says MBDyn output, but " + out +
         " (whose Step lines give the time of every output block) is not beside it: copy it and the .log there "
         "to read node:, joint: and rel: channels, or read this file's columns as col:K with --dt";
}

namespace {

class ColumnFormat final : public FormatReader {
 public:
  std::string name() const override { return "column"; }
  std::vector<std::string> extensions() const override { return {"txt", "csv", "dat", "tsv"}; }
  bool recognizes(const std::string& path) const override { return is_file(path) || is_stream(path); }
  Inventory describe(const std::string& path) const override {
    ColumnFileOptions o;
    o.text_columns = true;  // a column of dates or labels is listed, and said to be no channel
    const Table t = read_column_file(path, o);
    Inventory inv;
    inv.source = path;
    inv.format = name();
    inv.columns = t.names;
    inv.blocks = t.rows();
    inv.warnings = t.warnings;
    for (std::size_t k = 0; k < t.text.size(); ++k)
      if (t.text[k].line != 0)
        inv.warnings.push_back("col:" + std::to_string(k + 1) + (t.has_header ? " (" + t.names[k] + ")" : "") +
                               " can be analysed only before its first field that is no number: " + t.text[k].message);
    if (const std::string hint = missing_mbdyn_out_hint(path); !hint.empty())
      inv.warnings.push_back("read as a column file" + hint);
    return inv;
  }
  ChannelSet read(const std::string& path, const std::vector<ChannelSpec>& channels,
                  const ReadOptions& /*options: no time axis of its own*/) const override {
    ColumnFileOptions o;
    for (const auto& c : channels) {
      if (c.kind != ChannelSpec::Kind::column)
        throw ReadError(path + ": channel '" + c.text + "': a column file takes col:K channels" + missing_mbdyn_out_hint(path));
      o.keep.push_back(c.column);
    }
    Table t = read_column_file(path, o);
    ChannelSet s;
    s.source = path;
    for (const auto& c : channels) s.names.push_back(c.text);
    s.values = std::move(t.columns);
    s.warnings = std::move(t.warnings);
    return s;
  }
};

class MbdynTextFormat final : public FormatReader {
 public:
  std::string name() const override { return "mbdyn-text"; }
  std::vector<std::string> extensions() const override {
    return {"out", "log", "mov", "jnt", "ine", "frc", "act", "aer", "prm", "drv", "mod",
            "abs", "ele", "prs", "hyd", "gen", "usr", "rot", ""};
  }
  bool recognizes(const std::string& path) const override {
    return is_file(detail::stored_file(mbdyn_prefix(path) + ".out"));
  }
  Inventory describe(const std::string& path) const override { return describe_mbdyn_text(path); }
  ChannelSet read(const std::string& path, const std::vector<ChannelSpec>& channels,
                  const ReadOptions& options) const override {
    return read_mbdyn_text(path, channels, options);
  }
};

/// The .nc file itself, or an output prefix whose text set has no entity rows (a run with
/// `output results: netcdf, no text` writes .out and .log, and its channels only to PREFIX.nc).
class MbdynNetcdfFormat final : public FormatReader {
 public:
  std::string name() const override { return "mbdyn-netcdf"; }
  std::vector<std::string> extensions() const override { return {"nc"}; }
  bool recognizes(const std::string& path) const override {
    if (extension_of(path) == "nc") return is_file(path);
    return !is_file(path) && is_file(path + ".nc") && !mbdyn_text_has_entity_rows(path);
  }
  /// NetCDF classic (CDF 1, 2, 5) or netCDF-4 (an HDF5 file) by its magic number.
  bool recognizes_content(const std::string& path) const override {
    if (!is_file(path)) return false;
    std::ifstream in(path, std::ios::binary);
    std::array<char, 8> head{};
    in.read(head.data(), head.size());
    const std::string_view got(head.data(), static_cast<std::size_t>(in.gcount()));
    return detail::starts_like_netcdf(got);
  }
  Inventory describe(const std::string& path) const override { return describe_mbdyn_netcdf(nc_file(path)); }
  ChannelSet read(const std::string& path, const std::vector<ChannelSpec>& channels,
                  const ReadOptions& options) const override {
    return read_mbdyn_netcdf(nc_file(path), channels, options);
  }

 private:
  static std::string nc_file(const std::string& path) {
    // The netCDF library reads only an uncompressed file (netCDF-4 compresses inside, per variable).
    if (detail::without_gz(path) != path)
      throw ReadError(path + ": a gzip-compressed NetCDF file cannot be read in place: 'gunzip -k " + path +
                      "' first (the text output set reads compressed)");
    return extension_of(path) == "nc" || is_file(path) ? path : path + ".nc";  // a file: claimed by its content
  }
};

}  // namespace

void FormatRegistry::add(std::unique_ptr<FormatReader> reader) { readers_.push_back(std::move(reader)); }

const FormatReader* FormatRegistry::by_name(const std::string& n) const {
  for (const auto& r : readers_)
    if (r->name() == n) return r.get();
  return nullptr;
}

const FormatReader& FormatRegistry::for_path(const std::string& path) const {
  const std::string ext = extension_of(path);
  // A file whose bytes say what it is, whatever it is called.
  for (const auto& r : readers_)
    if (r->recognizes_content(path)) return *r;
  // An extension a format owns decides, when that format also recognizes the path.
  if (!ext.empty())
    for (const auto& r : readers_)
      for (const auto& e : r->extensions())
        if (e == ext && r->recognizes(path)) return *r;
  // An output prefix (no file of that name): a format that recognizes it.
  if (!is_file(path))
    for (const auto& r : readers_)
      if (r->recognizes(path)) return *r;
  if (is_file(path) || is_stream(path))
    for (const auto& r : readers_)
      if (r->name() == "column") return *r;
  throw ReadError(path + ": cannot open the file (missing or unreadable, and no MBDyn output set " + path + ".out)");
}

std::vector<std::string> FormatRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& r : readers_) out.push_back(r->name());
  return out;
}

std::unique_ptr<FormatReader> make_column_format() { return std::make_unique<ColumnFormat>(); }
std::unique_ptr<FormatReader> make_mbdyn_text_format() { return std::make_unique<MbdynTextFormat>(); }
std::unique_ptr<FormatReader> make_mbdyn_netcdf_format() { return std::make_unique<MbdynNetcdfFormat>(); }

const FormatRegistry& default_registry() {
  static const FormatRegistry registry = [] {
    FormatRegistry r;
    r.add(make_mbdyn_netcdf_format());
    r.add(make_mbdyn_text_format());
    r.add(make_column_format());
    return r;
  }();
  return registry;
}

}  // namespace mlce::reader
