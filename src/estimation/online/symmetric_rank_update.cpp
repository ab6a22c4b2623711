#include "inertial/estimation/online/symmetric_rank_update.hpp"

#include "inertial/estimation/online/symmetric_span_product.hpp"
#include "inertial/inertia/assert.hpp"

namespace inertial {

namespace {
using Packet = Eigen::internal::packet_traits<double>::type;
constexpr int kLanes = Eigen::internal::packet_traits<double>::size;  // doubles per Packet
static_assert(kSpanBlock % kLanes == 0, "a panel's rows must be whole packets");

// Rows [i, i + R kLanes) of the four columns j0 .. j0+3 (all below the diagonal block):
// P(t, j) <- d_t d_j P(t, j) - f sum_k W(t, k) W(j, k).
template <int R>
void Panel(double* p, Eigen::Index ld, const double* w, Eigen::Index ldw, Eigen::Index m, const double* d, int j0,
           int i, double f) {
  // (m may be fewer than W's columns: SymmetricSpanRankUpdate's columns that have begun at j0.)
  using Eigen::internal::pmadd;
  using Eigen::internal::pmul;
  using Eigen::internal::ploadu;
  using Eigen::internal::pset1;
  using Eigen::internal::pstoreu;
  using Eigen::internal::psub;
  Packet acc[R][kSpanBlock];
  for (int r = 0; r < R; ++r) {
    for (int c = 0; c < kSpanBlock; ++c) acc[r][c] = pset1<Packet>(0.0);
  }
  for (Eigen::Index k = 0; k < m; ++k) {
    const double* wk = w + k * ldw;
    Packet b[kSpanBlock];
    for (int c = 0; c < kSpanBlock; ++c) b[c] = pset1<Packet>(wk[j0 + c]);
    for (int r = 0; r < R; ++r) {
      const Packet a = ploadu<Packet>(wk + i + r * kLanes);
      for (int c = 0; c < kSpanBlock; ++c) acc[r][c] = pmadd(a, b[c], acc[r][c]);
    }
  }
  const Packet pf = pset1<Packet>(f);
  for (int r = 0; r < R; ++r) {
    const Packet dt = ploadu<Packet>(d + i + r * kLanes);
    for (int c = 0; c < kSpanBlock; ++c) {
      double* pc = p + (j0 + c) * ld + i + r * kLanes;
      const Packet scaled = pmul(ploadu<Packet>(pc), pmul(dt, pset1<Packet>(d[j0 + c])));
      pstoreu(pc, psub(scaled, pmul(pf, acc[r][c])));
    }
  }
}

// The one pass over P of both entry points: with `first`, column block j0 takes only W's leading
// columns that have begun by its last column (those after are zero there), and a block none has
// reached is left as it is (which needs d = 1: the caller asserts it).
void RankUpdate(Eigen::Ref<Eigen::MatrixXd, 0, Eigen::OuterStride<>> P, const Eigen::Ref<const Eigen::VectorXd>& d,
                const Eigen::Ref<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>& W, double f, const int* first) {
  const int n = static_cast<int>(P.rows());
  INERTIAL_ASSERT(P.cols() == n && n % kSpanBlock == 0 && d.size() == n && W.rows() == n && W.cols() >= 1);
  const Eigen::Index ld = P.outerStride(), ldw = W.outerStride(), m = W.cols();
  double* p = P.data();
  const double* w = W.data();
  const double* dd = d.data();
  // Rows of the main panels: twelve accumulators of four lanes (AVX: 16 registers) hide the
  // multiply-add latency; of two lanes (NEON: 32 registers) sixteen.
  constexpr int kRows = (kLanes >= 4 ? 3 : 2) * kSpanBlock;
  Eigen::Index active = first == nullptr ? m : 0;
  for (int j0 = 0; j0 < n; j0 += kSpanBlock) {
    if (first != nullptr) {
      while (active < m && first[active] < j0 + kSpanBlock) ++active;
      if (active == 0) continue;  // no column of W reaches these columns of P: they do not change
    }
    // The diagonal block's lower triangle, element by element (ten of sixteen).
    for (int c = 0; c < kSpanBlock; ++c) {
      for (int r = c; r < kSpanBlock; ++r) {
        double s = 0.0;
        for (Eigen::Index k = 0; k < active; ++k) s += w[k * ldw + j0 + r] * w[k * ldw + j0 + c];
        double& x = p[(j0 + c) * ld + j0 + r];
        x = x * (dd[j0 + r] * dd[j0 + c]) - f * s;
      }
    }
    int i = j0 + kSpanBlock;
    for (; i + kRows <= n; i += kRows) Panel<kRows / kLanes>(p, ld, w, ldw, active, dd, j0, i, f);
    if (i + 2 * kSpanBlock <= n) {  // n is whole blocks: eight rows or four are left, or none
      Panel<2 * kSpanBlock / kLanes>(p, ld, w, ldw, active, dd, j0, i, f);
    } else if (i < n) {
      Panel<kSpanBlock / kLanes>(p, ld, w, ldw, active, dd, j0, i, f);
    }
  }
}
}  // namespace

void ScaledSymmetricRankUpdate(Eigen::Ref<Eigen::MatrixXd, 0, Eigen::OuterStride<>> P, const Eigen::Ref<const Eigen::VectorXd>& d,
                               const Eigen::Ref<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>& W, double f) {
  RankUpdate(P, d, W, f, nullptr);
}

void SymmetricSpanRankUpdate(Eigen::Ref<Eigen::MatrixXd, 0, Eigen::OuterStride<>> P,
                             const Eigen::Ref<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>& W, const int* first,
                             const Eigen::Ref<const Eigen::VectorXd>& ones, double f) {
  INERTIAL_ASSERT((ones.array() == 1.0).all());  // blocks no column reaches are not scaled
  RankUpdate(P, ones, W, f, first);
}

}  // namespace inertial
