#include "inertial/diagnosis/model_comparison.hpp"

#include <cmath>
#include <stdexcept>

#include "inertial/model/number_text.hpp"
#include "inertial/signal/sample_selection.hpp"

namespace inertial {
namespace {

constexpr int kNamedRows = 3;

// Keeps the finite rows of v.signals / v.predicted, naming the others; throws if none is left.
void LeaveOutNonFinite(ModelComparison* v) {
  const std::vector<int> bad = NonFiniteRows(v->predicted, v->signals);
  if (bad.empty()) return;
  const JointSamples& s = v->signals;
  for (int k = 0; k < static_cast<int>(bad.size()) && k < kNamedRows; ++k) {
    const int i = bad[k];
    std::string what = "the model's prediction";
    for (int j = 0; j < s.tau.cols(); ++j) {
      if (!(std::abs(s.tau(i, j)) < kLargestSquarable)) what = "tau_" + v->channels[j];
      if (!std::isfinite(s.qd(i, j))) what = "qd_" + v->channels[j];
    }
    v->left_out_reasons.push_back("sample " + std::to_string(i) + " (t = " + FormatNumber(s.t[i], 10) + " s): " + what +
                                  " is not finite or too large to square");
  }
  if (static_cast<int>(bad.size()) == s.size()) {
    throw std::invalid_argument("no sample gives a finite prediction (first: " + v->left_out_reasons.front() +
                                "): a coefficient or inertia of the model is too large, or the log's values are");
  }
  const std::vector<int> keep = RowsExcept(s.size(), bad);
  Eigen::MatrixXd predicted(static_cast<int>(keep.size()), v->predicted.cols());
  for (int r = 0; r < static_cast<int>(keep.size()); ++r) predicted.row(r) = v->predicted.row(keep[r]);
  v->predicted = predicted;
  v->signals = SelectSamples(s, keep);
  v->left_out = static_cast<int>(bad.size());
}

// The errors and the residual analysis of v's (finite) predictions.
void Compare(ModelComparison* v) {
  LeaveOutNonFinite(v);
  v->errors = CompareTorques(v->predicted, v->signals.tau);
  v->residuals = AnalyzeResiduals(v->signals, v->predicted, kFailureWindowSeconds, kWorstFailureWindows);
}

}  // namespace

std::vector<int> NonFiniteRows(const Eigen::MatrixXd& predicted, const JointSamples& data) {
  std::vector<int> rows;
  const int n = static_cast<int>(data.tau.cols());
  for (int i = 0; i < data.size(); ++i) {
    bool bad = !predicted.row(i).allFinite() || !data.q.row(i).allFinite() || !data.qd.row(i).allFinite() ||
               !data.qdd.row(i).allFinite() || !data.tau.row(i).allFinite() || !std::isfinite(data.t[i]);
    // A torque or an error whose square overflows (1e300 from a glitch) would make the RMS inf
    // and the relative error NaN.
    for (int c = 0; c < predicted.cols() && n > 0 && !bad; ++c) {
      bad = !(std::abs(data.tau(i, c % n)) < kLargestSquarable) ||
            !(std::abs(predicted(i, c) - data.tau(i, c % n)) < kLargestSquarable);
    }
    if (bad) rows.push_back(i);
  }
  return rows;
}

ModelComparison CompareJointModel(const RobotDynamics& model, const Eigen::VectorXd& x, const JointSamples& data) {
  ModelComparison v;
  v.channels = model.dof_names();
  v.unit = "N m";
  v.predicted = PredictJointTorques(model, x, data);
  v.signals = data;
  Compare(&v);
  return v;
}

std::vector<ModelComparison> CompareJointModelByRun(const RobotDynamics& model, const Eigen::VectorXd& x,
                                                    const RecordedRuns& runs) {
  std::vector<ModelComparison> out;
  for (int k = 0; k < runs.num_runs(); ++k) {
    try {
      out.push_back(CompareJointModel(model, x, runs.Run(k)));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(runs.names[static_cast<size_t>(k)] + ": " + e.what());
    }
  }
  return out;
}

ModelComparison CompareBodyModel(const BodyEffectModel& model, const Eigen::VectorXd& x, const BodyLog& data) {
  const int P = data.num_pairs();
  if (P < 1) throw std::invalid_argument("single-body validation needs at least 2 samples");
  if (x.size() != model.num_parameters()) throw std::invalid_argument("single-body validation: wrong parameter count");
  ModelComparison v;
  v.channels = {"mx", "my", "mz", "fx", "fy", "fz"};
  v.unit = "N m | N";
  JointSamples& s = v.signals;
  s.joint_names = v.channels;
  s.t.resize(P);
  s.q = s.qdd = Eigen::MatrixXd::Zero(P, 6);
  s.qd.resize(P, 6);
  s.tau.resize(P, 6);
  for (int i = 0; i < P; ++i) {
    s.t[i] = 0.5 * (data.samples[i].t + data.samples[i + 1].t);
    s.qd.row(i) = (0.5 * (data.samples[i].twist + data.samples[i + 1].twist)).transpose();
    s.tau.row(i) = BodyEffectModel::MeasuredPair(data, i).transpose();
  }
  v.predicted = model.Residuals(x, data) + s.tau;
  Compare(&v);
  return v;
}

}  // namespace inertial
