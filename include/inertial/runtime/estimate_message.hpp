/// @file estimate_message.hpp
/// The estimate sink's message, inertial.estimate_t (lcmtypes/estimate_t.lcm), of a robot's or a
/// body's estimator: every body (pi, theta, mass, COM and their standard deviations, consistency
/// margins), the effects' coefficients, the residual RMS per channel over the pipeline's window,
/// and the pipeline's counters (rejections by name, rejection.hpp). Published by inertiald and
/// written by replay: one encoder for both. And the description a checkpoint is tagged with.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "inertial/estimation/online/online_body_estimator.hpp"
#include "inertial/estimation/online/online_joint_estimator.hpp"
#include "inertial/signal/rejection.hpp"
#include "inertial/runtime/sample_pipeline.hpp"

namespace inertial {

/// The estimate message of the pipeline's estimator now (robot or body), with `counters`
/// (normally TotalCounters of its stages).
/// `unexcited`: the quantities the stream did not determine (excitation_monitor.hpp), robot mode.
/// `lost`: samples lost before the daemon (stream_gap_counter.hpp), estimate_t.lost.
std::vector<std::uint8_t> EncodeEstimate(const SamplePipeline& pipeline, std::int64_t utime, const SampleCounters& counters,
                                         const std::vector<std::string>& unexcited = {}, std::uint64_t lost = 0);

/// The estimate message of the single-body estimator (one body `name`; channels mx .. fz).
std::vector<std::uint8_t> EncodeBodyEstimate(const OnlineBodyEstimator& estimator, const std::string& name,
                                             std::int64_t utime, const Eigen::VectorXd& residual_rms,
                                             double residual_window, const SampleCounters& counters,
                                             std::uint64_t lost = 0);

/// The estimate message of an online estimator (bodies, effects, residual RMS, counters).
std::vector<std::uint8_t> EncodeEstimate(const OnlineJointEstimator& estimator, std::int64_t utime,
                                         const Eigen::VectorXd& residual_rms, double residual_window,
                                         const SampleCounters& counters, const std::vector<std::string>& unexcited = {},
                                         std::uint64_t lost = 0);

/// What a robot estimator's checkpoint says of its model ("gauss_newton estimator; joints ...;
/// parameters ..."): a checkpoint is restored only into an estimator with the same description.
std::string CheckpointDescription(const OnlineJointEstimator& estimator);
/// The same for a pipeline's estimator ("... estimator; single body" for a body).
std::string CheckpointDescription(const SamplePipeline& pipeline);

}  // namespace inertial
