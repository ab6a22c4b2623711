/// @file replay_summary.hpp
/// What `inertial replay` says about a replay (log_replay.hpp): the counts and the throughput, why
/// a replay that gave the estimator no sample gave none, and the origin line of the model file of
/// its final estimate.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "inertial/runtime/log_replay.hpp"

namespace inertial {

/// "replayed <path>: <events> events, <received> on <channel>; accepted <n>, rejected <n>
/// (<reasons>)\nthroughput: <samples/s, whole> samples/s (<seconds> s)\n"; a candump log (options.can)
/// counts lines and frame lines and adds "\nCAN: <samples> complete ticks; <n> lines that are not
/// frames" before the throughput.
std::string ReplaySummaryText(const std::string& path, const ReplayOptions& options, const ReplayResult& result);

/// Why a replay gave the estimator nothing (one line, no "Error: " and no newline): "replay: <path>
/// gave the estimator no sample: " and, for a candump log, that no line is a frame or how few
/// complete ticks its frames made; for a joint CSV, every sample refused and why; for an LCM log, no
/// message on the channel (and which channels it has) or every message refused and why.
std::string NothingReplayedText(const std::string& path, const ReplayOptions& options, const ReplayResult& result);

/// "the online estimate after replaying <path> (<accepted> samples, <estimator>)".
std::string ReplayEstimateOrigin(const std::string& path, std::uint64_t accepted, std::string_view estimator);

}  // namespace inertial
