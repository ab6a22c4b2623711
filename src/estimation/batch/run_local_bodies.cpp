#include "inertial/estimation/batch/run_local_bodies.hpp"

#include <stdexcept>
#include <string>

namespace inertial {

void ZeroFeatures(int first, int count, JointNormalEquations* eq) {
  eq->AtA.middleRows(first, count).setZero();
  eq->AtA.middleCols(first, count).setZero();
  eq->Atb.segment(first, count).setZero();
}

void ZeroFeatures(int first, int count, GainProblem* problem) {
  ZeroFeatures(first, count, &problem->links);
  for (JointNormalEquations& e : problem->logged) ZeroFeatures(first, count, &e);
  for (JointNormalEquations& e : problem->known) ZeroFeatures(first, count, &e);
  for (Eigen::VectorXd& a : problem->Aty) a.segment(first, count).setZero();
}

void AddStatistics(const JointNormalEquations& more, JointNormalEquations* sum) {
  if (sum->AtA.size() == 0 && sum->num_samples == 0) {
    *sum = more;
    return;
  }
  if (sum->AtA.rows() != more.AtA.rows() || sum->Atb.size() != more.Atb.size()) {
    throw std::invalid_argument("run statistics: the runs' statistics are of different models");
  }
  sum->AtA += more.AtA;
  sum->Atb += more.Atb;
  sum->btb += more.btb;
  sum->num_samples += more.num_samples;
}

void AddStatistics(const GainProblem& more, GainProblem* sum) {
  if (sum->links.AtA.size() == 0 && sum->links.num_samples == 0) {
    *sum = more;
    return;
  }
  if (sum->dofs != more.dofs || sum->logged.size() != more.logged.size()) {
    throw std::invalid_argument("run statistics: the runs' gain problems have different gain joints");
  }
  AddStatistics(more.links, &sum->links);
  for (size_t j = 0; j < more.logged.size(); ++j) {
    AddStatistics(more.logged[j], &sum->logged[j]);
    AddStatistics(more.known[j], &sum->known[j]);
    sum->ytp[j] += more.ytp[j];
  }
  for (size_t g = 0; g < more.dofs.size(); ++g) {
    sum->Aty[g] += more.Aty[g];
    sum->yty[g] += more.yty[g];
    sum->ytb[g] += more.ytb[g];
  }
}

namespace {

void CheckBodyRuns(const RobotDynamics& model, size_t num_runs, const std::vector<int>& body_runs) {
  if (body_runs.size() != model.bodies().size()) {
    throw std::invalid_argument("run statistics: body_runs needs one entry per estimated body (" +
                                std::to_string(model.bodies().size()) + "), not " + std::to_string(body_runs.size()));
  }
  for (size_t e = 0; e < body_runs.size(); ++e) {
    const EstimatedBody& b = model.bodies()[e];
    if (body_runs[e] < -1 || body_runs[e] >= static_cast<int>(num_runs)) {
      throw std::invalid_argument("run statistics: " + b.name + " is given run " + std::to_string(body_runs[e]) +
                                  " of " + std::to_string(num_runs));
    }
    if (body_runs[e] >= 0 && b.block == b.tree_body) {
      throw std::invalid_argument("run statistics: " + b.name +
                                  " shares its link's columns, so it cannot belong to one run only (give it "
                                  "own_features)");
    }
  }
}

// Zeroes, in run r's statistics, the blocks of the bodies of other runs.
template <typename Statistics>
void KeepRunBodies(const RobotDynamics& model, int r, const std::vector<int>& body_runs, Statistics* s) {
  for (size_t e = 0; e < body_runs.size(); ++e) {
    if (body_runs[e] >= 0 && body_runs[e] != r) ZeroFeatures(10 * model.bodies()[e].block, 10, s);
  }
}

}  // namespace

JointNormalEquations AccumulateRunNormalEquations(const RobotDynamics& model, const std::vector<JointSamples>& runs,
                                                  const std::vector<int>& body_runs) {
  CheckBodyRuns(model, runs.size(), body_runs);
  JointNormalEquations sum;
  for (size_t r = 0; r < runs.size(); ++r) {
    JointNormalEquations run = AccumulateNormalEquations(model, runs[r]);
    KeepRunBodies(model, static_cast<int>(r), body_runs, &run);
    AddStatistics(run, &sum);
  }
  return sum;
}

GainProblem AccumulateRunGainProblem(const RobotDynamics& model, const std::vector<JointSamples>& runs,
                                     const std::vector<Eigen::MatrixXd>& known, const std::vector<int>& gain_dofs,
                                     const std::vector<int>& body_runs) {
  CheckBodyRuns(model, runs.size(), body_runs);
  if (known.size() != runs.size()) throw std::invalid_argument("run statistics: one known-torque matrix per run");
  GainProblem sum;
  for (size_t r = 0; r < runs.size(); ++r) {
    GainProblem run = AccumulateGainProblem(model, runs[r], known[r], gain_dofs);
    KeepRunBodies(model, static_cast<int>(r), body_runs, &run);
    AddStatistics(run, &sum);
  }
  return sum;
}

}  // namespace inertial
