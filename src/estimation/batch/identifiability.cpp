#include "inertial/estimation/batch/identifiability.hpp"
#include "inertial/model/number_text.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace inertial {
namespace {

std::string Describe(const std::vector<std::pair<std::string, double>>& terms) {
  if (terms.size() == 1) return terms[0].first + " does not affect the torques (not excited)";
  if (terms.size() == 2) {
    // Moving a by t and b by c t changes nothing: only b - c a is identified.
    const std::string& a = terms[0].first;
    const std::string& b = terms[1].first;
    const double c = terms[1].second / terms[0].second;
    if (std::abs(c + 1.0) < 1e-3) return a + " and " + b + " only as their sum";
    if (std::abs(c - 1.0) < 1e-3) return a + " and " + b + " only as their difference";
    return a + " and " + b + " only as the combination " + b + (c > 0 ? " - " : " + ") + FormatNumber(std::abs(c), 3) + " " + a;
  }
  std::string s = "moving together ";
  for (size_t i = 0; i < terms.size(); ++i) {
    s += (i == 0 ? "" : ", ") + terms[i].first + " by " + FormatNumber(terms[i].second / terms[0].second, 3);
  }
  return s + " leaves every torque unchanged";
}

// "a + 2.94 b - c": a combination's terms as a sum (coefficients 1 unwritten). Four digits: betas
// are often products of link lengths, 0.075^2 = 0.005625 would round to 0.00563 or 0.00562 by
// its last bit at three.
std::string CombinationText(const std::vector<std::pair<std::string, double>>& terms) {
  std::string s = terms[0].first;
  for (size_t i = 1; i < terms.size(); ++i) {
    const std::string c = FormatNumber(std::abs(terms[i].second), 4);
    s += (terms[i].second < 0 ? " - " : " + ") + (c == "1" ? "" : c + " ") + terms[i].first;
  }
  return s;
}

// The identifiable combinations (header). M (R x P) is the column-scaled regressor B = A D
// truncated to its R retained singular directions, in the coordinates of its left singular vectors
// (B ~ U M with U orthonormal, so M's columns have the lengths and angles of B's); d the column
// scaling (0: a zero column, which is in no combination); `threshold` the least distance of an
// independent column from the span of those before it.
std::vector<BaseCombination> BaseCombinations(const Eigen::MatrixXd& M, const Eigen::VectorXd& d, double threshold,
                                              const std::vector<std::string>& names) {
  const int R = static_cast<int>(M.rows()), P = static_cast<int>(M.cols());
  std::vector<BaseCombination> combinations;
  if (R == 0) return combinations;
  // Independent columns, leftmost first, by Gram-Schmidt (twice, for orthogonality to rounding):
  // a column farther than `threshold` from the span of the chosen ones joins them. Below the rank
  // tolerance a column adds a direction the truncation already counted as null (B_I would have a
  // singular value below it).
  Eigen::MatrixXd Q(R, R);
  int chosen = 0;
  std::vector<bool> independent(P, false);
  auto residual = [&](int j) {
    Eigen::VectorXd r = M.col(j);
    for (int pass = 0; pass < 2; ++pass) r -= Q.leftCols(chosen) * (Q.leftCols(chosen).transpose() * r);
    return r;
  };
  auto choose = [&](int j, const Eigen::VectorXd& r) {
    Q.col(chosen++) = r / r.norm();
    independent[j] = true;
  };
  for (int j = 0; j < P && chosen < R; ++j) {
    if (d[j] == 0.0) continue;
    const Eigen::VectorXd r = residual(j);
    if (r.norm() > threshold) choose(j, r);
  }
  // Fewer than R (possible only when the columns reach the last directions in many small steps,
  // each below the threshold): the farthest remaining column each time, as column-pivoted QR does.
  while (chosen < R) {
    int best = -1;
    Eigen::VectorXd best_r;
    for (int j = 0; j < P; ++j) {
      if (independent[j] || d[j] == 0.0) continue;
      Eigen::VectorXd r = residual(j);
      if (best < 0 || r.norm() > best_r.norm()) best = j, best_r = r;
    }
    if (best < 0 || !(best_r.norm() > 0.0)) break;
    choose(best, best_r);
  }
  std::vector<int> pivots;
  for (int j = 0; j < P; ++j) {
    if (independent[j]) pivots.push_back(j);
  }
  const int r_found = static_cast<int>(pivots.size());
  Eigen::MatrixXd M_I(R, r_found);
  for (int i = 0; i < r_found; ++i) M_I.col(i) = M.col(pivots[i]);
  // Scaled betas: b_j = sum_i beta_ij b_{p_i} (B's columns), i.e. M = M_I beta; M_I is square and
  // invertible when all R columns were found (each independent of the ones before it).
  const Eigen::MatrixXd beta = M_I.fullPivLu().solve(M);
  for (int i = 0; i < r_found; ++i) {
    const int p = pivots[i];
    BaseCombination c;
    c.terms.emplace_back(names[p], 1.0);
    c.columns.push_back(p);
    for (int j = 0; j < P; ++j) {
      // Independent columns are in their own combination only (beta = identity there); a beta
      // below 1e-6 is a column whose torques are below 1e-6 of the independent one's: rounding.
      if (independent[j] || d[j] == 0.0 || !(std::abs(beta(i, j)) >= 1e-6)) continue;
      // In physical units: a_j = b_j / d_j = sum_i beta_ij (d_{p_i} / d_j) a_{p_i}.
      c.terms.emplace_back(names[j], beta(i, j) * d[p] / d[j]);
      c.columns.push_back(j);
    }
    c.text = CombinationText(c.terms);
    combinations.push_back(std::move(c));
  }
  return combinations;
}

}  // namespace

