#pragma once
// MBDyn NetCDF output (format doc section 11): `time`, node.struct.<L>.{X,E|Phi|R,XP,Omega,...},
// elem.joint.<L>.{f,m,F,M,<extras>}. Channel specs address it exactly like the text set:
// joint:L:K counts columns as the .jnt file would (2-4 f, 5-7 m, 8-10 F, 11-13 M, then the
// joint's further variables in file order, flattened). Eigenanalyses (eig.*) are read apart, below.
#include <string>
#include <vector>

#include "mlce/reader/channel_set.hpp"
#include "mlce/reader/channel_spec.hpp"
#include "mlce/reader/mbdyn_eigenanalysis.hpp"

namespace mlce::reader {

ChannelSet read_mbdyn_netcdf(const std::string& path, const std::vector<ChannelSpec>& channels,
                             const ReadOptions& options = {});
Inventory describe_mbdyn_netcdf(const std::string& path);

/// The eigenanalyses MBDyn wrote into its NetCDF output (`eigenanalysis:` with `output results: netcdf`;
/// DataManager::OutputEigPrepare, OutputEigParams, OutputEigFullMatrices, OutputEigSparseMatrices,
/// OutputEigenvectors):
///   eig.time, eig.dCoef (dimension `eigensolutions`: one per planned analysis; the fill value for one
///   the run never reached), eig.step, eig.idx (not read);
///   eig.<k>.alpha (eig_<k>_iNVec_out, 3): alphar, alphai, beta, with `output eigenvectors`;
///   eig.<k>.Aplus, eig.<k>.Aminus: (eig_iSize, eig_iSize) with `output matrices`, stored as MBDyn's
///   FullMatrixHandler holds them, column by column, so that the variable's [i][j] is A(j, i) (transposed
///   back here); or (time, 3) 1-based triplets with `output sparse matrices`, along the record dimension
///   (the records after the last triplet hold the fill value);
///   eig.<k>.VR, eig.<k>.VL (not read).
/// Each analysis comes as the .m reader returns it (mbdyn_eigenanalysis.hpp), double precision, source
/// "PATH:eig.<k>".
struct MbdynNetcdfEigenanalyses {
  std::vector<MbdynEigenanalysis> analyses;  ///< those performed, in the file's order
  std::vector<std::string> warnings;         ///< analyses planned but never performed
};

/// Empty (no analysis, no warning) when the file holds no eig.time. Throws ReadError naming the file and
/// the variable on a dCoef that is not positive, a number that is not finite or was never written, a
/// matrix that is not square or is larger than kLargestEigenanalysisMatrix, a triplet index outside
/// 1..eig_iSize, or an analysis with neither alpha nor both matrices.
MbdynNetcdfEigenanalyses read_mbdyn_netcdf_eigenanalyses(const std::string& path);

}  // namespace mlce::reader
