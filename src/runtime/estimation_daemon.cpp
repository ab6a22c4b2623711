#include "inertial/runtime/estimation_daemon.hpp"

#include "inertial/report/online_diagnosis_report.hpp"
#include "inertial/report/payload_report.hpp"
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
#include "inertial/runtime/slot_ring.hpp"
#include "inertial/signal/stream_gap_counter.hpp"
#include "inertial/transport/lcm_log_check.hpp"

namespace inertial {
namespace {

// A payload event's log line, with a pick-up as the controllers load it (the formatter of
// `inertial payload`).
std::string PayloadEventLine(const PayloadEvent& event) {
  std::string text = PayloadEventText(event);
  if (const std::optional<PayloadValues> p = PayloadValuesOf(event)) {
    text += "; in " + event.link + "'s frame, URScript " + UrScriptPayload(*p) + ", Franka " + FrankaSetLoad(*p);
  }
  return text;
}

double NowSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

// What the estimator thread hands the publisher thread: a slot of the ring, made once (the
// residual's vectors sized for the robot), so that filling one with a residual or a request
// allocates nothing. A payload event (rare: a payload picked up or put down) is encoded on the
// estimator thread, which allocates as it always did; its bytes and log line go into room reserved
// for a typical one (256 bytes each, queue_capacity slots: kept small, the ring is mostly residuals).
struct EstimationDaemon::Outgoing {
  enum Kind : int { kEstimate, kDiagnosis, kResidual, kPayloadEvent };
  int kind = kEstimate;
  std::int64_t utime = 0;
  UpdateStatus status = UpdateStatus::kAccepted;
  Eigen::VectorXd measured, predicted;  // kResidual
  std::vector<std::uint8_t> bytes;      // kPayloadEvent: the encoded event
  std::string text;                     // kPayloadEvent: its log line
};

namespace {

// A log line of the receiver's, for the writer thread to write.
struct LogLine {
  LogLevel level = LogLevel::kInfo;
  std::string text;
};

template <typename T>
T Reserved(T prototype, std::size_t bytes, std::size_t text) {
  prototype.bytes.reserve(bytes);
  prototype.text.reserve(text);
  return prototype;
}

LogLine ReservedLine() {
  LogLine l;
  l.text.reserve(512);
  return l;
}

}  // namespace

// The receiver's half: the source and the decoding stage, and the queue into the estimator thread;
// and the sinks' hand-overs.
struct EstimationDaemon::Impl {
  Impl(const DaemonOptions& o, SampleDecoder d, const Sample& prototype, const Outgoing& outgoing_prototype)
      : lcm(o.lcm_url),
        decoder(std::move(d)),
        queue(o.queue_capacity, prototype),
        scratch(prototype),
        outgoing(o.queue_capacity, outgoing_prototype),
        receiver_log(64, ReservedLine()) {}
  lcm::LCM lcm;  // received on by the receiver thread, published on by the publisher thread
  SampleDecoder decoder;         // receiver thread, under decode_mutex
  std::unique_ptr<CanBus> bus;   // CAN mode: frames from here instead of LCM
  BoundedQueue<Sample> queue;
  Sample scratch;  // decoded into by the receiver thread only
  mutable std::mutex decode_mutex;  // decoder, gaps and queue_full, against counters() from other threads
  std::uint64_t queue_full = 0;
  StreamGapCounter gaps;           // the decoded samples' time stamps, under decode_mutex
  bool count_gaps = true;          // false where time stamps are arrival times (a format without one)
  EstimationDaemon* owner = nullptr;

  // Estimator thread -> publisher thread.
  SlotRing<Outgoing> outgoing;
  Doorbell publisher_bell;
  inertial::residual_t residual;  // the publisher's; channel names set once
  // Receiver thread -> writer thread; the estimator's requests of a checkpoint or a model file.
  SlotRing<LogLine> receiver_log;
  Doorbell writer_bell;
  std::atomic<bool> checkpoint_pending{false}, model_pending{false};
  std::atomic<std::uint64_t> residuals_dropped{0}, messages_dropped{0}, log_lines_dropped{0},
      checkpoints_coalesced{0}, models_coalesced{0};

