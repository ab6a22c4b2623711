#include "inertial/estimation/fit_uncertainty.hpp"
#include "inertial/estimation/batch/region_barrier.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "inertial/inertia/log_det_divergence.hpp"

namespace inertial {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
/// Eigenvalues of the Jacobi-scaled H below this fraction of the largest are undetermined.
constexpr double kUndeterminedEigenvalue = 1e-12;
/// A gradient whose component along the undetermined subspace exceeds this fraction of its norm
/// (both in scaled coordinates) gives an infinite standard deviation.
constexpr double kUndeterminedComponent = 1e-6;

/// The eigen-decomposition of the Jacobi-scaled Hessian of the estimated parameters.
struct ScaledHessian {
  Eigen::VectorXd inv_sqrt_diag;  ///< D^-1/2 (1 where the diagonal is not positive)
  Eigen::MatrixXd pseudo_inverse;  ///< (D^-1/2 H D^-1/2)^+ on the determined directions
  Eigen::MatrixXd undetermined;    ///< orthonormal basis of the undetermined directions (scaled)
};

ScaledHessian DecomposeScaled(const Eigen::MatrixXd& H) {
  const int n = static_cast<int>(H.rows());
  ScaledHessian s;
  s.inv_sqrt_diag.resize(n);
  if (n == 0) {  // nothing estimated (every body frozen, no effect): Eigen's solver needs a matrix
    s.pseudo_inverse.resize(0, 0);
    s.undetermined.resize(0, 0);
    return s;
  }
  for (int i = 0; i < n; ++i) s.inv_sqrt_diag[i] = H(i, i) > 0.0 ? 1.0 / std::sqrt(H(i, i)) : 1.0;
  const Eigen::MatrixXd Hs = s.inv_sqrt_diag.asDiagonal() * H * s.inv_sqrt_diag.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Hs);
  const Eigen::VectorXd& lambda = eig.eigenvalues();  // ascending
  const double largest = n > 0 ? lambda[n - 1] : 0.0;
  int null_count = 0;
  while (null_count < n && !(lambda[null_count] > kUndeterminedEigenvalue * largest && largest > 0.0)) ++null_count;
  const Eigen::MatrixXd U = eig.eigenvectors().rightCols(n - null_count);
  s.pseudo_inverse = U * lambda.tail(n - null_count).cwiseInverse().asDiagonal() * U.transpose();
  s.undetermined = eig.eigenvectors().leftCols(null_count);
  return s;
}

/// True if the gradient g (of a quantity, with respect to the estimated parameters, unscaled) has
/// a component along the undetermined subspace. `first` and g's size select a block of them.
bool TouchesUndetermined(const ScaledHessian& s, int first, const Eigen::VectorXd& g) {
  if (s.undetermined.cols() == 0) return false;
  const Eigen::VectorXd g_scaled = s.inv_sqrt_diag.segment(first, g.size()).cwiseProduct(g);
  const double along = (s.undetermined.middleRows(first, g.size()).transpose() * g_scaled).norm();
  return along > kUndeterminedComponent * g_scaled.norm();
}

}  // namespace

std::vector<int> SeamFreePieces(const JointSamples& data) {
  const int N = data.size();
  std::vector<int> starts{0};
  if (N >= 3) {
    std::vector<double> steps(N - 1);
    for (int i = 0; i + 1 < N; ++i) steps[i] = data.t[i + 1] - data.t[i];
    std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
    const double median = steps[steps.size() / 2];
    for (int i = 1; i < N; ++i) {
      if (data.t[i] - data.t[i - 1] > 5.0 * median) starts.push_back(i);
    }
  }
  starts.push_back(N);
  return starts;
}

