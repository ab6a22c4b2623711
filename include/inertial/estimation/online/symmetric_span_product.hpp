/// @file symmetric_span_product.hpp
/// The kernel of the Kalman update's P H^T (kalman_update.hpp): four columns of
///
///   out = sym(P) G,     G: rows [c, e) nonzero, the others zero,
///
/// reading only the lower triangle of the symmetric P. Each element P(t, s), t > s, of the
/// triangle is used twice (out(t, .) += P(t, s) G(s, .) when s is in the span, out(s, .) +=
/// P(t, s) G(t, .) when t is), and for all four columns at once, so that every element loaded
/// serves eight multiply-adds: 4 n (e - c) of them for the four columns, nothing outside the span.
/// Written with Eigen's packet primitives (AVX on x86-64, NEON on Arm) rather than Eigen's
/// products: its blocked SYMM/GEMM would need packing buffers that exceed the stack allowance at a
/// humanoid's size and are then allocated on the heap, and its coefficient-based products reload
/// every element once per output. No allocation, no exception.
/// Preconditions (debug-asserted): P square with a size that is a multiple of 4; c and e multiples
/// of 4 with 0 <= c <= e <= size; G and out of P's size by 4 columns.
#pragma once

#include <Eigen/Core>

namespace inertial {

/// Columns of the products, rows of P's panels and spans' granularity.
inline constexpr int kSpanBlock = 4;

/// out = sym(P) G over G's rows [c, e) (see the file comment).
/// P may be a square block of a larger matrix (a diagonal block [c, e) x [c, e) of P with G's and
/// out's rows [c, e) gives those rows of sym(P) G when G is zero outside them: a quadratic form
/// over a span costs (e - c)^2, not n (e - c)).
void SymmetricSpanProduct(const Eigen::Ref<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>& P,
                          const Eigen::Ref<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>& G, int c, int e,
                          Eigen::Ref<Eigen::MatrixXd, 0, Eigen::OuterStride<>> out);

/// The span [first, end) of v's nonzero entries (first == end == 0 for a zero vector): a
/// regressor row of a robot is nonzero only over the bodies its joint carries and its own effects.
void NonzeroSpan(const Eigen::Ref<const Eigen::VectorXd>& v, int* first, int* end);

}  // namespace inertial
