#pragma once
// MBDyn NetCDF output (format doc section 11): `time`, node.struct.<L>.{X,E|Phi|R,XP,Omega,...},
// elem.joint.<L>.{f,m,F,M,<extras>}. Channel specs address it exactly like the text set:
// joint:L:K counts columns as the .jnt file would (2-4 f, 5-7 m, 8-10 F, 11-13 M, then the
// joint's further variables in file order, flattened).
#include <string>
#include <vector>

#include "mlce/reader/channel_set.hpp"
#include "mlce/reader/channel_spec.hpp"

namespace mlce::reader {

ChannelSet read_mbdyn_netcdf(const std::string& path, const std::vector<ChannelSpec>& channels,
                             const ReadOptions& options = {});
Inventory describe_mbdyn_netcdf(const std::string& path);

}  // namespace mlce::reader
