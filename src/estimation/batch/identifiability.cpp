#include "inertial/estimation/batch/identifiability.hpp"
#include "inertial/model/number_text.hpp"

#include <Eigen/Eigenvalues>
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

}  // namespace

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
  return report;
}

}  // namespace inertial
