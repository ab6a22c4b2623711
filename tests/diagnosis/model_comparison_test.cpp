// A model against measurements (model_comparison.hpp): the rows NonFiniteRows finds in hand-made
// data; and the leg's torques from its recursive Newton-Euler inverse dynamics with a constant
// offset per joint and one bad second on the knee, so the residual's constant part is minus each
// offset (predicted - measured), the worst window is that second, and its worst joint the knee.
#include "inertial/diagnosis/model_comparison.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "estimation/leg_chain.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

TEST(ModelComparison, NonFiniteRowsByHand) {
  JointSamples d;
  d.t = Eigen::VectorXd::LinSpaced(6, 0.0, 0.5);
  d.q = d.qd = d.qdd = d.tau = Eigen::MatrixXd::Zero(6, 1);
  Eigen::MatrixXd predicted = Eigen::MatrixXd::Zero(6, 2);  // two channels per joint: c mod 1 = 0
  d.q(1, 0) = std::numeric_limits<double>::quiet_NaN();
  d.tau(3, 0) = 2 * kLargestSquarable;
  predicted(4, 1) = kLargestSquarable;  // its error reaches the bound
  d.t[5] = std::numeric_limits<double>::infinity();
  predicted(2, 0) = 0.5 * kLargestSquarable;  // large, but below the bound: kept
  EXPECT_EQ(NonFiniteRows(predicted, d), (std::vector<int>{1, 3, 4, 5}));
}

TEST(ModelComparison, OffsetsAndABadSecondOnTheLeg) {
  const RobotDynamics model(testing::LegChain(testing::LegPriorLinks()), testing::kLegJoints, {}, testing::NoLinks());
  const Eigen::VectorXd x = testing::TrueParameters(model, {0.0}, 5, 0.25);
  JointSamples data = testing::SimulateLogs(model, x, 0.0, 6.0, 5, 100).train;
  const Eigen::Vector3d offset(0.1, -0.2, 0.3);
  for (int i = 0; i < data.size(); ++i) {
    Eigen::Vector3d tau = model.InverseDynamics(x, data.q.row(i).transpose(), data.qd.row(i).transpose(),
                                                data.qdd.row(i).transpose()) + offset;
    if (data.t[i] >= 2.2 && data.t[i] < 2.8) tau[2] += 2.0;  // the knee's bad stretch
    data.tau.row(i) = tau.transpose();
  }
  const ModelComparison c = CompareJointModel(model, x, data);
  EXPECT_EQ(c.left_out, 0);
  EXPECT_EQ(c.channels, testing::kLegJoints);
  ASSERT_EQ(c.predicted.rows(), data.size());
  for (int j = 0; j < 2; ++j) {  // abad and hip: the residual is minus the offset, exactly
    EXPECT_NEAR(c.residuals.joints[j].coefficients[kResidualMean], -offset[j], 1e-9) << j;
    EXPECT_NEAR(c.errors.rms[j], std::abs(offset[j]), 1e-9) << j;
  }
  ASSERT_FALSE(c.residuals.worst_windows.empty());
  const ResidualWindow& worst = c.residuals.worst_windows.front();
  EXPECT_LE(worst.t_start, 2.5);
  EXPECT_GT(worst.t_end, 2.5);
  EXPECT_EQ(worst.worst_joint, 2);
  EXPECT_LE(c.residuals.worst_windows.size(), static_cast<size_t>(kWorstFailureWindows));
}

}  // namespace
}  // namespace inertial
