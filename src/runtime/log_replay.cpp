#include "inertial/runtime/log_replay.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <stdexcept>
#include <thread>

#include "inertial/formats/file_error.hpp"
#include "inertial/formats/joint_csv.hpp"
#include "inertial/runtime/estimate_message.hpp"
#include "inertial/runtime/sample_decoder.hpp"
#include "inertial/transport/can_frame.hpp"
#include "inertial/transport/lcm_log_check.hpp"

namespace inertial {
namespace {

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The estimate CSV sink: t, the counters so far, per body mass and COM, effect coefficients, the
// residual per channel of the last sample.
class EstimateCsv {
 public:
  EstimateCsv(const std::string& path, const SamplePipeline& pipeline)
      : file_(std::fopen(path.c_str(), "w"), &std::fclose), path_(path) {
    if (!file_) throw std::runtime_error(CannotText("write", "", path));
    std::string header = "t,accepted,rejected";
    auto body_columns = [&](const std::string& b) { header += "," + b + ".m," + b + ".cx," + b + ".cy," + b + ".cz"; };
    if (const OnlineJointEstimator* e = pipeline.robot()) {
      const RobotDynamics& model = e->model();
      for (const EstimatedBody& b : model.bodies()) body_columns(b.name);
      const std::vector<std::string> names = model.FeatureNames();
      for (int f = model.num_inertia_features(); f < model.num_features(); ++f) header += "," + names[f];
      for (const std::string& j : model.dof_names()) header += ",residual_" + j;
    } else {
      body_columns("body");
      for (const char* c : {"mx", "my", "mz", "fx", "fy", "fz"}) header += std::string(",residual_") + c;
    }
    std::fprintf(file_.get(), "%s\n", header.c_str());
  }
  void Row(const SamplePipeline& pipeline, double t, const SampleCounters& c) {
    std::fprintf(file_.get(), "%.9g,%llu,%llu", t, static_cast<unsigned long long>(c.accepted),
                 static_cast<unsigned long long>(c.total_rejected()));
    auto body = [&](const InertialParams& b) {
      const Vector3 com = b.mass() > 0 ? b.com() : Vector3::Zero();
      std::fprintf(file_.get(), ",%.17g,%.17g,%.17g,%.17g", b.mass(), com.x(), com.y(), com.z());
    };
    if (const OnlineJointEstimator* e = pipeline.robot()) {
      const RobotDynamics& model = e->model();
      for (int b = 0; b < static_cast<int>(model.bodies().size()); ++b) body(e->Body(b));
      for (int f = model.num_inertia_features(); f < model.num_features(); ++f) {
        std::fprintf(file_.get(), ",%.17g", e->coefficients()[f]);
      }
    } else {
      body(pipeline.body()->Body());
    }
    const Eigen::VectorXd& r = pipeline.last_residual();
    for (Eigen::Index k = 0; k < r.size(); ++k) std::fprintf(file_.get(), ",%.17g", r[k]);
    std::fprintf(file_.get(), "\n");
    if (std::ferror(file_.get())) throw std::runtime_error(CannotText("write", "", path_));
  }

 private:
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
  std::string path_;
};

// The replay loop: a source's samples through the pipeline, the sinks at every estimate period of
// log time.
class Replayer {
 public:
  Replayer(SamplePipeline* pipeline, const ReplayOptions& options,
           const std::function<void(const Sample&, SamplePipeline::Outcome)>& on_sample)
      : pipeline_(*pipeline), options_(options), on_sample_(on_sample), start_(std::chrono::steady_clock::now()) {
    if (!options.csv_path.empty()) csv_ = std::make_unique<EstimateCsv>(options.csv_path, pipeline_);
    if (!options.log_path.empty()) {
      out_ = std::make_unique<lcm::LogFile>(options.log_path, "w");
      if (!out_->good()) throw std::runtime_error(CannotText("write", "LCM log", options.log_path));
    }
  }

  /// One decoded sample: the pipeline, then the sinks when an estimate period has passed.
  void Feed(Sample* s, const SampleCounters& decoded) {
    const double t = s->time(pipeline_.body_mode());
    if (options_.realtime) {
      if (!have_first_) {
        first_t_ = t;
        have_first_ = true;
      }
      std::this_thread::sleep_until(start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                 std::chrono::duration<double>(t - first_t_)));
    }
    ++samples_;
    const SamplePipeline::Outcome outcome = pipeline_.Process(s);
    pipeline_.Solve();  // in line: a replay is not real time, and its estimates must not depend on the machine
    if (on_sample_) on_sample_(*s, outcome);
    if (next_row_ >= 0 && t < next_row_) return;
    next_row_ = t + options_.estimate_period_s;
    Emit(t, TotalCounters(decoded, pipeline_.counters()));
  }

  void Finish(ReplayResult* result, const SampleCounters& decoded) {
    pipeline_.Solve(true);  // the final estimate: identify's fit of every sample kept
    result->counters = TotalCounters(decoded, pipeline_.counters());
    result->samples = samples_;
    result->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    result->samples_per_second = result->seconds > 0 ? static_cast<double>(samples_) / result->seconds : 0.0;
    result->estimate_rows = rows_;
  }

