#include "inertial/estimation/online/linear_rls.hpp"

#include <stdexcept>

namespace inertial {

template <int M, int F>
BasicLinearRls<M, F>::BasicLinearRls(int num_measurements, const Eigen::VectorXd& w0, const Eigen::VectorXd& initial_std,
                                     const KalmanOptions& options)
    : RecursiveEstimator(static_cast<int>(w0.size()), num_measurements),
      kalman_(static_cast<int>(w0.size()), num_measurements, initial_std, options),
      w_(w0) {
  if (!w0.allFinite()) throw std::invalid_argument("linear RLS: w0 must be finite");
  r_.resize(num_measurements);
}

template <int M, int F>
UpdateStatus BasicLinearRls<M, F>::Update(double t, const MatrixA& A, const VectorM& y) {
  const bool sizes_ok = A.rows() == num_measurements() && A.cols() == num_features() && y.size() == num_measurements();
  return Admit(t, sizes_ok, sizes_ok && A.allFinite() && y.allFinite(), [&] { return Step(A, y); });
}

template <int M, int F>
UpdateStatus BasicLinearRls<M, F>::Apply(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) {
  if constexpr (M == Eigen::Dynamic) {
    return Step(A, y);
  } else {
    return Step(MatrixA(A), VectorM(y));
  }
}

template <int M, int F>
UpdateStatus BasicLinearRls<M, F>::Step(const MatrixA& A, const VectorM& y) {
  r_ = y;
  r_.noalias() -= A * w_;
  const UpdateStatus status = kalman_.Step(A, r_);
  if (status != UpdateStatus::kAccepted) return status;
  w_ += kalman_.step();
  kalman_.Commit();
  return UpdateStatus::kAccepted;
}

template <int M, int F>
bool BasicLinearRls<M, F>::SetParameters(const Eigen::VectorXd& x, const Eigen::MatrixXd& P, std::string* why) {
  if (!kalman_.SetCovariance(P)) {
    if (why != nullptr) *why = "the covariance is missing, of the wrong size or not finite";
    return false;
  }
  w_ = x;
  return true;
}

template class BasicLinearRls<Eigen::Dynamic, Eigen::Dynamic>;
template class BasicLinearRls<6, 10>;

}  // namespace inertial