Eigen::VectorXd BaseCombination::Vector(int num_parameters) const {
  Eigen::VectorXd k = Eigen::VectorXd::Zero(num_parameters);
  for (size_t i = 0; i < columns.size(); ++i) {
    if (columns[i] < 0 || columns[i] >= num_parameters) {
      throw std::invalid_argument("base combination: a column is outside the " + std::to_string(num_parameters) +
                                  " parameters");
    }
    k[columns[i]] = terms[i].second;
  }
  return k;
}

IdentifiabilityReport AnalyzeIdentifiability(const Eigen::MatrixXd& AtA, const std::vector<std::string>& names,
                                             double relative_tolerance) {
  const int P = static_cast<int>(AtA.rows());
  if (AtA.cols() != P || static_cast<int>(names.size()) != P) {
    throw std::invalid_argument("identifiability: A^T A must be square with one name per column");
  }
  if (!AtA.allFinite()) {
    // NaN would leave every direction without a term (and the analysis meaningless).
    throw std::invalid_argument("identifiability: A^T A has entries that are not finite numbers");
  }
  IdentifiabilityReport report;
  report.num_parameters = P;
  // Column scaling D = diag(1/||a_k||); zero columns stay zero.
  Eigen::VectorXd d(P);
  for (int k = 0; k < P; ++k) d[k] = AtA(k, k) > 0 ? 1.0 / std::sqrt(AtA(k, k)) : 0.0;
  const Eigen::MatrixXd S = d.asDiagonal() * AtA * d.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S);
  const Eigen::VectorXd sigma = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();  // ascending
  const double sigma_max = sigma.size() > 0 ? sigma.maxCoeff() : 0.0;
  std::vector<int> null_columns;
  for (int k = 0; k < P; ++k) {
    if (!(sigma[k] > relative_tolerance * sigma_max)) null_columns.push_back(k);
  }
  report.rank = P - static_cast<int>(null_columns.size());
  report.condition_number = report.rank > 0 ? sigma_max / sigma[P - report.rank] : 0.0;
  // Null-space basis in physical units (V = D Z; zero columns are null directions by themselves).
  const int k_null = static_cast<int>(null_columns.size());
  Eigen::MatrixXd V(k_null, P);
  for (int i = 0; i < k_null; ++i) {
    Eigen::VectorXd z = eig.eigenvectors().col(null_columns[i]);
    for (int k = 0; k < P; ++k) z[k] = d[k] > 0 ? z[k] * d[k] : z[k];
    V.row(i) = z.transpose() / std::max(z.lpNorm<Eigen::Infinity>(), 1e-300);
  }
  // Reduced row echelon form (Gauss-Jordan with partial pivoting over columns): sparse directions.
  int row = 0;
  std::vector<int> pivots;
  for (int col = 0; col < P && row < k_null; ++col) {
    int best = row;
    for (int i = row; i < k_null; ++i) {
      if (std::abs(V(i, col)) > std::abs(V(best, col))) best = i;
    }
    if (std::abs(V(best, col)) < 1e-9) continue;
    V.row(row).swap(V.row(best));
    V.row(row) /= V(row, col);
    for (int i = 0; i < k_null; ++i) {
      if (i != row) V.row(i) -= V(i, col) * V.row(row);
    }
    pivots.push_back(col);
    ++row;
  }
  for (int i = 0; i < row; ++i) {
    UnidentifiedDirection dir;
    for (int k = 0; k < P; ++k) {
      if (std::abs(V(i, k)) > 1e-6) dir.terms.emplace_back(names[k], V(i, k));
    }
    if (dir.terms.empty()) continue;  // every entry below 1e-6 (the pivot's is 1: cannot happen with finite V)
    std::stable_sort(dir.terms.begin() + 1, dir.terms.end(),
                     [](const auto& a, const auto& b) { return std::abs(a.second) > std::abs(b.second); });
    dir.description = Describe(dir.terms);
    report.directions.push_back(dir);
  }
  // The row space: the retained eigenvectors (the orthogonal complement of the null ones above,
  // in the scaled coordinates), weighted by their singular values.
  const int R = report.rank;
  const Eigen::MatrixXd M = sigma.tail(R).asDiagonal() * eig.eigenvectors().rightCols(R).transpose();
  report.base_combinations = BaseCombinations(M, d, relative_tolerance * sigma_max, names);
  return report;
}

}  // namespace inertial
