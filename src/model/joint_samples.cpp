#include "inertial/model/joint_samples.hpp"

namespace inertial {

void CopySample(const JointSamples& log, int i, JointSample* out) {
  out->t = log.t[i];
  out->q = log.q.row(i).transpose();
  out->qd = log.qd.row(i).transpose();
  out->qdd = log.qdd.row(i).transpose();
  out->tau = log.tau.row(i).transpose();
  out->has_qdd = true;
  out->qdd_measured = true;
}

}  // namespace inertial
