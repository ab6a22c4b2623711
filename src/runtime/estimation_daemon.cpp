#include "inertial/runtime/estimation_daemon.hpp"

#include "inertial/report/online_diagnosis_report.hpp"
#include "inertial/runtime/diagnosis_message.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include <unistd.h>

#include "inertial/estimation/online/state_entry_names.hpp"
#include "inertial/estimation/online/state_extension.hpp"
#include "inertial/formats/estimator_state_file.hpp"
#include "inertial/residual_t.hpp"
#include "inertial/runtime/bounded_queue.hpp"
#include "inertial/transport/lcm_log_check.hpp"

namespace inertial {
namespace {

double NowSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

// The receiver's half: the source and the decoding stage, and the queue into the estimator thread.
struct EstimationDaemon::Impl {
  Impl(const DaemonOptions& o, SampleDecoder d, const Sample& prototype)
      : lcm(o.lcm_url), decoder(std::move(d)), queue(o.queue_capacity, prototype), scratch(prototype) {}
  lcm::LCM lcm;  // received on by the receiver thread, published on by the estimator thread
  SampleDecoder decoder;         // receiver thread, under decode_mutex
  std::unique_ptr<CanBus> bus;   // CAN mode: frames from here instead of LCM
  BoundedQueue<Sample> queue;
  Sample scratch;  // decoded into by the receiver thread only
  mutable std::mutex decode_mutex;  // decoder and queue_full, against counters() from other threads
  std::uint64_t queue_full = 0;
  EstimationDaemon* owner = nullptr;

  // A rejection is logged at warn the first time its reason occurs, then at debug level (counted).
  void LogRejection(Rejection r, const std::string& text) {
    const std::string reason(ToString(r));
    const bool first = owner->FirstTime("rejected " + reason);
    owner->Log(first ? LogLevel::kWarn : LogLevel::kDebug,
               text + (first ? " (further '" + reason + "' rejections are counted, not logged at warn)" : ""));
  }

  // A decoded sample into the queue (a full queue drops it, counted).
  void Push() {
    if (!queue.TryPush(scratch)) {
      std::lock_guard<std::mutex> lock(decode_mutex);
      ++queue_full;
    }
  }

  // CAN mode: one frame into the decoder; a completed tick into the queue.
  void OnFrame(const CanFrame& frame) {
    std::string why;
    bool tick = false;
    Rejection r = Rejection::kNone;
    {
      std::lock_guard<std::mutex> lock(decode_mutex);
      tick = decoder.DecodeFrame(frame, &scratch, &why);
      r = decoder.last_rejection();
    }
    if (tick) Push();
    if (r == Rejection::kMalformed) LogRejection(r, "rejected a CAN frame: " + why);
  }

  void OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string& /*channel*/) {
    std::string why;
    bool decoded = false;
    Rejection r = Rejection::kNone;
    {
      std::lock_guard<std::mutex> lock(decode_mutex);
      decoded = decoder.DecodeMessage(rbuf->data, rbuf->data_size, rbuf->recv_utime, &scratch, &why);
      r = decoder.last_rejection();
    }
    if (decoded) {
      Push();
    } else {
      LogRejection(r, "rejected a message on " + owner->options_.input_channel + " (" + std::string(ToString(r)) +
                          "): " + why);
    }
  }

