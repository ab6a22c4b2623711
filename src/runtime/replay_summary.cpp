#include "inertial/runtime/replay_summary.hpp"

#include <sstream>

#include "inertial/signal/rejection.hpp"

namespace inertial {

std::string ReplaySummaryText(const std::string& path, const ReplayOptions& options, const ReplayResult& r) {
  const std::string reasons = RejectionsText(r.counters);
  std::ostringstream out;
  out << "replayed " << path << ": " << r.events << (options.can ? " lines, " : " events, ") << r.counters.received
      << (options.can ? " frame lines" : " on " + options.channel) << "; accepted " << r.counters.accepted
      << ", rejected " << r.counters.total_rejected() << (reasons.empty() ? "" : " (" + reasons + ")");
  if (options.can) {
    out << "\nCAN: " << r.samples << " complete ticks; " << r.lines_not_frames << " lines that are not frames";
  }
  out << "\nthroughput: " << static_cast<long long>(r.samples_per_second) << " samples/s (" << r.seconds << " s)\n";
  return out.str();
}

std::string NothingReplayedText(const std::string& path, const ReplayOptions& options, const ReplayResult& r) {
  std::ostringstream out;
  out << "replay: " << path << " gave the estimator no sample: ";
  if (options.can) {
    if (r.counters.received == 0) {
      out << "of its " << r.events << " lines none is a candump frame";
    } else {
      out << "its " << r.counters.received << " frame lines made " << r.samples << " complete ticks ("
          << RejectionsText(r.counters) << "): check --can-config's ids and window";
    }
  } else if (path.size() >= 4 && path.compare(path.size() - 4, 4, ".csv") == 0) {
    out << "every one of its " << r.counters.received << " samples was refused: " << RejectionsText(r.counters);
  } else if (r.counters.received == 0) {
    out << "no message on channel " << options.channel << ";";
    if (r.channels.empty()) out << " it has no channel at all";
    for (const auto& [channel, count] : r.channels) out << " " << channel << " (" << count << " messages)";
    out << "; choose one with --channel";
  } else {
    out << "every one of the " << r.counters.received << " messages on " << options.channel
        << " was refused: " << RejectionsText(r.counters);
    if (r.counters[Rejection::kUnknownJoint] != 0) out << " (the messages name joints the --model does not have)";
  }
  return out.str();
}

std::string ReplayEstimateOrigin(const std::string& path, std::uint64_t accepted, std::string_view estimator) {
  return "the online estimate after replaying " + path + " (" + std::to_string(accepted) + " samples, " +
         std::string(estimator) + ")";
}

}  // namespace inertial