double IntegratedAutocorrelationTime(const Eigen::VectorXd& r, const std::vector<int>& starts) {
  // Centred per piece (a constant offset of a piece is not a correlation in time).
  Eigen::VectorXd c = r;
  for (size_t p = 0; p + 1 < starts.size(); ++p) {
    const int a = starts[p], len = starts[p + 1] - starts[p];
    if (len > 0) c.segment(a, len).array() -= c.segment(a, len).mean();
  }
  const double c0 = c.squaredNorm();
  if (!(c0 > 0.0) || !std::isfinite(c0)) return 1.0;
  int longest = 0;
  for (size_t p = 0; p + 1 < starts.size(); ++p) longest = std::max(longest, starts[p + 1] - starts[p]);
  double tau = 1.0;
  for (int k = 1; k < longest; ++k) {
    double ck = 0.0;
    for (size_t p = 0; p + 1 < starts.size(); ++p) {
      const int a = starts[p], len = starts[p + 1] - starts[p];
      if (len > k) ck += c.segment(a, len - k).dot(c.segment(a + k, len - k));
    }
    tau += 2.0 * ck / c0;
    if (k >= 5.0 * tau) break;  // Sokal's window: M >= 5 tau_int(M)
  }
  return std::max(1.0, tau);
}

TimeBlocks AccumulateTimeBlocks(const RobotDynamics& model, const JointSamples& data, const Eigen::VectorXd& x) {
  if (x.size() != model.num_parameters()) {
    throw std::invalid_argument("time blocks: x must have " + std::to_string(model.num_parameters()) + " entries");
  }
  if (data.size() < 2) throw std::invalid_argument("time blocks: at least two samples are needed");
  const int N = data.size(), n = model.num_dofs(), F = model.num_features();
  const Eigen::MatrixXd residual = PredictJointTorques(model, x, data) - data.tau;  // throws on mismatch
  TimeBlocks tb;
  const std::vector<int> starts = SeamFreePieces(data);
  tb.pieces = static_cast<int>(starts.size()) - 1;
  tb.correlation_time = 1.0;
  for (int j = 0; j < n; ++j) {
    tb.correlation_time = std::max(tb.correlation_time, IntegratedAutocorrelationTime(residual.col(j), starts));
  }
  int L = static_cast<int>(std::ceil(5.0 * tb.correlation_time));
  L = std::max(1, std::min(L, N / kMinTimeBlocks));
  tb.block_length = L;
  // Each piece into round(len / L) (at least 1) blocks of equal length.
  std::vector<int> block_of(N);
  int K = 0;
  for (int p = 0; p < tb.pieces; ++p) {
    const int a = starts[p], len = starts[p + 1] - starts[p];
    const int count = std::max(1, static_cast<int>(std::lround(static_cast<double>(len) / L)));
    for (int i = 0; i < len; ++i) block_of[a + i] = K + static_cast<int>(static_cast<long long>(i) * count / len);
    K += count;
  }
  tb.blocks.assign(K, JointNormalEquations{Eigen::MatrixXd::Zero(F, F), Eigen::VectorXd::Zero(F), 0.0, 0});
  Eigen::MatrixXd A(n, F);
  for (int i = 0; i < N; ++i) {
    model.Features(data.q.row(i).transpose(), data.qd.row(i).transpose(), data.qdd.row(i).transpose(), A);
    JointNormalEquations& b = tb.blocks[block_of[i]];
    const Eigen::VectorXd tau = data.tau.row(i).transpose();
    b.AtA.selfadjointView<Eigen::Lower>().rankUpdate(A.transpose());
    b.Atb.noalias() += A.transpose() * tau;
    b.btb += tau.squaredNorm();
    ++b.num_samples;
  }
  for (JointNormalEquations& b : tb.blocks) b.AtA = b.AtA.selfadjointView<Eigen::Lower>();
  return tb;
}

Matrix10 ReportFrameMap(const EstimatedBody& body) {
  // The pseudo-inertia moves as J_A = T J_B T^T, linear in pi: L's columns are the images of e_k.
  const Matrix3 R = body.report_frame.R_AB.transpose();
  Matrix4 T = Matrix4::Identity();
  T.block<3, 3>(0, 0) = R;
  T.block<3, 1>(0, 3) = -(R * body.report_frame.p_AB);
  Matrix10 L;
  for (int k = 0; k < 10; ++k) {
    L.col(k) = PiFromPseudoInertia(T * PseudoInertiaFromPi(Vector10::Unit(k)) * T.transpose());
  }
  return L;
}

