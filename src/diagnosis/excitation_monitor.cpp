#include "inertial/diagnosis/excitation_monitor.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>

#include "inertial/estimation/fit_uncertainty.hpp"
#include "inertial/estimation/parameter_layout.hpp"
#include "inertial/inertia/assert.hpp"
#include "inertial/model/number_text.hpp"

namespace inertial {

namespace {

// mci order (parameter_layout.hpp): mass, COM, inertia about the COM.
constexpr const char* kBodyQuantityNames[10] = {"m", "cx", "cy", "cz", "Ixx", "Iyy", "Izz", "Ixy", "Iyz", "Ixz"};

// "a", "a and b", "a, b and c".
std::string JoinEnglish(const std::vector<std::string>& items) {
  std::string s;
  for (size_t i = 0; i < items.size(); ++i) {
    if (i > 0) s += i + 1 == items.size() ? " and " : ", ";
    s += items[i];
  }
  return s;
}

// The unexcited quantities of one scope as listed items, one per body or effect term: "all of
// <group>" when none of its three or more quantities is excited, else "<group>.<a>/<b>/<c>"; beyond
// max_items, the rest is counted. *count gets the number of quantities.
std::vector<std::string> UnexcitedItems(const ExcitationReport& report, bool since_start, int max_items, int* count) {
  const auto unexcited = [&](const QuantityExcitation& q) {
    return since_start ? !q.excited_since_start : !q.excited_window;
  };
  std::vector<std::string> items;
  std::vector<int> item_sizes;
  *count = 0;
  const auto& qs = report.quantities;
  for (size_t i = 0; i < qs.size();) {
    size_t end = i;
    int in_group = 0;
    while (end < qs.size() && qs[end].group == qs[i].group) {
      in_group += unexcited(qs[end]) ? 1 : 0;
      ++end;
    }
    const int group_size = static_cast<int>(end - i);
    if (group_size >= 3 && in_group == group_size) {
      items.push_back("all of " + qs[i].group);
    } else if (in_group > 0) {
      // "thigh.m/Ixx/Iyy": the group once, then its quantities' own names.
      std::string item;
      for (size_t k = i; k < end; ++k) {
        if (!unexcited(qs[k])) continue;
        item += item.empty() ? qs[k].name : "/" + qs[k].name.substr(qs[k].group.size() + 1);
      }
      items.push_back(item);
    }
    if (in_group > 0) item_sizes.push_back(in_group);
    *count += in_group;
    i = end;
  }
  const int limit = std::max(max_items, 1);
  if (static_cast<int>(items.size()) > limit) {
    int rest = 0;
    for (size_t k = limit - 1; k < items.size(); ++k) rest += item_sizes[k];
    items.resize(limit - 1);
    items.push_back(std::to_string(rest) + " more quantities");
  }
  return items;
}

}  // namespace

ExcitationMonitor::ExcitationMonitor(const RobotDynamics& model, const Eigen::VectorXd& measurement_sigma,
                                     const Eigen::MatrixXd& prior_covariance, const ExcitationOptions& options)
    : model_(model), options_(options), sigma_(measurement_sigma) {
  const int m = model_.num_dofs(), F = model_.num_features(), P = model_.num_parameters();
  if (sigma_.size() != m) {
    throw std::invalid_argument("excitation monitor: measurement_sigma has " + std::to_string(sigma_.size()) +
                                " entries, the model has " + std::to_string(m) + " DOFs");
  }
  for (int i = 0; i < m; ++i) {
    if (!(sigma_[i] > 0.0) || !std::isfinite(sigma_[i])) {
      throw std::invalid_argument("excitation monitor: measurement_sigma of " + model_.dof_names()[i] + " is " +
                                  std::to_string(sigma_[i]) + ", must be positive and finite");
    }
  }
  if (!(options_.window_seconds > 0.0) || !std::isfinite(options_.window_seconds)) {
    throw std::invalid_argument("excitation monitor: window_seconds is " + std::to_string(options_.window_seconds) +
                                ", must be positive and finite");
  }
  if (options_.num_blocks < 1) {
    throw std::invalid_argument("excitation monitor: num_blocks is " + std::to_string(options_.num_blocks) +
                                ", must be at least 1");
  }
  if (!(options_.excited_ratio > 0.0 && options_.excited_ratio < 1.0)) {
    throw std::invalid_argument("excitation monitor: excited_ratio is " + std::to_string(options_.excited_ratio) +
                                ", must lie in (0, 1)");
  }
  if (prior_covariance.rows() != P || prior_covariance.cols() != P) {
    throw std::invalid_argument("excitation monitor: the prior covariance is " +
                                std::to_string(prior_covariance.rows()) + " x " +
                                std::to_string(prior_covariance.cols()) + ", the model has " + std::to_string(P) +
                                " parameters");
  }
  if (!prior_covariance.allFinite()) {
    throw std::invalid_argument("excitation monitor: the prior covariance is not finite");
  }
  const double asymmetry = (prior_covariance - prior_covariance.transpose()).cwiseAbs().maxCoeff();
  if (asymmetry > 1e-12 * prior_covariance.cwiseAbs().maxCoeff()) {
    throw std::invalid_argument("excitation monitor: the prior covariance is not symmetric (largest |P - P^T| " +
                                std::to_string(asymmetry) + ")");
  }
  P0_ = 0.5 * (prior_covariance + prior_covariance.transpose());
  const Eigen::LLT<Eigen::MatrixXd> llt(P0_);
  if (llt.info() != Eigen::Success) {
    throw std::invalid_argument("excitation monitor: the prior covariance is not positive definite");
  }
  L0_ = llt.matrixL();
  inverse_sigma_ = sigma_.cwiseInverse();
  block_seconds_ = options_.window_seconds / options_.num_blocks;

  for (const EstimatedBody& b : model_.bodies()) {
    for (const char* n : kBodyQuantityNames) {
      names_.push_back(b.name + "." + n);
      groups_.push_back(b.name);
    }
  }
  for (const EffectTerm& t : model_.effects()) {
    const std::string group = std::string(ToString(t.kind)) + "@" + t.joint;
    for (const std::string& n : EffectValueNames(t.kind)) {
      names_.push_back(group + "." + n);
      groups_.push_back(group);
    }
  }

  current_ = Eigen::MatrixXd::Zero(F, F);
  closed_total_ = Eigen::MatrixXd::Zero(F, F);
  ring_.assign(options_.num_blocks, Eigen::MatrixXd::Zero(F, F));
  ring_weight_.assign(options_.num_blocks, 0.0);
  scaled_ = Eigen::MatrixXd::Zero(m, F);
  transposed_ = Eigen::MatrixXd::Zero(F, m);
  row_first_ = Eigen::VectorXi::Zero(F);
  row_last_ = Eigen::VectorXi::Zero(F);
}

void ExcitationMonitor::Reset() noexcept {
  current_.setZero();
  closed_total_.setZero();
  for (Eigen::MatrixXd& block : ring_) block.setZero();
  std::fill(ring_weight_.begin(), ring_weight_.end(), 0.0);
  current_weight_ = closed_weight_ = 0.0;
  current_block_ = closed_blocks_ = 0;
  has_time_ = false;
  first_time_ = last_time_ = 0.0;
  accepted_ = 0;
}

void ExcitationMonitor::CloseBlocks(std::int64_t up_to_block) noexcept {
  const std::int64_t n = options_.num_blocks;
  if (current_block_ >= up_to_block) return;
  // The current block goes into the ring (a swap: no copy, no allocation) and the since-start sum.
  const int slot = static_cast<int>(current_block_ % n);
  closed_total_.triangularView<Eigen::Lower>() += current_;
  closed_weight_ += current_weight_;
  ring_[slot].swap(current_);
  ring_weight_[slot] = current_weight_;
  current_.setZero();
  current_weight_ = 0.0;
  ++current_block_;
  ++closed_blocks_;
  // Blocks without samples: each empties the oldest slot; after n of them the ring is empty.
  const std::int64_t empty = up_to_block - current_block_;
  const std::int64_t to_clear = std::min(empty, n);
  for (std::int64_t b = 0; b < to_clear; ++b) {
    const int s = static_cast<int>((current_block_ + b) % n);
    ring_[s].setZero();
    ring_weight_[s] = 0.0;
  }
  current_block_ = up_to_block;
  closed_blocks_ += empty;
}

UpdateStatus ExcitationMonitor::Add(double t, const Eigen::MatrixXd& A, double weight) noexcept {
  const int m = model_.num_dofs(), F = model_.num_features();
  if (A.rows() != m || A.cols() != F) return UpdateStatus::kWrongSize;
  if (!std::isfinite(t) || !A.allFinite()) return UpdateStatus::kNonFinite;
  if (has_time_ && !(t > last_time_)) return UpdateStatus::kOutOfOrder;
  if (!(weight > 0.0) || !std::isfinite(weight)) return UpdateStatus::kNumerical;

  if (!has_time_) {
    has_time_ = true;
    first_time_ = t;
  } else {
    // The block t falls in, counted from the first sample; far-future times saturate (every block
    // then expires, which is what they mean).
    const double index = std::floor((t - first_time_) / block_seconds_);
    const std::int64_t block = index < 4e18 ? static_cast<std::int64_t>(index) : static_cast<std::int64_t>(4e18);
    CloseBlocks(block);
  }
  last_time_ = t;
  ++accepted_;
  current_weight_ += weight;

  // B = sqrt(weight) S^-1 A; the block's lower triangle gets B^T B over, per column, only the rows
  // where the column is non-zero (a body's columns vanish on joints that do not carry it, an
  // effect's on every joint but its own, a velocity feature's on a joint at rest).
  scaled_.noalias() = (std::sqrt(weight) * inverse_sigma_).asDiagonal() * A;
  for (int j = 0; j < F; ++j) {
    int first = 0, last = m - 1;
    while (first < m && scaled_(first, j) == 0.0) ++first;
    while (last > first && scaled_(last, j) == 0.0) --last;
    row_first_[j] = first;  // first == m: a zero column
    row_last_[j] = first < m ? last : -1;
  }
  // Panels of neighbouring columns with the same rows (a body's ten, usually) take one product:
  // rows [k0, F) of columns [k0, k0 + width) get B(:, k0..)^T B(:, k0 .. k0 + width) over the rows
  // they share. The panel's strictly upper triangle is written too, and never read.
  for (int k0 = 0; k0 < F;) {
    const int first = row_first_[k0], last = row_last_[k0];
    int width = 1;
    while (k0 + width < F && row_first_[k0 + width] == first && row_last_[k0 + width] == last) ++width;
    if (first <= last) {
      const int rows = last - first + 1;
      transposed_.topRows(F - k0).leftCols(rows) = scaled_.block(first, k0, rows, F - k0).transpose();
      current_.block(k0, k0, F - k0, width).noalias() +=
          transposed_.topLeftCorner(F - k0, rows).lazyProduct(scaled_.block(first, k0, rows, width));
    }
    k0 += width;
  }
  return UpdateStatus::kAccepted;
}

ExcitationInformation ExcitationMonitor::MakeInformation() const {
  const int F = model_.num_features();
  ExcitationInformation info;
  info.window = Eigen::MatrixXd::Zero(F, F);
  info.since_start = Eigen::MatrixXd::Zero(F, F);
  return info;
}

void ExcitationMonitor::CopyInformation(ExcitationInformation* out) const {
  const int F = model_.num_features();
  out->window.resize(F, F);
  out->since_start.resize(F, F);
  out->window.triangularView<Eigen::Lower>() = current_;
  double window_weight = current_weight_;
  for (size_t s = 0; s < ring_.size(); ++s) {
    out->window.triangularView<Eigen::Lower>() += ring_[s];
    window_weight += ring_weight_[s];
  }
  out->since_start.triangularView<Eigen::Lower>() = closed_total_;
  out->since_start.triangularView<Eigen::Lower>() += current_;
  out->window.triangularView<Eigen::StrictlyUpper>() = out->window.transpose();
  out->since_start.triangularView<Eigen::StrictlyUpper>() = out->since_start.transpose();
  out->window_weight = window_weight;
  out->since_start_weight = closed_weight_ + current_weight_;
  if (has_time_) {
    const std::int64_t oldest = std::max<std::int64_t>(0, current_block_ - options_.num_blocks);
    out->window_seconds = last_time_ - (first_time_ + static_cast<double>(oldest) * block_seconds_);
    out->since_start_seconds = last_time_ - first_time_;
  } else {
    out->window_seconds = out->since_start_seconds = 0.0;
  }
}

Eigen::MatrixXd ExcitationMonitor::QuantityGradients(const Eigen::VectorXd& x) const {
  const int P = model_.num_parameters();
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(names_.size()), P);
  int row = 0;
  for (size_t e = 0; e < model_.bodies().size(); ++e) {
    const EstimatedBody& body = model_.bodies()[e];
    const int first = 10 * static_cast<int>(e);
    Matrix10 J_pi_theta;
    body.map.ToPi(x.segment<10>(first), &J_pi_theta);
    Matrix10 J_mci_pi;
    MassComInertiaAboutCom(model_.BodyInertia(static_cast<int>(e), x), &J_mci_pi);
    G.block<10, 10>(row, first) = J_mci_pi * ReportFrameMap(body) * J_pi_theta;
    row += 10;
  }
  for (const EffectTerm& t : model_.effects()) {
    const int p = t.first_parameter;
    switch (t.kind) {
      case EffectKind::kOffset:
        G(row++, p) = 1.0;
        break;
      case EffectKind::kSpring:
        G(row++, p) = std::exp(x[p]);
        G(row++, p + 1) = 1.0;
        break;
      case EffectKind::kAsymmetric:
        G(row++, p) = std::exp(x[p]);
        G(row++, p + 1) = std::exp(x[p + 1]);
        break;
      default:
        G(row++, p) = std::exp(x[p]);
        break;
    }
  }
  INERTIAL_ASSERT(row == G.rows());
  return G;
}