  // A rejection is logged at warn the first time its reason occurs, then at debug level (counted).
  // The receiver does not write: the line goes to the writer thread.
  void LogRejection(Rejection r, const std::string& text) {
    const std::string reason(ToString(r));
    const bool first = owner->FirstTime("rejected " + reason);
    const LogLevel level = first ? LogLevel::kWarn : LogLevel::kDebug;
    if (static_cast<int>(level) > static_cast<int>(owner->options_.log_level)) return;
    LogLine* line = receiver_log.Claim();
    if (line == nullptr) {
      ++log_lines_dropped;
      return;
    }
    line->level = level;
    line->text = text + (first ? " (further '" + reason + "' rejections are counted, not logged at warn)" : "");
    receiver_log.Commit();
    writer_bell.Ring();
  }
  // Writer thread (or Run after the threads stopped): the receiver's lines, written.
  void WriteReceiverLog() {
    while (LogLine* line = receiver_log.Front()) {
      owner->Log(line->level, line->text);
      receiver_log.Pop();
    }
  }

  // A decoded sample into the queue (a full queue drops it, counted), its time to the gap counter.
  void Push() {
    if (count_gaps) {
      std::lock_guard<std::mutex> lock(decode_mutex);
      gaps.Observe(scratch.time(decoder.body_mode()));
    }
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
      if (!decoded) gaps.Skip();  // maybe the sample a gap will miss: it was received, and counted rejected
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
  if (robot_) pipeline_->SetLogGains(options_.log_gains);
  const Sample prototype = robot_ ? Sample::ForJoints(robot_->model().num_dofs()) : Sample{};
  const bool can = decoder.can_mode();
  const std::vector<CanId> ids = decoder.can_ids();
  // Time stamps that are the receive time (a format without one) show the network's jitter and
  // bursts, not the stream's gaps: no gap counting on them.
  const bool own_time = decoder.body_mode() || can || !options_.format.utime_field.empty();
  Outgoing outgoing;
  if (robot_) {
    outgoing.measured = outgoing.predicted = Eigen::VectorXd::Zero(robot_->model().num_dofs());
  }
  impl_ = std::make_unique<Impl>(options_, std::move(decoder), prototype, Reserved(outgoing, 256, 256));
  impl_->owner = this;
  impl_->count_gaps = own_time;
  if (robot_) {
    inertial::residual_t& m = impl_->residual;
    m.num_channels = static_cast<std::int32_t>(robot_->model().num_dofs());
    m.channel_names = robot_->model().dof_names();
    m.measured.resize(static_cast<size_t>(m.num_channels));
    m.predicted.resize(static_cast<size_t>(m.num_channels));
    m.residual.resize(static_cast<size_t>(m.num_channels));
  }
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
  if (!can) {
    // LCM queues at most 30 messages per subscription by default and drops the rest unseen (before
    // the daemon can count them): 3 ms of a 1 kHz stream played at 10x, less than a scheduling
    // delay of the receiver on a loaded machine. Its queue gets the length of the daemon's own
    // (queue_capacity samples): a stall the daemon's queue would absorb is absorbed before it too.
    lcm::Subscription* subscription = impl_->lcm.subscribe(options_.input_channel, &Impl::OnMessage, impl_.get());
    if (subscription != nullptr) subscription->setQueueCapacity(static_cast<int>(options_.queue_capacity));
  }
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
    std::function<void()> write;
    {
      std::lock_guard<std::mutex> lock(process_mutex_);
      write = model_sink_(*robot_);
    }
    if (write) write();
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
    if (outcome.accepted()) diagnosis_->Observe(sample->joint, pipeline_->last_residual());
  }
  if (payload_events_ && outcome.rejection == Rejection::kNone) {
    if (const std::optional<PayloadEvent> event = payload_events_->Observe(*robot_, sample->joint)) {
      // Rare (a payload picked up or put down): encoded here, published and logged by the publisher.
      Outgoing* o = impl_->outgoing.Claim();
      if (o == nullptr) {
        ++impl_->messages_dropped;
      } else {
        const std::vector<std::uint8_t> bytes = EncodePayloadEvent(*event);
        o->kind = Outgoing::kPayloadEvent;
        o->bytes.assign(bytes.begin(), bytes.end());
        o->text = PayloadEventLine(*event);
        impl_->outgoing.Commit();
        impl_->publisher_bell.Ring();
      }
    }
  }
  if (!robot_ || options_.residual_channel.empty() || outcome.rejection != Rejection::kNone) return;
  // The residual's numbers into a slot sized at start (no allocation; the joint names and the
  // message are the publisher's, prepared once).
  Outgoing* o = impl_->outgoing.Claim();
  if (o == nullptr) {
    ++impl_->residuals_dropped;
    return;
  }
  const JointSample& j = sample->joint;
  o->kind = Outgoing::kResidual;
  o->utime = static_cast<std::int64_t>(std::llround(j.t * 1e6));
  o->status = outcome.status;
  o->measured = j.tau;
  o->predicted = robot_->predicted();
  impl_->outgoing.Commit();
  impl_->publisher_bell.Ring();
}

bool EstimationDaemon::Request(int kind, std::int64_t utime) {
  Outgoing* o = impl_->outgoing.Claim();
  if (o == nullptr) {
    ++impl_->messages_dropped;
    return false;
  }
  o->kind = kind;
  o->utime = utime;
  impl_->outgoing.Commit();
  impl_->publisher_bell.Ring();
  return true;
}

void EstimationDaemon::Deliver(const Outgoing& o) {
  switch (o.kind) {
    case Outgoing::kEstimate:
      Publish();
      return;
    case Outgoing::kDiagnosis:
      PublishDiagnosis(o.utime);
      return;
    case Outgoing::kPayloadEvent:
      if (impl_->lcm.publish(options_.payload_channel, o.bytes.data(), static_cast<unsigned>(o.bytes.size())) == 0) {
        std::lock_guard<std::mutex> sinks(sinks_mutex_);
        ++payload_events_published_;
      }
      Log(LogLevel::kInfo, o.text);
      return;
    case Outgoing::kResidual: {
      inertial::residual_t& m = impl_->residual;
      const auto n = static_cast<size_t>(o.measured.size());
      m.utime = o.utime;
      m.status = std::string(ToString(o.status));
      for (size_t k = 0; k < n; ++k) {
        m.measured[k] = o.measured[static_cast<Eigen::Index>(k)];
        m.predicted[k] = o.predicted[static_cast<Eigen::Index>(k)];
        m.residual[k] = m.measured[k] - m.predicted[k];
      }
      impl_->lcm.publish(options_.residual_channel, &m);
      return;
    }
    default:
      return;
  }
}

void EstimationDaemon::Publish() {
  const DaemonCounters all = counters();
  const SampleCounters& totals = all.samples;
  std::vector<std::string> unexcited;
  {
    std::lock_guard<std::mutex> lock(sinks_mutex_);
    unexcited = unexcited_;
  }
  std::vector<std::uint8_t> bytes;
  {
    std::lock_guard<std::mutex> lock(process_mutex_);
    const auto utime = static_cast<std::int64_t>(std::llround(pipeline_->last_time() * 1e6));
    bytes = EncodeEstimate(*pipeline_, utime, totals, unexcited, all.lost);
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
    // Writer thread (or Run at exit): the state copied under the estimator's lock, written after it.
    EstimatorState state;
    std::string description;
    {
      std::lock_guard<std::mutex> lock(process_mutex_);
      state = pipeline_->estimator().State();
      description = CheckpointDescription(*pipeline_);
    }
    SaveEstimatorState(options_.checkpoint_path, state, description);
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

void EstimationDaemon::ReceiveLoop(const std::atomic<bool>& stop, std::atomic<bool>& failed) {
  CanFrame frame;
  while (!stop) {
    if (impl_->bus) {
      try {
        if (impl_->bus->Read(&frame, 50)) impl_->OnFrame(frame);
      } catch (const std::exception& e) {
        Log(LogLevel::kError, e.what());
        failed = true;
        return;
      }
    } else if (impl_->lcm.handleTimeout(50) < 0) {
      failed = true;
      return;
    }
  }
}

void EstimationDaemon::PublishLoop(const std::atomic<bool>& stop) {
  for (;;) {
    const bool stopping = stop;
    impl_->publisher_bell.Wait(std::chrono::milliseconds(100));
    while (const Outgoing* o = impl_->outgoing.Front()) {
      try {
        if (publisher_hook_) publisher_hook_();
        Deliver(*o);
      } catch (const std::exception& e) {  // bad input never stops the daemon; a sink's failure neither
        if (FirstTime("deliver")) Log(LogLevel::kError, std::string("publishing failed: ") + e.what());
      }
      impl_->outgoing.Pop();
    }
    if (stopping) return;
  }
}

void EstimationDaemon::WriteLoop(const std::atomic<bool>& stop) {
  for (;;) {
    const bool stopping = stop;
    impl_->writer_bell.Wait(std::chrono::milliseconds(100));
    impl_->WriteReceiverLog();
    if (impl_->checkpoint_pending.exchange(false)) Checkpoint();
    if (impl_->model_pending.exchange(false)) WriteModel();
    if (stopping) return;
  }
}

void EstimationDaemon::SolveLoop(const std::atomic<bool>& stop) {
  while (!stop) {
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
}

void EstimationDaemon::FinishRun(std::int64_t utime) {
  // Estimation is over: the last publication, checkpoint and model file are written here, in order.
  std::optional<PayloadEvent> last_event;
  if (robot_) {  // the final estimate: identify's fit of every sample kept, as replay's
    std::lock_guard<std::mutex> lock(process_mutex_);
    try {
      pipeline_->Solve(true);
    } catch (const std::exception& e) {  // the checkpoint and the model are still written
      Log(LogLevel::kError, std::string("the final solve failed: ") + e.what());
    }
    // A payload change confirmed but still settling when the stream stops is concluded on the
    // samples there were, as replay concludes it at the end of a log (payload_event.hpp).
    if (payload_events_) last_event = payload_events_->Flush(*robot_);
  }
  if (last_event) {  // the publisher has stopped: published here
    const std::vector<std::uint8_t> bytes = EncodePayloadEvent(*last_event);
    if (impl_->lcm.publish(options_.payload_channel, bytes.data(), static_cast<unsigned>(bytes.size())) == 0) {
      std::lock_guard<std::mutex> sinks(sinks_mutex_);
      ++payload_events_published_;
    }
    Log(LogLevel::kInfo, PayloadEventLine(*last_event));
  }
  Publish();
  FinalDiagnosis(utime);
  Checkpoint();
  WriteModel();
  Log(LogLevel::kInfo, CountersText());
}

std::int64_t EstimationDaemon::LastUtime() const {
  std::lock_guard<std::mutex> lock(process_mutex_);
  return static_cast<std::int64_t>(std::llround(pipeline_->last_time() * 1e6));
}

void EstimationDaemon::EstimateLoop(const std::atomic<bool>& stop, const std::atomic<bool>& receiver_failed,
                                    Sample* sample_buffer) {
  Sample& sample = *sample_buffer;
  double next_publish = NowSeconds() + 1.0 / options_.publish_rate_hz;
  double next_checkpoint = NowSeconds() + options_.checkpoint_interval_s;
  double next_diagnosis = NowSeconds() + options_.diagnosis_period_s;
  // A request of the writer's: one still pending takes this one's place (it will write the state
  // as it is then), counted.
  auto request_write = [&](std::atomic<bool>& pending, std::atomic<std::uint64_t>& coalesced) {
    if (pending.exchange(true)) ++coalesced;
    impl_->writer_bell.Ring();
  };
  // The estimator thread: pops, processes, hands over. Nothing here publishes, writes or syncs.
  while (!stop && !receiver_failed) {
    if (impl_->queue.PopWait(&sample, std::chrono::milliseconds(20))) Process(&sample);
    const double now = NowSeconds();
    if (now >= next_publish) {
      Request(Outgoing::kEstimate, 0);
      next_publish = now + 1.0 / options_.publish_rate_hz;
    }
    if (now >= next_checkpoint) {
      if (!options_.checkpoint_path.empty()) request_write(impl_->checkpoint_pending, impl_->checkpoints_coalesced);
      next_checkpoint = now + options_.checkpoint_interval_s;
    }
    if (diagnosis_ && now >= next_diagnosis) {
      Request(Outgoing::kDiagnosis, LastUtime());
      next_diagnosis = now + options_.diagnosis_period_s;
    }
    if (model_request_ != nullptr && model_request_->exchange(false)) {
      request_write(impl_->model_pending, impl_->models_coalesced);
    }
  }
}

int EstimationDaemon::Run(const std::atomic<bool>& stop) {
  std::atomic<bool> receiver_failed{false}, receiver_stop{false};
  Sample sample = impl_->scratch;  // before the receiver thread writes scratch (sized once)
  // The receiver only drains the source: decode, note the time, push (Impl).
  std::thread receiver([&] { ReceiveLoop(receiver_stop, receiver_failed); });
  // The publisher: every hand-over of the estimator thread's, published on LCM; the writer:
  // checkpoints and model files (the slow disk's), and the receiver's log lines. At stop, their
  // work is emptied first.
  std::atomic<bool> publisher_stop{false}, writer_stop{false};
  std::thread publisher([&] { PublishLoop(publisher_stop); });
  std::thread writer([&] { WriteLoop(writer_stop); });
  auto stop_sinks = [&] {
    publisher_stop = true;
    impl_->publisher_bell.Ring();
    publisher.join();
    writer_stop = true;
    impl_->writer_bell.Ring();
    writer.join();
    impl_->WriteReceiverLog();  // lines of the receiver's last moments
  };
  Log(LogLevel::kInfo, "listening on " + (impl_->bus ? std::string("the CAN bus") : options_.input_channel) + ", publishing " + options_.estimate_channel + " at " +
                           std::to_string(options_.publish_rate_hz) + " Hz (" +
                           std::to_string(recursive_estimator().num_parameters()) + " parameters, " +
                           std::string(recursive_estimator().kind()) + (body_ ? ", single body" : "") + ")");
  // The solver (gauss_newton of a robot, online_fit.hpp): the objective re-solved on a thread of
  // its own from a snapshot of the statistics, so that the estimator thread only accumulates.
  std::atomic<bool> solver_stop{false};
  std::thread solver;
  if (robot_ && robot_->fit() != nullptr) solver = std::thread([&] { SolveLoop(solver_stop); });
  bool failed = false;
  try {
    EstimateLoop(stop, receiver_failed, &sample);
  } catch (const std::exception& e) {
    Log(LogLevel::kError, std::string("estimation stopped: ") + e.what());
    failed = true;
  }
  receiver_stop = true;
  receiver.join();
  solver_stop = true;
  if (solver.joinable()) solver.join();
  if (failed) {
    stop_sinks();
    return 1;
  }
  while (impl_->queue.PopWait(&sample, std::chrono::milliseconds(0))) Process(&sample);
  stop_sinks();  // the residuals of the last samples published, a pending checkpoint written
  FinishRun(LastUtime());
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
  {
    std::lock_guard<std::mutex> decode(impl_->decode_mutex);
    c.lost = impl_->gaps.lost();
    c.gaps = impl_->gaps.gaps();
    c.longest_gap_s = impl_->gaps.longest_gap();
    c.median_interval_s = impl_->gaps.median_interval();
  }
  c.residuals_dropped = impl_->residuals_dropped;
  c.messages_dropped = impl_->messages_dropped;
  c.log_lines_dropped = impl_->log_lines_dropped;
  c.checkpoints_coalesced = impl_->checkpoints_coalesced;
  c.models_coalesced = impl_->models_coalesced;
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
  // dropped: inside the daemon (its queue was full); lost: before it (gaps in the stream's time stamps).
  out << ", dropped " << dropped << " (queue full); lost " << c.lost << " before the daemon (" << c.gaps
      << " gaps in the time stamps";
  if (c.gaps > 0) out << ", the longest " << c.longest_gap_s << " s";
  if (c.median_interval_s > 0) out << "; median interval " << c.median_interval_s * 1e3 << " ms";
  out << "); published " << c.published << " estimates, " << c.checkpoints << " checkpoints";
  if (c.diagnoses > 0) out << "; " << c.diagnoses << " diagnoses";
  if (c.payload_events > 0) out << "; " << c.payload_events << " payload events";
  if (c.diagnosis_dropped > 0) out << "; " << c.diagnosis_dropped << " samples the diagnosis had no room for";
  if (c.publish_failures > 0) out << "; " << c.publish_failures << " estimates LCM could not send";
  if (c.checkpoint_failures > 0) out << "; " << c.checkpoint_failures << " checkpoints that could not be written";
  const std::uint64_t at_sink = c.residuals_dropped + c.messages_dropped + c.log_lines_dropped;
  out << "; dropped at the sink " << at_sink;
  if (at_sink > 0) {
    out << " (" << c.residuals_dropped << " residuals, " << c.messages_dropped << " estimates, diagnoses or events, "
        << c.log_lines_dropped << " log lines)";
  }
  if (c.checkpoints_coalesced + c.models_coalesced > 0) {
    out << "; coalesced " << c.checkpoints_coalesced << " checkpoints, " << c.models_coalesced << " model files";
  }
  return out.str();
}

}  // namespace inertial
