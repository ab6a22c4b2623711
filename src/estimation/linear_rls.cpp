#include "inertial/estimation/linear_rls.hpp"

#include <stdexcept>

namespace inertial {

LinearRls::LinearRls(int num_measurements, const Eigen::VectorXd& w0, const Eigen::VectorXd& initial_std,
                     const KalmanOptions& options)
    : RecursiveEstimator(static_cast<int>(w0.size()), num_measurements),
      kalman_(static_cast<int>(w0.size()), num_measurements, initial_std, options),
      w_(w0) {
  if (!w0.allFinite()) throw std::invalid_argument("linear RLS: w0 must be finite");
  r_.resize(num_measurements);
}

UpdateStatus LinearRls::Apply(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) {
  r_ = y;
  r_.noalias() -= A * w_;
  const UpdateStatus status = kalman_.Step(A, r_);
  if (status != UpdateStatus::kAccepted) return status;
  w_ += kalman_.step();
  kalman_.Commit();
  return UpdateStatus::kAccepted;
}

bool LinearRls::SetParameters(const Eigen::VectorXd& x, const Eigen::MatrixXd& P, std::string* why) {
  if (!kalman_.SetCovariance(P)) {
    if (why != nullptr) *why = "the covariance is missing, of the wrong size or not finite";
    return false;
  }
  w_ = x;
  return true;
}

}  // namespace inertial