ExcitationReport ExcitationMonitor::Evaluate(const Eigen::VectorXd& x) const {
  ExcitationInformation info = MakeInformation();
  CopyInformation(&info);
  return Evaluate(x, info);
}

ExcitationReport ExcitationMonitor::Evaluate(const Eigen::VectorXd& x, const ExcitationInformation& info) const {
  const int F = model_.num_features(), P = model_.num_parameters();
  if (x.size() != P || !x.allFinite()) {
    throw std::invalid_argument("excitation monitor: x must be " + std::to_string(P) + " finite numbers");
  }
  if (info.window.rows() != F || info.window.cols() != F || info.since_start.rows() != F ||
      info.since_start.cols() != F) {
    throw std::invalid_argument("excitation monitor: the information must be " + std::to_string(F) + " x " +
                                std::to_string(F));
  }
  Eigen::MatrixXd J_w_x;
  model_.Coefficients(x, &J_w_x);
  // u_q = L0^T g_q: the prior variance of quantity q is |u_q|^2. With the information form
  // M = 1 + L0^T J^T F_w J L0 = Lm Lm^T (eigenvalues >= 1: well conditioned whatever F_w), the
  // posterior is Post = L0 M^-1 L0^T, so g^T Post g = |Lm^-1 u|^2 and ratio = |Lm^-1 u|^2 / |u|^2.
  const Eigen::MatrixXd U = L0_.transpose() * QuantityGradients(x).transpose();
  const Eigen::RowVectorXd prior_variance = U.colwise().squaredNorm();
  const Eigen::MatrixXd JL = J_w_x * L0_;  // F x P
  const auto ratios = [&](const Eigen::MatrixXd& information) {
    Eigen::MatrixXd M = JL.transpose() * information * JL;
    M = 0.5 * (M + M.transpose());
    M.diagonal().array() += 1.0;
    const Eigen::LLT<Eigen::MatrixXd> llt(M);
    const Eigen::MatrixXd V = llt.matrixL().solve(U);
    Eigen::RowVectorXd r = V.colwise().squaredNorm();
    for (Eigen::Index q = 0; q < r.size(); ++q) {
      r[q] = prior_variance[q] > 0.0 ? std::min(1.0, r[q] / prior_variance[q]) : 1.0;
    }
    return r;
  };
  const Eigen::RowVectorXd window = ratios(info.window);
  const Eigen::RowVectorXd since_start = ratios(info.since_start);

  ExcitationReport report;
  report.nominal_window_seconds = options_.window_seconds;
  report.window_seconds = info.window_seconds;
  report.since_start_seconds = info.since_start_seconds;
  report.window_weight = info.window_weight;
  report.since_start_weight = info.since_start_weight;
  report.threshold = options_.excited_ratio;
  report.quantities.resize(names_.size());
  for (size_t q = 0; q < names_.size(); ++q) {
    QuantityExcitation& e = report.quantities[q];
    e.name = names_[q];
    e.group = groups_[q];
    e.ratio_window = window[static_cast<Eigen::Index>(q)];
    e.ratio_since_start = since_start[static_cast<Eigen::Index>(q)];
    e.excited_window = e.ratio_window <= options_.excited_ratio;
    e.excited_since_start = e.ratio_since_start <= options_.excited_ratio;
  }
  return report;
}

