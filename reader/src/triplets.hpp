#pragma once
// Sparse matrices as MBDyn writes them for its eigenanalysis, in the .m file (`i j v;` rows, then
// spconvert) and in NetCDF (a (record, 3) variable): shared by both readers.
#include <cstddef>
#include <string>
#include <vector>

namespace mlce::reader::detail {

/// Throws ReadError starting with `where` when an n x n matrix is larger than this reader holds dense.
void check_matrix_size(const std::string& where, std::size_t n);

/// `count` 1-based (row, column, value) triplets at `t` (3 doubles each) as a row-major n x n matrix;
/// repeated positions add up, as Octave's spconvert (sparse(i, j, v)) does. n is `size` when the file
/// names it (NetCDF's eig_iSize), else, for size 0, the largest index. Throws ReadError starting with
/// `where` on an index that is not a whole number from 1 to n (at most kLargestEigenanalysisMatrix) or
/// on no triplet at all.
std::vector<double> matrix_from_triplets(const double* t, std::size_t count, std::size_t size, const std::string& where,
                                         std::size_t& n);

}  // namespace mlce::reader::detail