namespace {

// The inputs' sizes and values; std::invalid_argument naming the wrong one.
void CheckUncertaintyInputs(const RobotDynamics& model, const JointNormalEquations& data, const Eigen::VectorXd& x,
                            double prior_weight, const std::vector<bool>& frozen_bodies) {
  const int F = model.num_features(), P = model.num_parameters();
  const int B = static_cast<int>(model.bodies().size());
  if (data.AtA.rows() != F || data.AtA.cols() != F || data.Atb.size() != F) {
    throw std::invalid_argument("fit uncertainty: normal equations do not match the model's features");
  }
  if (x.size() != P || !x.allFinite()) {
    throw std::invalid_argument("fit uncertainty: x must be " + std::to_string(P) + " finite numbers");
  }
  if (!(prior_weight >= 0.0) || !std::isfinite(prior_weight)) {
    throw std::invalid_argument("fit uncertainty: the prior weight must be finite and non-negative");
  }
  if (!frozen_bodies.empty() && static_cast<int>(frozen_bodies.size()) != B) {
    throw std::invalid_argument("fit uncertainty: frozen_bodies must have one flag per estimated body");
  }
}

// The estimated parameters (frozen bodies left out), and each parameter's position among them (-1:
// frozen).
struct FreeParameters {
  std::vector<int> index;
  std::vector<int> position;
  int size() const { return static_cast<int>(index.size()); }
};

FreeParameters ListFreeParameters(int P, int B, const std::vector<bool>& frozen_bodies) {
  FreeParameters f;
  f.position.assign(P, -1);
  for (int p = 0; p < P; ++p) {
    if (p < 10 * B && !frozen_bodies.empty() && frozen_bodies[p / 10]) continue;
    f.position[p] = f.size();
    f.index.push_back(p);
  }
  return f;
}

// The Gauss-Newton Hessian of F (as IdentifyJointModel forms it) on the estimated parameters: the
// data's part, the prior's part per body, and their sum.
struct FitHessian {
  Eigen::MatrixXd data;
  std::vector<Matrix10> prior;
  Eigen::MatrixXd total;
};

FitHessian HessianOfTheFit(const RobotDynamics& model, const JointNormalEquations& data, const Eigen::VectorXd& x,
                           double prior_weight, const FreeParameters& free, const Eigen::MatrixXd& J_w_x,
                           const std::vector<bool>& frozen_bodies) {
  const int F = model.num_features(), n = free.size();
  const int B = static_cast<int>(model.bodies().size());
  Eigen::MatrixXd J_w_free(F, n);
  for (int i = 0; i < n; ++i) J_w_free.col(i) = J_w_x.col(free.index[i]);
  FitHessian h;
  h.data = J_w_free.transpose() * data.AtA * J_w_free;
  h.total = h.data;
  h.prior.assign(B, Matrix10::Zero());
  for (int e = 0; e < B; ++e) {
    if (!frozen_bodies.empty() && frozen_bodies[e]) continue;
    Matrix10 J_r_theta;
    LogDetDivergenceResiduals(model.bodies()[e].map, x.segment<10>(10 * e), &J_r_theta);
    h.prior[e] = prior_weight * J_r_theta.transpose() * J_r_theta;
    // A body against its region's wall (region_barrier.hpp) is held there by prior knowledge too:
    // the barrier's curvature (Gauss-Newton part; zero while the body is well inside).
    if (model.bodies()[e].region) {
      Matrix10 H_b;
      if (std::isfinite(RegionBarrier(model.bodies()[e], x.segment<10>(10 * e), false, nullptr, &H_b))) {
        h.prior[e] += 0.5 * RegionBarrierWeight(data.btb, data.num_samples) * H_b;
      }
    }
    h.total.block<10, 10>(free.position[10 * e], free.position[10 * e]) += h.prior[e];
  }
  return h;
}

// Body e's standard deviations (every quantity through its gradient with respect to theta_e) and
// which of them the prior holds, into u.
// With time blocks: the white-noise covariance and the one with the data's part from the block
// sandwich (file comment); each quantity's variance is the larger of the two.
struct BlockVariances {
  Eigen::MatrixXd laplace, block;
  double Variance(int first, const Eigen::VectorXd& g) const {
    const int m = static_cast<int>(g.size());
    return std::max(g.dot(laplace.block(first, first, m, m) * g), g.dot(block.block(first, first, m, m) * g));
  }
  double Ratio(int first, const Eigen::VectorXd& g) const {
    const int m = static_cast<int>(g.size());
    const double white = g.dot(laplace.block(first, first, m, m) * g);
    return white > 0.0 ? std::sqrt(std::max(0.0, g.dot(block.block(first, first, m, m) * g)) / white) : 1.0;
  }
};

void BodyUncertaintyOfTheFit(const RobotDynamics& model, const Eigen::VectorXd& x, int e, const FreeParameters& free,
                             const FitHessian& hessian, const ScaledHessian& scaled, const Eigen::MatrixXd& H_pinv,
                             const Eigen::MatrixXd& C_free, double prior_weight,
                             const std::vector<bool>& frozen_bodies, FitUncertainty& u,
                             const BlockVariances* block = nullptr) {
  const int B = static_cast<int>(model.bodies().size());
  const std::vector<int>& position = free.position;
  const Eigen::MatrixXd& H_data = hessian.data;
  const std::vector<Matrix10>& H_prior = hessian.prior;
  auto frozen = [&](int b) { return !frozen_bodies.empty() && frozen_bodies[b]; };
  const EstimatedBody& body = model.bodies()[e];
  const int first = position[10 * e];
  Matrix10 J_pi_theta;
  body.map.ToPi(x.segment<10>(10 * e), &J_pi_theta);
  const Matrix10 J_piReport_theta = ReportFrameMap(body) * J_pi_theta;
  const InertialParams in_report = model.BodyInertia(e, x);
  const Matrix10 C_theta = C_free.block<10, 10>(first, first);
  BodyUncertainty& bu = u.bodies[e];
  u.body_pi_covariance[e] = J_piReport_theta * C_theta * J_piReport_theta.transpose();
  bu = UncertaintyOf(in_report, u.body_pi_covariance[e]);

  // Rows of d(quantity)/d(pi_report): mass, COM and I_C from J_mci_pi, then I_O entries.
  Matrix10 J_mci_pi;
  MassComInertiaAboutCom(in_report, &J_mci_pi);
  Eigen::Matrix<double, 16, 10> G_pi = Eigen::Matrix<double, 16, 10>::Zero();
  G_pi.topRows<10>() = J_mci_pi;
  G_pi.bottomRows<6>().rightCols<6>().setIdentity();
  const Eigen::Matrix<double, 16, 10> G_theta = G_pi * J_piReport_theta;
  double* std_of[16] = {&bu.mass};
  for (int k = 0; k < 3; ++k) std_of[mci_index::kCx + k] = &bu.com[k];
  for (int k = 0; k < 6; ++k) {
    std_of[mci_index::kIxx + k] = &bu.inertia_about_com[k];
    std_of[10 + k] = &bu.inertia[k];
  }
  // The variance of each theta entry a CAD drawing's error gives (header, "honest spread").
  const InertialParams& prior = body.prior;
  const Vector3 c0 = prior.com();
  const double rho0 =
      std::sqrt(std::max(0.0, (prior.second_moments_about_origin() - prior.mass() * c0 * c0.transpose()).trace() / prior.mass()));
  Vector10 cad_variance;
  cad_variance << kCadSpreadAlpha * kCadSpreadAlpha, Vector6::Constant(kCadSpreadShape * kCadSpreadShape),
      Vector3::Constant(std::pow(kCadSpreadTranslation * rho0, 2));
  // Held: the prior's share of the posterior variance exceeds the data's. With y = H^+ g,
  // v_post = y^T H y = y^T H_data y + sum_b y_b^T H_prior,b y_b (over s^2).
  bool held[10] = {};
  double fit_std[10];
  for (int q = 0; q < 10; ++q) fit_std[q] = -1.0;  // set where a quantity is judged held or not
  for (int q = 0; q < 16; ++q) {
    const Eigen::VectorXd g = G_theta.row(q).transpose();
    if (block != nullptr) *std_of[q] = std::sqrt(std::max(0.0, block->Variance(first, g)));
    if (block != nullptr && q < 10 && prior_weight == 0.0 && std::isfinite(*std_of[q])) {
      u.max_block_to_white_ratio = std::max(u.max_block_to_white_ratio, block->Ratio(first, g));
    }
    if (TouchesUndetermined(scaled, first, g)) *std_of[q] = kInfinity;
    if (q >= 10 || prior_weight == 0.0 || std::isinf(*std_of[q])) continue;
    const Eigen::VectorXd y = H_pinv.middleCols(first, 10) * g;
    double prior_share = 0.0;
    for (int b = 0; b < B; ++b) {
      if (frozen(b)) continue;
      const Vector10 y_b = y.segment<10>(position[10 * b]);
      prior_share += y_b.dot(H_prior[b] * y_b);
    }
    held[q] = prior_share > y.dot(H_data * y);
    fit_std[q] = *std_of[q];
    if (held[q]) *std_of[q] = std::max(*std_of[q], std::sqrt(g.dot(cad_variance.cwiseProduct(g))));
    if (block != nullptr && !held[q]) {
      u.max_block_to_white_ratio = std::max(u.max_block_to_white_ratio, block->Ratio(first, g));
    }
  }
  // The same without the CAD spread's floor (what the fit's curvature and the residual alone say).
  BodyUncertainty& from_fit = u.bodies_from_fit[e];
  from_fit = bu;
  double* from_fit_of[10] = {&from_fit.mass};
  for (int k = 0; k < 3; ++k) from_fit_of[mci_index::kCx + k] = &from_fit.com[k];
  for (int k = 0; k < 6; ++k) from_fit_of[mci_index::kIxx + k] = &from_fit.inertia_about_com[k];
  for (int q = 0; q < 10; ++q) {
    if (fit_std[q] >= 0.0) *from_fit_of[q] = fit_std[q];
  }
  BodyHeldByPrior& h = u.body_held[e];
  h.mass = held[mci_index::kMass];
  for (int k = 0; k < 3; ++k) h.com[k] = held[mci_index::kCx + k];
  for (int k = 0; k < 6; ++k) h.inertia_about_com[k] = held[mci_index::kIxx + k];
}

// Effect k's standard deviations: each physical value's from the std of its parameter.
std::vector<double> EffectUncertaintyOfTheFit(const RobotDynamics& model, const Eigen::VectorXd& x, int k,
                                              const FreeParameters& free, const Eigen::MatrixXd& C_free,
                                              const std::vector<bool>& undetermined_parameter,
                                              const BlockVariances* block, double* max_ratio) {
  const std::vector<int>& position = free.position;
  const EffectTerm& t = model.effects()[k];
  const std::vector<double> values = model.EffectValues(k, x);
  std::vector<double> stds(values.size());
  for (int i = 0; i < static_cast<int>(values.size()); ++i) {
    const int p = position[t.first_parameter + i];
    double variance = C_free(p, p);
    if (block != nullptr) {
      const Eigen::VectorXd unit = Eigen::VectorXd::Ones(1);
      variance = block->Variance(p, unit);
      if (!undetermined_parameter[p]) *max_ratio = std::max(*max_ratio, block->Ratio(p, unit));
    }
    const double sd = std::sqrt(std::max(0.0, variance));
    // Exponential coefficients (every one but an offset and a spring's q0): d(e^s)/ds = e^s.
    const bool exponential = t.kind != EffectKind::kOffset && (i == 0 || t.kind != EffectKind::kSpring);
    stds[i] = undetermined_parameter[p] ? kInfinity : exponential ? values[i] * sd : sd;
  }
  return stds;
}

// The block sandwich (file comment): Omega from the blocks' centred scores, and the white-noise
// and block covariances of the estimated parameters.
BlockVariances BlockSandwich(const RobotDynamics& model, const TimeBlocks& blocks, const Eigen::VectorXd& w,
                             const Eigen::MatrixXd& J_w_x, const FreeParameters& free, const FitHessian& hessian,
                             const Eigen::MatrixXd& H_pinv, double s2, double rows, double p_eff,
                             double data_samples) {
  const int F = model.num_features(), n = free.size();
  const int K = static_cast<int>(blocks.blocks.size());
  Eigen::MatrixXd J_w_free(F, n);
  for (int i = 0; i < n; ++i) J_w_free.col(i) = J_w_x.col(free.index[i]);
  Eigen::MatrixXd scores(n, K);
  double samples = 0.0;
  for (int k = 0; k < K; ++k) {
    const JointNormalEquations& b = blocks.blocks[k];
    scores.col(k) = J_w_free.transpose() * (b.AtA * w - b.Atb);
    samples += b.num_samples;
  }
  const Eigen::VectorXd G = scores.rowwise().sum();
  for (int k = 0; k < K; ++k) {
    const double share = samples > 0.0 ? blocks.blocks[k].num_samples / samples : 1.0 / K;
    scores.col(k) -= share * G;
  }
  // Blocks of only a part of the data (a restored online fit: the header): their spread per
  // sample taken for every sample's, N / N_blocks.
  const double coverage = samples > 0.0 ? std::max(1.0, data_samples / samples) : 1.0;
  const double c = coverage * static_cast<double>(K) / (K - 1) * rows / std::max(1.0, rows - p_eff);
  const Eigen::MatrixXd omega = c * scores * scores.transpose();
  BlockVariances v;
  v.laplace = s2 * H_pinv;
  const Eigen::MatrixXd H_prior = hessian.total - hessian.data;
  v.block = s2 * H_pinv * H_prior * H_pinv + H_pinv * omega * H_pinv;
  v.block = 0.5 * (v.block + v.block.transpose());
  return v;
}

// The covariance reported as a matrix (file comment): C_laplace + (C_block - C_laplace)_+, the
// positive part taken in the Jacobi-scaled coordinates; its quadratic forms are at least both.
Eigen::MatrixXd ReportedCovariance(const ScaledHessian& scaled, const BlockVariances& v) {
  const int n = static_cast<int>(v.laplace.rows());
  if (n == 0) return v.laplace;
  // M in scaled coordinates (D^1/2 M D^1/2), its positive part, back.
  const Eigen::VectorXd sqrt_diag = scaled.inv_sqrt_diag.cwiseInverse();
  const Eigen::MatrixXd M = sqrt_diag.asDiagonal() * (v.block - v.laplace) * sqrt_diag.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (M + M.transpose()));
  const Eigen::VectorXd positive = eig.eigenvalues().cwiseMax(0.0);
  const Eigen::MatrixXd M_plus = eig.eigenvectors() * positive.asDiagonal() * eig.eigenvectors().transpose();
  return v.laplace + scaled.inv_sqrt_diag.asDiagonal() * M_plus * scaled.inv_sqrt_diag.asDiagonal();
}

