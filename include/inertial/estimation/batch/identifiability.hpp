/// @file identifiability.hpp
/// Which parameter directions the data did not excite: the (numerical) null space of the stacked
/// regressor A, found from A^T A after scaling every column to unit norm (so units do not matter),
/// and put into a sparse, readable form (reduced row echelon form of the null-space basis), so that
/// each direction names few parameters, e.g. "link2.Ixx and link3.Ixx only as their sum".
///
/// And what the data do determine, written as what they determine: the identifiable (base)
/// combinations of the coefficients, a basis of the row space of A (the orthogonal complement of
/// the null space above), in the classical base-parameter form (Mayeda, Yoshida and Osuka, IEEE
/// Trans. Robot. Autom. 1990; Gautier and Khalil, IEEE Trans. Robot. Autom. 1990; Gautier, J.
/// Robot. Syst. 1991 for the numerical form): the columns split into independent ones a_I and
/// dependent ones a_D = a_I beta (each dependent column a combination of the independent ones), so
///   A w = a_I (w_I + beta w_D),
/// and each row of w_I + beta w_D, "one independent coefficient + sum_j beta_j * dependent
/// coefficients", is determined by the torques while no other combination is. The matrix
/// [I beta] (columns in their places) is the reduced row echelon form of the row space, with the
/// independent columns chosen leftmost first: a column is independent if it is farther from the
/// span of the independent columns before it (in the column-scaled, rank-truncated regressor)
/// than the rank tolerance; parents' columns come before their children's, so a parent's
/// coefficient keeps the children's regrouped into it, as in Khalil's regrouping rules.
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

/// One identifiable combination of the coefficients (file comment): k^T w with k = e_independent +
/// sum_j beta_j e_j.
struct BaseCombination {
  /// (name, coefficient in physical units) of each coefficient in it: the independent one first
  /// (coefficient 1), then the dependent ones regrouped into it (beta_j: the torques of a unit of
  /// w_j are beta_j times those of a unit of w_independent), in column order. A beta whose
  /// torques are below 1e-6 of the independent coefficient's (|beta_j| ||a_j|| < 1e-6 ||a_i||)
  /// is left out.
  std::vector<std::pair<std::string, double>> terms;
  std::vector<int> columns;  ///< the column of A (index into w) of each term
  std::string text;          ///< "thigh.hz + 2.94 shank.m", in the units of the first coefficient
  /// k as a vector over the P columns.
  Eigen::VectorXd Vector(int num_parameters) const;
};

struct IdentifiabilityReport {
  int num_parameters = 0;
  int rank = 0;                  ///< number of identifiable combinations
  double condition_number = 0;   ///< of the column-scaled regressor, over its identifiable part
  std::vector<UnidentifiedDirection> directions;
  /// The rank's identifiable combinations, one per independent column, in column order.
  std::vector<BaseCombination> base_combinations;
};

/// @param AtA the regressor's A^T A; @param names one name per column;
/// @param relative_tolerance singular values of the scaled A below this fraction of the largest
/// count as zero.
IdentifiabilityReport AnalyzeIdentifiability(const Eigen::MatrixXd& AtA, const std::vector<std::string>& names,
                                             double relative_tolerance = 1e-5);

}  // namespace inertial