 private:
  void Emit(double t, const SampleCounters& totals) {
    if (csv_) csv_->Row(pipeline_, t, totals);
    if (out_) {
      const std::int64_t utime = static_cast<std::int64_t>(std::llround(t * 1e6));
      std::vector<std::uint8_t> bytes = EncodeEstimate(pipeline_, utime, totals);
      lcm::LogEvent ev;
      ev.eventnum = eventnum_++;
      ev.timestamp = utime;
      ev.channel = options_.estimate_channel;
      ev.datalen = static_cast<std::int32_t>(bytes.size());
      ev.data = bytes.data();
      if (out_->writeEvent(&ev) != 0) throw std::runtime_error(CannotText("write", "LCM log", options_.log_path));
    }
    ++rows_;
  }

  SamplePipeline& pipeline_;
  const ReplayOptions& options_;
  const std::function<void(const Sample&, SamplePipeline::Outcome)>& on_sample_;
  std::unique_ptr<EstimateCsv> csv_;
  std::unique_ptr<lcm::LogFile> out_;
  std::chrono::steady_clock::time_point start_;
  double first_t_ = 0.0, next_row_ = -1.0;
  bool have_first_ = false;
  std::int64_t eventnum_ = 0;
  std::uint64_t samples_ = 0, rows_ = 0;
};

// The messages of options.channel in an LCM log through `decoder` and the replayer.
void ReplayLcmLog(const std::string& path, SampleDecoder* decoder, Replayer* replayer, Sample* sample,
                  const ReplayOptions& options, ReplayResult* result) {
  CheckLcmChannelName(options.channel, "--channel");
  if (!options.estimate_channel.empty()) CheckLcmChannelName(options.estimate_channel, "--estimate-channel");
  CheckLcmLog(path);  // every event header against the bytes left, before liblcm trusts them
  lcm::LogFile log(path, "r");
  if (!log.good()) throw std::runtime_error(CannotText("read", "LCM log", path));
  for (const lcm::LogEvent* ev = log.readNextEvent(); ev != nullptr; ev = log.readNextEvent()) {
    ++result->events;
    ++result->channels[ev->channel];
    if (ev->channel != options.channel) continue;
    if (decoder->DecodeMessage(ev->data, static_cast<std::size_t>(ev->datalen), ev->timestamp, sample)) {
      replayer->Feed(sample, decoder->counters());
    }
  }
  if (result->events == 0) throw std::runtime_error("'" + path + "' holds no LCM events (not an lcm-logger log?)");
}

}  // namespace

ReplayResult ReplayLog(const std::string& path, OnlineJointEstimator* estimator, const ReplayOptions& options,
                       const std::function<void(const Sample&, SamplePipeline::Outcome)>& on_sample) {
  ReplayResult result;
  const RobotDynamics& model = estimator->model();
  Sample sample = Sample::ForJoints(model.num_dofs());
  if (options.can) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(CannotText("read", "candump log", path));
    SampleDecoder decoder = SampleDecoder::CanFrames(*options.can, model.dof_names());
    SamplePipeline pipeline(estimator, decoder.accel_cutoff_hz(), options.residual_window_s);
    pipeline.SetLogGains(options.log_gains);
    Replayer replayer(&pipeline, options, on_sample);
    std::string line, iface;
    CanFrame frame;
    while (std::getline(in, line)) {
      ++result.events;
      try {
        if (ParseCandumpLine(line, &frame, &iface) == CandumpLine::kNotAFrame) {
          ++result.lines_not_frames;
          continue;
        }
      } catch (const std::invalid_argument&) {
        decoder.CountBadLine();
        continue;
      }
      if (decoder.DecodeFrame(frame, &sample)) replayer.Feed(&sample, decoder.counters());
    }
    replayer.Finish(&result, decoder.counters());
  } else if (EndsWith(path, ".csv")) {
    // A file's samples are decoded already; the CSV source counts each row as received and given.
    JointCsvReport read;
    const JointSamples log = ReadJointLog(path, model.dof_names(), options.csv, &read);
    SamplePipeline pipeline(estimator, options.format.accel_cutoff_hz, options.residual_window_s);
    pipeline.SetLogGains(options.log_gains);
    Replayer replayer(&pipeline, options, on_sample);
    SampleCounters rows;
    for (int i = 0; i < log.size(); ++i) {
      CopySample(log, i, &sample.joint);
      // qdd derived from q when the file had none: the estimator fits momentum rows instead.
      sample.joint.qdd_measured = !read.missing_qdd;
      ++result.events;
      ++rows.received;
      ++rows.accepted;
      replayer.Feed(&sample, rows);
    }
    replayer.Finish(&result, rows);
  } else {
    SampleDecoder decoder = SampleDecoder::JointMessages(options.format, model.dof_names());
    SamplePipeline pipeline(estimator, decoder.accel_cutoff_hz(), options.residual_window_s);
    pipeline.SetLogGains(options.log_gains);
    Replayer replayer(&pipeline, options, on_sample);
    ReplayLcmLog(path, &decoder, &replayer, &sample, options, &result);
    replayer.Finish(&result, decoder.counters());
  }
  return result;
}

ReplayResult ReplayBodyLog(const std::string& path, OnlineBodyEstimator* estimator, const ReplayOptions& options,
                           const std::function<void(const Sample&, SamplePipeline::Outcome)>& on_sample) {
  ReplayResult result;
  Sample sample;
  SampleDecoder decoder = SampleDecoder::BodyWrenches();
  SamplePipeline pipeline(estimator, options.residual_window_s);
  Replayer replayer(&pipeline, options, on_sample);
  ReplayLcmLog(path, &decoder, &replayer, &sample, options, &result);
  replayer.Finish(&result, decoder.counters());
  return result;
}

}  // namespace inertial
