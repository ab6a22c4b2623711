#include "inertial/estimation/online/symmetric_span_product.hpp"

#include <algorithm>

#include "inertial/inertia/assert.hpp"

namespace inertial {

namespace {
using Packet = Eigen::internal::packet_traits<double>::type;
constexpr int kLanes = Eigen::internal::packet_traits<double>::size;  // doubles per Packet
static_assert(kSpanBlock % kLanes == 0, "a panel's rows must be whole packets");
}  // namespace

void SymmetricSpanProduct(const Eigen::Ref<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>& P,
                          const Eigen::Ref<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>& G, int c, int e,
                          Eigen::Ref<Eigen::MatrixXd, 0, Eigen::OuterStride<>> out) {
  using Eigen::internal::pmadd;
  using Eigen::internal::ploadu;
  using Eigen::internal::pset1;
  using Eigen::internal::pstoreu;
  const int n = static_cast<int>(P.rows());
  INERTIAL_ASSERT(P.cols() == n && n % kSpanBlock == 0 && c % kSpanBlock == 0 && e % kSpanBlock == 0 && 0 <= c &&
                  c <= e && e <= n);
  INERTIAL_ASSERT(G.rows() == n && G.cols() == kSpanBlock && out.rows() == n && out.cols() == kSpanBlock);
  const Eigen::Index ld = P.outerStride(), ldg = G.outerStride(), ldo = out.outerStride();
  const double* g = G.data();
  double* o = out.data();
  out.setZero();
  for (int s = 0; s < e; s += kSpanBlock) {
    const double* p = P.data() + s * ld;  // column s of P
    if (s >= c) {
      // The diagonal block P[s:s+4, s:s+4], symmetric from its lower triangle.
      for (int a = 0; a < kSpanBlock; ++a) {
        for (int b = 0; b < kSpanBlock; ++b) {
          const double pab = a >= b ? p[b * ld + s + a] : p[a * ld + s + b];
          for (int j = 0; j < kSpanBlock; ++j) o[j * ldo + s + a] += pab * g[j * ldg + s + b];
        }
      }
      // Below it, columns s .. s+3 in the span: out(t, j) += sum_b P(t, s+b) G(s+b, j), t >= s+4.
      Packet gb[kSpanBlock][kSpanBlock];
      for (int j = 0; j < kSpanBlock; ++j) {
        for (int b = 0; b < kSpanBlock; ++b) gb[j][b] = pset1<Packet>(g[j * ldg + s + b]);
      }
      for (int t = s + kSpanBlock; t < n; t += kLanes) {
        const Packet p0 = ploadu<Packet>(p + t), p1 = ploadu<Packet>(p + ld + t);
        const Packet p2 = ploadu<Packet>(p + 2 * ld + t), p3 = ploadu<Packet>(p + 3 * ld + t);
        for (int j = 0; j < kSpanBlock; ++j) {
          double* oj = o + j * ldo + t;
          Packet acc = ploadu<Packet>(oj);
          acc = pmadd(p0, gb[j][0], acc);
          acc = pmadd(p1, gb[j][1], acc);
          acc = pmadd(p2, gb[j][2], acc);
          acc = pmadd(p3, gb[j][3], acc);
          pstoreu(oj, acc);
        }
      }
    }
    // The same elements mirrored, rows t of the span below the block:
    // out(s+a, j) += sum_t P(t, s+a) G(t, j), two columns j at a time (eight accumulators).
    const int t0 = std::max(c, s + kSpanBlock);
    if (t0 >= e) continue;
    for (int j = 0; j < kSpanBlock; j += 2) {
      Packet acc[kSpanBlock][2];
      for (int a = 0; a < kSpanBlock; ++a) acc[a][0] = acc[a][1] = pset1<Packet>(0.0);
      const double* g0 = g + j * ldg;
      const double* g1 = g0 + ldg;
      for (int t = t0; t < e; t += kLanes) {
        const Packet h0 = ploadu<Packet>(g0 + t), h1 = ploadu<Packet>(g1 + t);
        for (int a = 0; a < kSpanBlock; ++a) {
          const Packet pa = ploadu<Packet>(p + a * ld + t);
          acc[a][0] = pmadd(pa, h0, acc[a][0]);
          acc[a][1] = pmadd(pa, h1, acc[a][1]);
        }
      }
      for (int a = 0; a < kSpanBlock; ++a) {
        o[j * ldo + s + a] += Eigen::internal::predux(acc[a][0]);
        o[(j + 1) * ldo + s + a] += Eigen::internal::predux(acc[a][1]);
      }
    }
  }
}

void NonzeroSpan(const Eigen::Ref<const Eigen::VectorXd>& v, int* first, int* end) {
  const int n = static_cast<int>(v.size());
  int c = 0, e = n;
  while (c < n && v[c] == 0.0) ++c;
  while (e > c && v[e - 1] == 0.0) --e;
  if (c == e) c = e = 0;
  *first = c;
  *end = e;
}

}  // namespace inertial