  SampleCounters decoded() const {
    std::lock_guard<std::mutex> lock(decode_mutex);
    return decoder.counters();
  }
  std::uint64_t dropped() const {
    std::lock_guard<std::mutex> lock(decode_mutex);
    return queue_full;
  }
};

namespace {

void CheckOptions(const DaemonOptions& o) {
  if (!(o.publish_rate_hz > 0) || !(o.residual_window_s > 0) || !(o.checkpoint_interval_s > 0) || o.queue_capacity == 0) {
    throw std::invalid_argument("inertiald: rates, window, interval and queue capacity must be positive");
  }
  CheckLcmChannelName(o.input_channel, "inertiald: the input channel");
  CheckLcmChannelName(o.estimate_channel, "inertiald: the estimate channel");
  if (!o.residual_channel.empty()) CheckLcmChannelName(o.residual_channel, "inertiald: the residual channel");
}

}  // namespace

namespace {

// By const reference (a copy at start-up): the delegating constructors also read the model's DOF
// names, and the order in which arguments are evaluated is unspecified.
std::unique_ptr<OnlineJointEstimator> RobotEstimator(const RobotDynamics& model, const DaemonOptions& o) {
  return std::make_unique<OnlineJointEstimator>(model, Eigen::VectorXd::Zero(model.num_parameters()), o.estimator);
}

}  // namespace

EstimationDaemon::EstimationDaemon(RobotDynamics model, DaemonOptions options)
    : EstimationDaemon(options, SampleDecoder::JointMessages(options.format, model.dof_names()),
                       RobotEstimator(model, options), nullptr, nullptr) {}

EstimationDaemon::EstimationDaemon(const InertialParams& prior, DaemonOptions options)
    : EstimationDaemon(options, SampleDecoder::BodyWrenches(), nullptr,
                       std::make_unique<OnlineBodyEstimator>(prior, options.estimator), nullptr) {}

EstimationDaemon::EstimationDaemon(RobotDynamics model, DaemonOptions options, CanConfig can, std::unique_ptr<CanBus> bus)
    : EstimationDaemon(options, SampleDecoder::CanFrames(std::move(can), model.dof_names()),
                       RobotEstimator(model, options), nullptr, std::move(bus)) {
  if (!impl_->bus) throw std::invalid_argument("inertiald: no CAN bus");
}

EstimationDaemon::EstimationDaemon(DaemonOptions options, SampleDecoder decoder, std::unique_ptr<OnlineJointEstimator> robot,
                                   std::unique_ptr<OnlineBodyEstimator> body, std::unique_ptr<CanBus> bus)
    : options_(std::move(options)), robot_(std::move(robot)), body_(std::move(body)) {
  CheckOptions(options_);
  const double cutoff = decoder.accel_cutoff_hz();
  pipeline_ = robot_ ? std::make_unique<SamplePipeline>(robot_.get(), cutoff, options_.residual_window_s)
                     : std::make_unique<SamplePipeline>(body_.get(), options_.residual_window_s);
  const Sample prototype = robot_ ? Sample::ForJoints(robot_->model().num_dofs()) : Sample{};
  const bool can = decoder.can_mode();
  const std::vector<CanId> ids = decoder.can_ids();
  impl_ = std::make_unique<Impl>(options_, std::move(decoder), prototype);
  impl_->owner = this;
  if (can && bus) {
    bus->SetFilters(ids);
    impl_->bus = std::move(bus);
  }
  if (!impl_->lcm.good()) {
    throw std::runtime_error("LCM could not start on '" + (options_.lcm_url.empty() ? "the default URL" : options_.lcm_url) +
                             "'");
  }
  RestoreCheckpoint();
  if (robot_ && !options_.diagnosis_channel.empty()) {
    CheckLcmChannelName(options_.diagnosis_channel, "inertiald: the diagnosis channel");
    if (!(options_.diagnosis_period_s > 0)) throw std::invalid_argument("inertiald: the diagnosis period must be positive");
    diagnosis_ = std::make_unique<StreamDiagnosis>(robot_->model(),
                                                   StreamDiagnosisOptionsFor(robot_->model(), options_.estimator));
    changes_seen_ = robot_->estimator().changes_detected();
  }
  if (robot_ && !options_.payload_channel.empty()) {
    CheckLcmChannelName(options_.payload_channel, "inertiald: the payload event channel");
    payload_events_ = std::make_unique<PayloadEventDetector>(*robot_);
  }
  if (!can) impl_->lcm.subscribe(options_.input_channel, &Impl::OnMessage, impl_.get());
}

namespace {

// A robot's checkpoint description (CheckpointDescription, estimate_message.hpp: "<kind> estimator;
// joints j1 j2 ...; parameters p1 p2 ..."), split into its parts.
struct CheckpointModel {
  std::string kind;
  std::vector<std::string> joints, parameters;
};

std::vector<std::string> Words(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

std::string Joined(const std::vector<std::string>& words) {
  std::string text;
  for (const std::string& w : words) text += (text.empty() ? "" : " ") + w;
  return text;
}

// Nullopt for any other description (a single body's, a foreign writer's).
std::optional<CheckpointModel> ParseCheckpointDescription(const std::string& description) {
  const std::string joints = " estimator; joints", parameters = "; parameters";
  const size_t a = description.find(joints);
  if (a == std::string::npos) return std::nullopt;
  const size_t b = description.find(parameters, a + joints.size());
  if (b == std::string::npos) return std::nullopt;
  CheckpointModel m;
  m.kind = description.substr(0, a);
  m.joints = Words(description.substr(a + joints.size(), b - a - joints.size()));
  m.parameters = Words(description.substr(b + parameters.size()));
  return m;
}

// A checkpoint of the same estimator kind, joints and links as `estimator` with fewer effects (its
// description differs from the model's): its state carried into the model by name
// (state_extension.hpp), the new effects' parameters at their priors with their prior variance.
// Nullopt, and *why naming what differs, for another estimator, other joints, a link missing from
// the checkpoint, or a parameter of the checkpoint this model lacks (an effect removed).
std::optional<ExtendedState> CheckpointWithFewerEffects(const std::string& description, const EstimatorState& saved,
                                                        const OnlineJointEstimator& estimator, std::string* why) {
  const std::optional<CheckpointModel> checkpoint = ParseCheckpointDescription(description);
  if (!checkpoint) {
    *why = "it is not a robot's checkpoint";
    return std::nullopt;
  }
  const std::string kind(ToString(estimator.kind()));
  if (checkpoint->kind != kind) {
    *why = "it is of a '" + checkpoint->kind + "' estimator, this one is '" + kind + "'";
    return std::nullopt;
  }
  const RobotDynamics& model = estimator.model();
  if (checkpoint->joints != model.dof_names()) {
    *why = "its joints are '" + Joined(checkpoint->joints) + "', this model's '" + Joined(model.dof_names()) + "'";
    return std::nullopt;
  }
  // Only effects may be new: every link of the model has its estimate in the checkpoint.
  const std::vector<std::string> parameters = model.ParameterNames();
  const std::set<std::string> saved_parameters(checkpoint->parameters.begin(), checkpoint->parameters.end());
  for (size_t e = 0; e < model.bodies().size(); ++e) {
    const EstimatedBody& body = model.bodies()[e];
    const bool link = !model.tree().is_rotor(body.tree_body) && model.tree().body_name(body.tree_body) == body.name;
    if (link && saved_parameters.count(parameters[10 * e]) == 0) {
      *why = "it has no estimate of link '" + body.name + "'";
      return std::nullopt;
    }
  }
  std::string missing;
  const std::optional<std::vector<std::string>> saved_names =
      StateEntryNames(model, estimator.kind(), checkpoint->parameters, &missing);
  if (!saved_names) {
    *why = missing + " (were effects removed?)";
    return std::nullopt;
  }
  const std::optional<std::vector<std::string>> names = StateEntryNames(model, estimator.kind(), parameters, nullptr);
  return ExtendEstimatorState(saved, *saved_names, estimator.estimator().State(), *names, why);
}

}  // namespace

void EstimationDaemon::RestoreCheckpoint() {
  if (options_.checkpoint_path.empty()) return;
  const std::filesystem::path path(options_.checkpoint_path);
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw StateFileError("--checkpoint '" + options_.checkpoint_path + "' is a directory, not a file");
  }
  // Refused now rather than failing at every interval: the directory must take new files.
  const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  if (!std::filesystem::is_directory(dir, ec) || ::access(dir.c_str(), W_OK | X_OK) != 0) {
    throw StateFileError("--checkpoint '" + options_.checkpoint_path + "': cannot write files in '" + dir.string() +
                             "' (" + (std::filesystem::exists(dir, ec) ? "permission denied" : "no such directory") +
                             ")");
  }
  if (!std::filesystem::exists(options_.checkpoint_path)) return;
  // Not restored: refuse to start (the file is left as it is) unless told to start afresh.
  auto unusable = [&](const std::string& why) {
    if (!options_.start_fresh) {
      throw StateFileError("--checkpoint '" + options_.checkpoint_path + "' " + why +
                               "; it is left untouched: give another path, or --fresh to start from the priors and "
                               "overwrite it");
    }
    Log(LogLevel::kWarn, "checkpoint " + options_.checkpoint_path + " " + why +
                             "; starting from the priors (--fresh): it will be overwritten");
  };
  std::string description;
  std::optional<EstimatorState> state;
  try {
    state = LoadEstimatorState(options_.checkpoint_path, &description);
  } catch (const std::exception& e) {
    unusable(std::string("is not a checkpoint this daemon can read (") + e.what() + ")");
  }
  std::string why;
  const auto samples = [&] {
    return std::to_string(state->counters.accepted()) + " samples, last at t = " + std::to_string(state->last_time) + " s";
  };
  if (!state) {
    // already reported
  } else if (description == CheckpointDescription(*pipeline_)) {
    if (!(robot_ ? robot_->Restore(*state, &why) : pipeline_->estimator().Restore(*state, &why))) {
      unusable("cannot be restored: " + why);
    } else {
      restored_ = true;
      Log(LogLevel::kInfo, "restored " + options_.checkpoint_path + " (" + samples() + ")");
    }
  } else if (!robot_) {
    unusable("is a checkpoint of another model or estimator (" + description + ")");
  } else {
    // The same links and joints with fewer effects (e.g. --effects grown): every saved parameter kept.
    const std::optional<ExtendedState> extended = CheckpointWithFewerEffects(description, *state, *robot_, &why);
    if (!extended) {
      unusable("is a checkpoint of another model or estimator: " + why + " (checkpoint of: " + description + ")");
    } else if (!(robot_ ? robot_->Restore(extended->state, &why) : pipeline_->estimator().Restore(extended->state, &why))) {
      unusable("cannot be restored: " + why);
    } else {
      restored_ = true;
      const std::string kept = std::to_string(state->x.size()) + " parameters (every link)";
      Log(LogLevel::kInfo,
          "restored " + options_.checkpoint_path +
              (extended->added.empty() ? " into a model of the same parameters in another order: kept " + kept
                                       : " into a model with more effects: kept " + kept +
                                             ", new at their priors: " + Joined(extended->added)) +
              " (" + samples() + ")");
    }
  }
}

EstimationDaemon::~EstimationDaemon() = default;

lcm::LCM& EstimationDaemon::lcm() { return impl_->lcm; }

void EstimationDaemon::WriteModel() {
  if (!model_sink_ || !robot_) return;
  try {
    std::lock_guard<std::mutex> lock(process_mutex_);
    model_sink_(*robot_);
  } catch (const std::exception& e) {
    Log(LogLevel::kError, std::string("writing the model failed: ") + e.what());
  }
}

bool EstimationDaemon::FirstTime(const std::string& problem) {
  std::lock_guard<std::mutex> lock(problems_mutex_);
  return problems_.insert(problem).second;
}

bool EstimationDaemon::Recovered(const std::string& problem) {
  std::lock_guard<std::mutex> lock(problems_mutex_);
  return problems_.erase(problem) > 0;
}

void EstimationDaemon::Log(LogLevel level, const std::string& text) const {
  if (static_cast<int>(level) > static_cast<int>(options_.log_level)) return;
  static const char* kNames[] = {"error", "warn", "info", "debug"};
  const std::string line = std::string("inertiald [") + kNames[static_cast<int>(level)] + "] " + text;
  std::lock_guard<std::mutex> lock(log_mutex_);  // both threads log
  if (log_sink_) {
    log_sink_(line);
  } else {
    std::cerr << line << "\n" << std::flush;
  }
}

void EstimationDaemon::Process(Sample* sample) {
  std::lock_guard<std::mutex> lock(process_mutex_);
  const SamplePipeline::Outcome outcome = pipeline_->Process(sample);
  if (diagnosis_) {
    // The residual before the update: a prequential (held-out) error. A detected change of the
    // system (the covariance reset) starts the diagnosis's statistics again.
    const std::uint64_t changes = robot_->estimator().changes_detected();
    if (changes != changes_seen_) {
      changes_seen_ = changes;
      diagnosis_->Reset();
    }
    if (outcome.accepted()) diagnosis_->Observe(sample->joint, robot_->residual());
  }
  if (payload_events_ && outcome.rejection == Rejection::kNone) {
    if (const std::optional<PayloadEvent> event = payload_events_->Observe(*robot_, sample->joint)) {
      const std::vector<std::uint8_t> bytes = EncodePayloadEvent(*event);
      if (impl_->lcm.publish(options_.payload_channel, bytes.data(), static_cast<unsigned>(bytes.size())) == 0) {
        std::lock_guard<std::mutex> sinks(sinks_mutex_);
        ++payload_events_published_;
      }
      Log(LogLevel::kInfo, PayloadEventText(*event));
    }
  }
  if (!robot_ || options_.residual_channel.empty() || outcome.rejection != Rejection::kNone) return;
  const JointSample& j = sample->joint;
  inertial::residual_t m;
  m.utime = static_cast<std::int64_t>(std::llround(j.t * 1e6));
  m.status = std::string(ToString(outcome.status));
  m.num_channels = static_cast<std::int32_t>(j.tau.size());
  m.channel_names = robot_->model().dof_names();
  m.measured.assign(j.tau.data(), j.tau.data() + j.tau.size());
  const Eigen::VectorXd& p = robot_->predicted();
  m.predicted.assign(p.data(), p.data() + p.size());
  m.residual.resize(m.measured.size());
  for (size_t k = 0; k < m.measured.size(); ++k) m.residual[k] = m.measured[k] - m.predicted[k];
  impl_->lcm.publish(options_.residual_channel, &m);
}

void EstimationDaemon::Publish(std::int64_t utime) {
  const SampleCounters totals = counters().samples;
  std::vector<std::string> unexcited;
  {
    std::lock_guard<std::mutex> lock(sinks_mutex_);
    unexcited = unexcited_;
  }
  std::vector<std::uint8_t> bytes;
  {
    std::lock_guard<std::mutex> lock(process_mutex_);
    bytes = EncodeEstimate(*pipeline_, utime, totals, unexcited);
  }
  const bool sent = impl_->lcm.publish(options_.estimate_channel, bytes.data(), static_cast<unsigned>(bytes.size())) == 0;
  {
    std::lock_guard<std::mutex> lock(sinks_mutex_);
    ++(sent ? published_ : publish_failures_);
  }
  if (!sent && FirstTime("publish")) {
    Log(LogLevel::kError, "cannot publish on " + options_.estimate_channel + " (" + options_.lcm_url +
                              "): LCM refused the message; estimation goes on, further failures are counted");
  } else if (sent && Recovered("publish")) {
    Log(LogLevel::kInfo, "publishing on " + options_.estimate_channel + " again");
  }
}

void EstimationDaemon::PublishDiagnosis(std::int64_t utime) {
  if (!diagnosis_) return;
  if (const std::optional<StreamJudgement> latest = diagnosis_->Latest()) {
    const std::vector<std::uint8_t> bytes = EncodeDiagnosis(latest->diagnosis, utime);
    if (impl_->lcm.publish(options_.diagnosis_channel, bytes.data(), static_cast<unsigned>(bytes.size())) == 0) {
      std::lock_guard<std::mutex> lock(sinks_mutex_);
      ++diagnoses_;
    }
    if (latest->excitation) {
      // The excitation in the log when it changes (not at every period).
      const std::string text = UnexcitedText(*latest->excitation);
      if (text != last_excitation_text_) Log(LogLevel::kInfo, "excitation: " + text);
      last_excitation_text_ = text;
      std::lock_guard<std::mutex> lock(sinks_mutex_);
      unexcited_ = UnexcitedNames(*latest->excitation, false);
    }
  }
  std::vector<OnlineBodyState> bodies;
  Eigen::VectorXd x;
  {
    std::lock_guard<std::mutex> lock(process_mutex_);
    bodies = BodyStatesOf(*robot_);
    x = robot_->estimator().parameters();
  }
  diagnosis_->RequestEvaluation(std::move(bodies), std::move(x));
}

void EstimationDaemon::FinalDiagnosis(std::int64_t utime) {
  if (!diagnosis_) return;
  std::vector<OnlineBodyState> bodies;
  Eigen::VectorXd x;
  {
    std::lock_guard<std::mutex> lock(process_mutex_);
    bodies = BodyStatesOf(*robot_);
    x = robot_->estimator().parameters();
  }
  const StreamJudgement judged = diagnosis_->EvaluateNow(bodies, x);
  const OnlineDiagnosisResult& result = judged.diagnosis;
  if (judged.excitation) Log(LogLevel::kInfo, "excitation: " + UnexcitedText(*judged.excitation));
  const std::vector<std::uint8_t> bytes = EncodeDiagnosis(result, utime);
  if (impl_->lcm.publish(options_.diagnosis_channel, bytes.data(), static_cast<unsigned>(bytes.size())) == 0) {
    std::lock_guard<std::mutex> lock(sinks_mutex_);
    ++diagnoses_;
  }
  Log(LogLevel::kInfo, OnlineDiagnosisText(result));
}

void EstimationDaemon::Checkpoint() {
  if (options_.checkpoint_path.empty()) return;
  try {
    EstimatorState state;
    {
      std::lock_guard<std::mutex> lock(process_mutex_);
      state = pipeline_->estimator().State();
    }
    SaveEstimatorState(options_.checkpoint_path, state, CheckpointDescription(*pipeline_));
    {
      std::lock_guard<std::mutex> lock(sinks_mutex_);
      ++checkpoints_;
    }
    if (Recovered("checkpoint")) Log(LogLevel::kInfo, "checkpoint " + options_.checkpoint_path + " written again");
  } catch (const std::exception& e) {
    {
      std::lock_guard<std::mutex> lock(sinks_mutex_);
      ++checkpoint_failures_;
    }
    const bool first = FirstTime("checkpoint");
    Log(first ? LogLevel::kError : LogLevel::kDebug,
        std::string("checkpoint failed: ") + e.what() +
            (first ? " (estimation goes on; further failures are counted, and a success is logged)" : ""));
  }
}

int EstimationDaemon::Run(const std::atomic<bool>& stop) {
  std::atomic<bool> receiver_failed{false}, receiver_stop{false};
  Sample sample = impl_->scratch;  // before the receiver thread writes scratch (sized once)
  std::thread receiver([&] {
    CanFrame frame;
    while (!receiver_stop) {
      if (impl_->bus) {
        try {
          if (impl_->bus->Read(&frame, 50)) impl_->OnFrame(frame);
        } catch (const std::exception& e) {
          Log(LogLevel::kError, e.what());
          receiver_failed = true;
          return;
        }
      } else if (impl_->lcm.handleTimeout(50) < 0) {
        receiver_failed = true;
        return;
      }
    }
  });
  Log(LogLevel::kInfo, "listening on " + (impl_->bus ? std::string("the CAN bus") : options_.input_channel) + ", publishing " + options_.estimate_channel + " at " +
                           std::to_string(options_.publish_rate_hz) + " Hz (" +
                           std::to_string(recursive_estimator().num_parameters()) + " parameters, " +
                           std::string(recursive_estimator().kind()) + (body_ ? ", single body" : "") + ")");
  double next_publish = NowSeconds() + 1.0 / options_.publish_rate_hz;
  double next_checkpoint = NowSeconds() + options_.checkpoint_interval_s;
  double next_diagnosis = NowSeconds() + options_.diagnosis_period_s;
  auto utime = [&] {
    std::lock_guard<std::mutex> lock(process_mutex_);
    return static_cast<std::int64_t>(std::llround(pipeline_->last_time() * 1e6));
  };
  // The solver (gauss_newton of a robot, online_fit.hpp): the objective re-solved on a thread of
  // its own from a snapshot of the statistics, so that the estimator thread only accumulates.
  std::atomic<bool> solver_stop{false};
  std::thread solver;
  if (robot_ && robot_->fit() != nullptr) {
    solver = std::thread([&] {
      while (!solver_stop) {
        std::optional<OnlineFitSnapshot> snapshot;
        {
          std::lock_guard<std::mutex> lock(process_mutex_);
          if (robot_->SolveDue()) snapshot = robot_->fit()->Snapshot();
        }
        if (!snapshot) {
          std::this_thread::sleep_for(std::chrono::milliseconds(5));
          continue;
        }
        bool adopted = false;
        try {
          const OnlineFitSolution solution = SolveOnlineFit(robot_->model(), *snapshot, robot_->fit()->options());
          std::lock_guard<std::mutex> lock(process_mutex_);
          adopted = robot_->Adopt(solution);
          pipeline_->Reconcile();
        } catch (const std::exception& e) {
          if (FirstTime("solve")) Log(LogLevel::kError, std::string("the solve failed: ") + e.what());
        }
        // A solve that failed or gave an estimate not taken is not retried at once: a second of
        // rest keeps a failing solve from taking a core.
        if (!adopted) std::this_thread::sleep_for(std::chrono::seconds(1));
      }
    });
  }
  bool failed = false;
  try {
    while (!stop && !receiver_failed) {
      if (impl_->queue.PopWait(&sample, std::chrono::milliseconds(20))) Process(&sample);
      const double now = NowSeconds();
      if (now >= next_publish) {
        Publish(utime());
        next_publish = now + 1.0 / options_.publish_rate_hz;
      }
      if (now >= next_checkpoint) {
        Checkpoint();
        next_checkpoint = now + options_.checkpoint_interval_s;
      }
      if (diagnosis_ && now >= next_diagnosis) {
        PublishDiagnosis(utime());
        next_diagnosis = now + options_.diagnosis_period_s;
      }
      if (model_request_ != nullptr && model_request_->exchange(false)) WriteModel();
    }
  } catch (const std::exception& e) {
    Log(LogLevel::kError, std::string("estimation stopped: ") + e.what());
    failed = true;
  }
  receiver_stop = true;
  receiver.join();
  solver_stop = true;
  if (solver.joinable()) solver.join();
  if (failed) return 1;
  while (impl_->queue.PopWait(&sample, std::chrono::milliseconds(0))) Process(&sample);
  if (robot_) {  // the final estimate: identify's fit of every sample kept, as replay's
    std::lock_guard<std::mutex> lock(process_mutex_);
    try {
      pipeline_->Solve(true);
    } catch (const std::exception& e) {  // the checkpoint and the model are still written
      Log(LogLevel::kError, std::string("the final solve failed: ") + e.what());
    }
  }
  Publish(utime());
  FinalDiagnosis(utime());
  Checkpoint();
  WriteModel();
  Log(LogLevel::kInfo, CountersText());
  if (receiver_failed) {
    Log(LogLevel::kError, impl_->bus ? "the CAN bus failed" : "LCM stopped receiving");
    return 1;
  }
  return 0;
}

DaemonCounters EstimationDaemon::counters() const {
  DaemonCounters c;
  {
    std::lock_guard<std::mutex> lock(process_mutex_);
    c.samples = pipeline_->counters();
  }
  c.samples = TotalCounters(impl_->decoded(), c.samples, impl_->dropped());
  std::lock_guard<std::mutex> lock(sinks_mutex_);
  c.published = published_;
  c.checkpoints = checkpoints_;
  c.checkpoint_failures = checkpoint_failures_;
  c.publish_failures = publish_failures_;
  c.diagnoses = diagnoses_;
  c.payload_events = payload_events_published_;
  if (diagnosis_) c.diagnosis_dropped = diagnosis_->dropped();
  return c;
}

std::string EstimationDaemon::CountersText() const {
  const DaemonCounters c = counters();
  const SampleCounters& s = c.samples;
  const std::uint64_t dropped = s[Rejection::kQueueFull];
  std::ostringstream out;
  out << "received " << s.received << ", accepted " << s.accepted << ", rejected " << s.total_rejected() - dropped;
  const std::string reasons = RejectionsText(s, Rejection::kQueueFull);
  if (!reasons.empty()) out << " (" << reasons << ")";
  out << ", dropped " << dropped << "; published " << c.published << " estimates, " << c.checkpoints
      << " checkpoints";
  if (c.diagnoses > 0) out << "; " << c.diagnoses << " diagnoses";
  if (c.payload_events > 0) out << "; " << c.payload_events << " payload events";
  if (c.diagnosis_dropped > 0) out << "; " << c.diagnosis_dropped << " samples the diagnosis had no room for";
  if (c.publish_failures > 0) out << "; " << c.publish_failures << " estimates LCM could not send";
  if (c.checkpoint_failures > 0) out << "; " << c.checkpoint_failures << " checkpoints that could not be written";
  return out.str();
}

}  // namespace inertial
