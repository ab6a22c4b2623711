// The pipeline's sample: ForJoints sizes every joint vector with zeros, and time() picks the
// body or the joint time.
#include "inertial/runtime/sample.hpp"

#include <gtest/gtest.h>

namespace inertial {
namespace {

TEST(Sample, ForJointsAndTime) {
  Sample s = Sample::ForJoints(4);
  for (const Eigen::VectorXd* v : {&s.joint.q, &s.joint.qd, &s.joint.qdd, &s.joint.tau}) {
    EXPECT_EQ(*v, Eigen::VectorXd::Zero(4));
  }
  s.joint.t = 1.5;
  s.body.t = 2.5;
  EXPECT_EQ(s.time(false), 1.5);
  EXPECT_EQ(s.time(true), 2.5);
  EXPECT_EQ(Sample::ForJoints(0).joint.q.size(), 0);
}

}  // namespace
}  // namespace inertial
