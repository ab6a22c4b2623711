/// @file identifiability.hpp
/// Which parameter directions the data did not excite: the (numerical) null space of the stacked
/// regressor A, found from A^T A after scaling every column to unit norm (so units do not matter),
/// and put into a sparse, readable form (reduced row echelon form of the null-space basis), so that
/// each direction names few parameters, e.g. "link2.Ixx and link3.Ixx only as their sum".
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace inertial {

struct UnidentifiedDirection {
  /// Parameter names with their coefficients in the direction (largest first); the torques do not
  /// change when the parameters move together along it.
  std::vector<std::pair<std::string, double>> terms;
  std::string description;  ///< in words
};

struct IdentifiabilityReport {
  int num_parameters = 0;
  int rank = 0;                  ///< number of identifiable combinations
  double condition_number = 0;   ///< of the column-scaled regressor, over its identifiable part
  std::vector<UnidentifiedDirection> directions;
};

/// @param AtA the regressor's A^T A; @param names one name per column;
/// @param relative_tolerance singular values of the scaled A below this fraction of the largest
/// count as zero.
IdentifiabilityReport AnalyzeIdentifiability(const Eigen::MatrixXd& AtA, const std::vector<std::string>& names,
                                             double relative_tolerance = 1e-5);

}  // namespace inertial
