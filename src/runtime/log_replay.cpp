#include "inertial/runtime/log_replay.hpp"

#include "inertial/formats/file_error.hpp"
#include "inertial/transport/lcm_log_check.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <stdexcept>
#include <thread>

#include "inertial/formats/joint_csv.hpp"

namespace inertial {
namespace {

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Writes the estimate rows: t, status counts so far, per body mass and COM, effect coefficients,
// residual per joint of the last sample.
class EstimateCsv {
 public:
  EstimateCsv(const std::string& path, const RobotDynamics& model) : file_(std::fopen(path.c_str(), "w"), &std::fclose), path_(path) {
    if (!file_) throw std::runtime_error(CannotText("write", "", path));
    std::string header = "t,accepted,rejected";
    for (const EstimatedBody& b : model.bodies()) header += "," + b.name + ".m," + b.name + ".cx," + b.name + ".cy," + b.name + ".cz";
    const std::vector<std::string> names = model.FeatureNames();
    for (int f = model.num_inertia_features(); f < model.num_features(); ++f) header += "," + names[f];
    for (const std::string& j : model.dof_names()) header += ",residual_" + j;
    std::fprintf(file_.get(), "%s\n", header.c_str());
  }
  void Row(const OnlineJointEstimator& e, double t, const DaemonCounters& c) {
    std::fprintf(file_.get(), "%.9g,%llu,%llu", t, static_cast<unsigned long long>(c.accepted),
                 static_cast<unsigned long long>(c.total_rejected()));
    const RobotDynamics& model = e.model();
    for (int b = 0; b < static_cast<int>(model.bodies().size()); ++b) {
      const InertialParams body = e.Body(b);
      const Vector3 com = body.mass() > 0 ? body.com() : Vector3::Zero();
      std::fprintf(file_.get(), ",%.17g,%.17g,%.17g,%.17g", body.mass(), com.x(), com.y(), com.z());
    }
    for (int f = model.num_inertia_features(); f < model.num_features(); ++f) {
      std::fprintf(file_.get(), ",%.17g", e.coefficients()[f]);
    }
    for (int k = 0; k < model.num_dofs(); ++k) std::fprintf(file_.get(), ",%.17g", e.residual()[k]);
    std::fprintf(file_.get(), "\n");
    if (std::ferror(file_.get())) throw std::runtime_error(CannotText("write", "", path_));
  }

 private:
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
  std::string path_;
};

}  // namespace

ReplayResult ReplayLog(const std::string& path, OnlineJointEstimator* estimator, const ReplayOptions& options,
                       const std::function<void(const JointSample&, UpdateStatus)>& on_sample) {
  ReplayResult result;
  const RobotDynamics& model = estimator->model();
  std::unique_ptr<EstimateCsv> csv;
  if (!options.csv_path.empty()) csv = std::make_unique<EstimateCsv>(options.csv_path, model);
  std::unique_ptr<lcm::LogFile> out;
  if (!options.log_path.empty()) {
    out = std::make_unique<lcm::LogFile>(options.log_path, "w");
    if (!out->good()) throw std::runtime_error(CannotText("write", "LCM log", options.log_path));
  }
  Eigen::VectorXd window_sum = Eigen::VectorXd::Zero(model.num_dofs());
  int window_count = 0;
  double next_row = -1.0;
  std::int64_t eventnum = 0;
  auto emit = [&](double t) {
    if (next_row >= 0 && t < next_row) return;
    next_row = t + options.estimate_period_s;
    if (csv) csv->Row(*estimator, t, result.counters);
    if (out) {
      const Eigen::VectorXd rms = window_count > 0 ? Eigen::VectorXd((window_sum / window_count).cwiseSqrt())
                                                   : Eigen::VectorXd::Zero(model.num_dofs());
      std::vector<std::uint8_t> bytes =
          EncodeEstimate(*estimator, static_cast<std::int64_t>(std::llround(t * 1e6)), rms, options.estimate_period_s,
                         result.counters);
      lcm::LogEvent ev;
      ev.eventnum = eventnum++;
      ev.timestamp = static_cast<std::int64_t>(std::llround(t * 1e6));
      ev.channel = options.estimate_channel;
      ev.datalen = static_cast<std::int32_t>(bytes.size());
      ev.data = bytes.data();
      if (out->writeEvent(&ev) != 0) throw std::runtime_error(CannotText("write", "LCM log", options.log_path));
    }
    window_sum.setZero();
    window_count = 0;
    ++result.estimate_rows;
  };
  const auto start = std::chrono::steady_clock::now();
  double first_t = 0.0;
  bool have_first = false;
  auto feed = [&](const JointSample& s) {
    if (options.realtime) {
      if (!have_first) {
        first_t = s.t;
        have_first = true;
      }
      const auto due = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                   std::chrono::duration<double>(s.t - first_t));
      std::this_thread::sleep_until(due);
    }
    const UpdateStatus status = estimator->Update(s);
    if (status == UpdateStatus::kAccepted) {
      ++result.counters.accepted;
      window_sum += estimator->residual().cwiseAbs2();
      ++window_count;
    } else if (IsRejection(status)) {
      ++result.counters.rejected[std::string(ToString(status))];
    }
    if (on_sample) on_sample(s, status);
    emit(s.t);
  };

