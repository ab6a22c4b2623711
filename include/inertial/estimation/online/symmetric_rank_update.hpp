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
/// P may be a square block of a larger matrix (a diagonal block over the span of W's nonzero rows).
void ScaledSymmetricRankUpdate(Eigen::Ref<Eigen::MatrixXd, 0, Eigen::OuterStride<>> P, const Eigen::Ref<const Eigen::VectorXd>& d,
                               const Eigen::Ref<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>& W, double f);

/// P <- P - f W W^T on the lower triangle of P, where W's column k is zero above row first[k] and
/// first is ascending (W's columns sorted by where they begin; ones: n ones, the kernel's unit
/// scaling). Column block j of P is updated with only the columns that have begun by its last
/// column, in one pass over P: for a robot's block-triangular regressor (a joint's row is zero over
/// the bodies before it), about F^2 m / 6 multiply-adds instead of F^2 m / 2 for a serial chain.
void SymmetricSpanRankUpdate(Eigen::Ref<Eigen::MatrixXd, 0, Eigen::OuterStride<>> P,
                             const Eigen::Ref<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>& W, const int* first,
                             const Eigen::Ref<const Eigen::VectorXd>& ones, double f);

}  // namespace inertial