std::vector<std::string> UnexcitedNames(const ExcitationReport& report, bool since_start) {
  std::vector<std::string> names;
  for (const QuantityExcitation& q : report.quantities) {
    if (since_start ? !q.excited_since_start : !q.excited_window) names.push_back(q.name);
  }
  return names;
}

std::string UnexcitedText(const ExcitationReport& report, int max_items) {
  if (report.since_start_weight <= 0.0) return "no samples yet: nothing is excited";
  int window_count = 0, start_count = 0;
  const std::vector<std::string> window_items = UnexcitedItems(report, false, max_items, &window_count);
  const std::vector<std::string> start_items = UnexcitedItems(report, true, max_items, &start_count);
  const auto sentence = [](const std::vector<std::string>& items, int count) {
    return JoinEnglish(items) + (count == 1 ? " is" : " are") + " not excited";
  };
  // A window shorter than nominal holds every sample since start (see CopyInformation): one scope.
  if (report.window_seconds + 1e-9 < report.nominal_window_seconds) {
    const std::string scope = "in the " + FormatNumber(report.window_seconds, 3) + " s since start";
    return window_count == 0 ? "every quantity is excited " + scope : sentence(window_items, window_count) + " " + scope;
  }
  const std::string window = "in the last " + FormatNumber(report.nominal_window_seconds, 3) + " s";
  if (window_count == 0 && start_count == 0) return "every quantity is excited " + window + " and since start";
  if (window_count == 0) {  // the window's samples are among since start's, so only by rounding
    return "every quantity is excited " + window + "; since start " + sentence(start_items, start_count);
  }
  const std::string text = sentence(window_items, window_count) + " " + window;
  if (start_count == 0) return text + "; since start every quantity is";
  if (UnexcitedNames(report, false) == UnexcitedNames(report, true)) return text + ", nor since start";
  return text + "; since start: " + JoinEnglish(start_items);
}

}  // namespace inertial