// The coefficients' covariance and its parts (header, "Combinations"): each part of x's
// covariance pushed through J_w (frozen bodies' columns left out: their coefficients are fixed).
// J_w is block diagonal (10 x 10 per body, 1 or 2 per effect) and H_prior block diagonal per
// body: as sparse matrices their products cost O(n^2), and the one dense product left is
// H^-1 (H_prior H^-1); the data's part is then s^2 H^-1 - the prior's (H^-1 H H^-1 = H^-1). At 91
// coefficients (a 7-joint arm with three effects) it takes 0.35 ms (dense products: 2 ms; the
// rest of EstimateFitUncertainty 12 ms).
CoefficientCovariance CoefficientCovarianceOfTheFit(const Eigen::MatrixXd& J_w_x, const FreeParameters& free,
                                                    const FitHessian& hessian, const ScaledHessian& scaled,
                                                    const Eigen::MatrixXd& H_pinv, const Eigen::MatrixXd& C_free,
                                                    double s2, const BlockVariances* block, double prior_weight) {
  const int F = static_cast<int>(J_w_x.rows()), n = free.size();
  Eigen::MatrixXd J_dense(F, n);
  for (int i = 0; i < n; ++i) J_dense.col(i) = J_w_x.col(free.index[i]);
  const Eigen::SparseMatrix<double> J = J_dense.sparseView(0.0, 0.0);  // exact zeros only
  auto push = [&](const Eigen::MatrixXd& C_x) -> Eigen::MatrixXd {  // J C_x J^T, symmetrized
    const Eigen::MatrixXd C = J * (J * C_x).transpose();  // C_x symmetric: (J C_x)^T = C_x J^T
    return 0.5 * (C + C.transpose());
  };
  const Eigen::SparseMatrix<double> H_prior = (hessian.total - hessian.data).sparseView(0.0, 0.0);
  const Eigen::MatrixXd prior_x = s2 * H_pinv * (H_prior * H_pinv);
  CoefficientCovariance c;
  c.total = push(C_free);
  c.prior = push(prior_x);
  c.data = push(s2 * H_pinv) - c.prior;
  // BlockVariances::block is the prior's part plus H^-1 Omega H^-1.
  if (block != nullptr) c.block_data = push(block->block) - c.prior;
  const Eigen::SparseMatrix<double> J_scaled =
      (J_dense * scaled.inv_sqrt_diag.asDiagonal()).sparseView(0.0, 0.0);
  c.undetermined_moves = J_scaled * scaled.undetermined;
  // Sparse times dense: Eigen's sparse-sparse product took 4 ms here at 91 coefficients.
  c.scaled_gradient_gram = J_scaled * Eigen::MatrixXd(J_scaled.transpose());
  c.prior_acts = prior_weight > 0.0;
  return c;
}

}  // namespace