  std::uint64_t samples = 0;
  if (options.can) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(CannotText("read", "candump log", path));
    CanJointAssembler assembler(*options.can, model.dof_names());
    std::string line, iface;
    CanFrame frame;
    JointSample s;
    while (std::getline(in, line)) {
      ++result.events;
      try {
        if (ParseCandumpLine(line, &frame, &iface) == CandumpLine::kNotAFrame) {
          ++result.lines_not_frames;
          continue;
        }
      } catch (const std::invalid_argument&) {
        ++result.counters.rejected["bad_line"];
        continue;
      }
      ++result.counters.received;
      if (assembler.Feed(frame, &s)) {
        ++samples;
        feed(s);
      }
    }
    result.can = assembler.counters();
    // Frames that gave no sample, by reason, as inertiald counts them.
    for (const auto& [reason, count] : {std::pair<const char*, std::uint64_t>{"unknown_id", result.can.unknown_id},
                                        {"malformed", result.can.malformed}, {"error_frame", result.can.error_frames},
                                        {"late", result.can.late}, {"superseded", result.can.superseded}}) {
      if (count > 0) result.counters.rejected[reason] += count;
    }
  } else if (EndsWith(path, ".csv")) {
    const JointSamples log = ReadJointCsv(path, model.dof_names(), options.csv);
    JointSample s;
    for (int i = 0; i < log.size(); ++i) {
      CopySample(log, i, &s);
      ++result.events;
      ++result.counters.received;
      ++samples;
      feed(s);
    }
  } else {
    CheckLcmChannelName(options.channel, "--channel");
    if (!options.estimate_channel.empty()) CheckLcmChannelName(options.estimate_channel, "--estimate-channel");
    CheckLcmLog(path);  // every event header against the bytes left, before liblcm trusts them
    lcm::LogFile log(path, "r");
    if (!log.good()) throw std::runtime_error(CannotText("read", "LCM log", path));
    JointMessageDecoder decoder(options.format, model.dof_names());
    JointSample s;
    for (const lcm::LogEvent* ev = log.readNextEvent(); ev != nullptr; ev = log.readNextEvent()) {
      ++result.events;
      ++result.channels[ev->channel];
      if (ev->channel != options.channel) continue;
      ++result.counters.received;
      const MessageRejection r = decoder.Decode(ev->data, static_cast<std::size_t>(ev->datalen), ev->timestamp, &s);
      if (r != MessageRejection::kNone) {
        ++result.counters.rejected[ToString(r)];
        continue;
      }
      ++samples;
      feed(s);
    }
    if (result.events == 0) throw std::runtime_error("'" + path + "' holds no LCM events (not an lcm-logger log?)");
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.samples_per_second = result.seconds > 0 ? static_cast<double>(samples) / result.seconds : 0.0;
  return result;
}

}  // namespace inertial
