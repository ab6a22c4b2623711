/// @file smallest_eigenvalue.hpp
/// The smallest eigenvalue of a symmetric matrix, without the others.
///
/// Levenberg-Marquardt on a Newton Hessian (dense_levenberg_marquardt.hpp) needs, when the damped
/// matrix is not positive definite, just the smallest eigenvalue, to damp just enough (and never
/// too little: a lower bound). A full symmetric eigensolver finds every eigenvalue by QR
/// iterations after the same reduction. Here: Householder tridiagonalization T = Q^T S Q (Eigen::Tridiagonalization), then bisection on
/// the Sturm sequence of T (the number of negative pivots of the LDL^T factorization of T - x I is
/// the number of eigenvalues below x; Golub and Van Loan, Matrix Computations, 4th ed., 8.4.1),
/// starting from T's Gershgorin interval and stopping at the resolution of doubles. O(n^3) for the
/// reduction (as the full solver) plus O(n) per bisection step.
#pragma once

#include <Eigen/Core>

namespace inertial {

/// The smallest eigenvalue lambda of the symmetric matrix S (its lower triangle is read), from
/// below: a value x <= lambda with lambda - x <= relative_tolerance |lambda| + a few units in the
/// last place of max |eigenvalue| (0: as close as doubles resolve). NaN if S has a non-finite entry.
/// @throws std::invalid_argument if S is not square or is empty, or the tolerance is negative.
double SmallestEigenvalue(const Eigen::MatrixXd& S, double relative_tolerance = 0.0);

}  // namespace inertial