CombinationUncertainty UncertaintyOfCombination(const CoefficientCovariance& c, const Eigen::VectorXd& k) {
  if (k.size() != c.total.rows() || !k.allFinite()) {
    throw std::invalid_argument("combination uncertainty: k must be " + std::to_string(c.total.rows()) +
                                " finite numbers (one per coefficient)");
  }
  CombinationUncertainty r;
  if (c.undetermined_moves.cols() > 0) {
    // As TouchesUndetermined: g = J_w^T k, D^-1/2 g's component along Z against its length.
    const double along = (c.undetermined_moves.transpose() * k).norm();
    if (along > kUndeterminedComponent * std::sqrt(std::max(0.0, k.dot(c.scaled_gradient_gram * k)))) {
      r.std = kInfinity;
      return r;
    }
  }
  const double v_prior = k.dot(c.prior * k), v_data = k.dot(c.data * k);
  const double v_block = c.block_data.size() > 0 ? k.dot(c.block_data * k) : 0.0;
  r.std = std::sqrt(std::max(0.0, v_prior + std::max(v_data, v_block)));
  r.held_by_prior = c.prior_acts && v_prior > v_data;
  return r;
}

FitUncertainty EstimateFitUncertainty(const RobotDynamics& model, const JointNormalEquations& data,
                                      const Eigen::VectorXd& x, double prior_weight,
                                      const std::vector<bool>& frozen_bodies) {
  return EstimateFitUncertainty(model, data, x, prior_weight, frozen_bodies, TimeBlocks{});
}

