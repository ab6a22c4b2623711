/// @file symmetric_rank_update.hpp
/// The kernel of the Kalman update's covariance step (kalman_update.hpp), on the lower triangle of
/// the symmetric P:
///
///   P <- D P D - f W W^T,     D = diag(d),
///
/// that is the prediction of the next sample (forgetting: d_i = lambda^-1/2 below the variance cap)
/// and the rank-m downdate of this one in a single pass over P, which at a robot's size no longer
/// fits the first-level cache: each element is loaded and stored once per sample instead of twice
/// (a forgetting pass, then Eigen's SYRK with its packing of W). Columns of P four at a time, rows
/// eight (two AVX packets, four NEON packets) at a time: every W packet loaded serves four columns
/// and every broadcast two row packets, so the loop is bound by multiply-adds, not loads.
/// The strictly upper triangle is neither read nor written. Written with Eigen's packet primitives
/// (AVX on x86-64, NEON on Arm); no allocation, no exception.
/// Preconditions (debug-asserted): P square with a size that is a multiple of kSpanBlock
/// (symmetric_span_product.hpp), d and W of P's rows, W with at least one column.
#pragma once

#include <Eigen/Core>

namespace inertial {

/// P <- diag(d) P diag(d) - f W W^T on the lower triangle of P (see the file comment).
void ScaledSymmetricRankUpdate(Eigen::MatrixXd& P, const Eigen::VectorXd& d,
                               const Eigen::Ref<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>& W, double f);

}  // namespace inertial