FitUncertainty EstimateFitUncertainty(const RobotDynamics& model, const JointNormalEquations& data,
                                      const Eigen::VectorXd& x, double prior_weight,
                                      const std::vector<bool>& frozen_bodies, const TimeBlocks& blocks) {
  CheckUncertaintyInputs(model, data, x, prior_weight, frozen_bodies);
  for (const JointNormalEquations& b : blocks.blocks) {
    if (b.AtA.rows() != model.num_features() || b.AtA.cols() != model.num_features() ||
        b.Atb.size() != model.num_features()) {
      throw std::invalid_argument("fit uncertainty: a time block's normal equations do not match the model's features");
    }
  }
  const int P = model.num_parameters();
  const int B = static_cast<int>(model.bodies().size());
  const FreeParameters free = ListFreeParameters(P, B, frozen_bodies);
  const int n = free.size();

  Eigen::MatrixXd J_w_x;
  const Eigen::VectorXd w = model.Coefficients(x, &J_w_x);
  const FitHessian hessian = HessianOfTheFit(model, data, x, prior_weight, free, J_w_x, frozen_bodies);
  const ScaledHessian scaled = DecomposeScaled(hessian.total);
  // H^+ in the unscaled parameters.
  const Eigen::MatrixXd H_pinv =
      scaled.inv_sqrt_diag.asDiagonal() * scaled.pseudo_inverse * scaled.inv_sqrt_diag.asDiagonal();

  FitUncertainty u;
  u.undetermined_directions = static_cast<int>(scaled.undetermined.cols());
  u.effective_parameters = (H_pinv.cwiseProduct(hessian.data)).sum();  // trace(H^+ H_data), both symmetric
  const double rows = static_cast<double>(data.num_samples) * model.num_dofs();
  u.dof = rows - u.effective_parameters;
  if (!(u.dof > 0.0)) {
    throw std::invalid_argument("fit uncertainty: " + std::to_string(rows) + " torque rows leave no residual " +
                                "degrees of freedom for " + std::to_string(u.effective_parameters) +
                                " effective parameters");
  }
  const double s2 = SquaredError(data, w) / u.dof;
  u.noise_sigma = std::sqrt(s2);

  Eigen::MatrixXd C_free = s2 * H_pinv;
  std::optional<BlockVariances> block;
  if (blocks.blocks.size() >= 2) {
    block = BlockSandwich(model, blocks, w, J_w_x, free, hessian, H_pinv, s2, rows, u.effective_parameters,
                          static_cast<double>(data.num_samples));
    C_free = ReportedCovariance(scaled, *block);
    u.time_blocks = static_cast<int>(blocks.blocks.size());
    u.block_length = blocks.block_length;
    u.correlation_time = blocks.correlation_time;
  }
  std::vector<bool> undetermined_parameter(n, false);
  for (int i = 0; i < n; ++i) {
    undetermined_parameter[i] = TouchesUndetermined(scaled, i, Eigen::VectorXd::Ones(1));
  }
  u.covariance = Eigen::MatrixXd::Zero(P, P);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      double c = C_free(i, j);
      if (undetermined_parameter[i] || undetermined_parameter[j]) {
        c = i == j ? kInfinity : std::numeric_limits<double>::quiet_NaN();
      }
      u.covariance(free.index[i], free.index[j]) = c;
    }
  }

  u.bodies.assign(B, BodyUncertainty());
  u.bodies_from_fit.assign(B, BodyUncertainty());
  u.body_held.assign(B, BodyHeldByPrior());
  u.body_pi_covariance.assign(B, Matrix10::Zero());
  for (int e = 0; e < B; ++e) {
    if (!frozen_bodies.empty() && frozen_bodies[e]) continue;
    BodyUncertaintyOfTheFit(model, x, e, free, hessian, scaled, H_pinv, C_free, prior_weight, frozen_bodies, u,
                            block ? &*block : nullptr);
  }
  for (int k = 0; k < static_cast<int>(model.effects().size()); ++k) {
    u.effects.push_back(EffectUncertaintyOfTheFit(model, x, k, free, C_free, undetermined_parameter,
                                                  block ? &*block : nullptr, &u.max_block_to_white_ratio));
  }
  u.coefficients = CoefficientCovarianceOfTheFit(J_w_x, free, hessian, scaled, H_pinv, C_free, s2,
                                                 block ? &*block : nullptr, prior_weight);
  return u;
}

}  // namespace inertial
