#include "inertial/runtime/estimation_daemon.hpp"


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

#include "inertial/report/uncertainty_report.hpp"
#include "inertial/estimate_t.hpp"
#include "inertial/estimation/parameter_layout.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inertial/transport/body_message.hpp"
#include "inertial/runtime/bounded_queue.hpp"
#include "inertial/formats/estimator_state_file.hpp"
#include "inertial/transport/lcm_log_check.hpp"
#include "inertial/model/rigid_body_regressor.hpp"
#include "inertial/residual_t.hpp"

namespace inertial {
namespace {

double NowSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// The estimator statuses reported as rejection reasons.
const char* RejectionName(UpdateStatus s) {
  switch (s) {
    case UpdateStatus::kNonFinite: return "non_finite";
    case UpdateStatus::kOutOfOrder: return "out_of_order";
    case UpdateStatus::kWrongSize: return "wrong_size";
    case UpdateStatus::kOutlier: return "outlier";
    case UpdateStatus::kNumerical: return "numerical";
    default: return nullptr;
  }
}

}  // namespace

std::uint64_t DaemonCounters::total_rejected() const {
  std::uint64_t n = 0;
  for (const auto& [reason, count] : rejected) n += count;
  return n;
}

struct EstimationDaemon::Sample {
  JointSample joint;
  BodySample body;
};

struct EstimationDaemon::Impl {
  Impl(const DaemonOptions& o, std::optional<JointMessageDecoder> d, const Sample& prototype)
      : lcm(o.lcm_url), decoder(std::move(d)), queue(o.queue_capacity, prototype), scratch(prototype) {}
  lcm::LCM lcm;  // received on by the receiver thread, published on by the estimator thread
  std::optional<JointMessageDecoder> decoder;  // robot mode; single-body messages need no state
  std::optional<CanJointAssembler> assembler;  // CAN mode: frames from `bus` instead of LCM
  std::unique_ptr<CanBus> bus;
  BoundedQueue<Sample> queue;
  Sample scratch;  // decoded by the receiver thread only
  EstimationDaemon* owner = nullptr;

  // A rejection is logged at warn the first time its reason occurs, then at debug level (counted).
  void LogRejection(const std::string& reason, const std::string& text) {
    const bool first = owner->FirstTime("rejected " + reason);
    owner->Log(first ? LogLevel::kWarn : LogLevel::kDebug,
               text + (first ? " (further '" + reason + "' rejections are counted, not logged at warn)" : ""));
  }

  // CAN mode: one frame into the assembler; a completed tick into the queue.
  void OnFrame(const CanFrame& frame) {
    const CanCounters before = assembler->counters();
    std::string why;
    const bool tick = assembler->Feed(frame, &scratch.joint, &why);
    const bool dropped = tick && !queue.TryPush(scratch);
    const CanCounters& after = assembler->counters();
    {
      std::lock_guard<std::mutex> lock(owner->counters_mutex_);
      ++owner->counters_.received;
      auto add = [&](const char* reason, std::uint64_t a, std::uint64_t b) {
        if (b > a) owner->counters_.rejected[reason] += b - a;
      };
      add("unknown_id", before.unknown_id, after.unknown_id);
      add("malformed", before.malformed, after.malformed);
      add("error_frame", before.error_frames, after.error_frames);
      add("late", before.late, after.late);
      add("superseded", before.superseded, after.superseded);
      add("priming", before.priming, after.priming);
      if (dropped) ++owner->counters_.dropped;
    }
    if (after.malformed > before.malformed) LogRejection("malformed", "rejected a CAN frame: " + why);
  }

  void OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    try {
      Handle(rbuf, channel);
    } catch (const std::exception& e) {  // nothing may escape the LCM thread
      {
        std::lock_guard<std::mutex> lock(owner->counters_mutex_);
        ++owner->counters_.received;
        ++owner->counters_.rejected["decode"];
      }
      LogRejection("decode", std::string("a message on ") + owner->options_.input_channel +
                                 " could not be handled: " + e.what());
    }
  }

  void Handle(const lcm::ReceiveBuffer* rbuf, const std::string& /*channel*/) {
    std::string why;
    const MessageRejection r =
        decoder ? decoder->Decode(rbuf->data, rbuf->data_size, rbuf->recv_utime, &scratch.joint, &why)
                : DecodeBodyWrench(rbuf->data, rbuf->data_size, &scratch.body, &why);
    bool dropped = false;
    if (r == MessageRejection::kNone) dropped = !queue.TryPush(scratch);
    {
      std::lock_guard<std::mutex> lock(owner->counters_mutex_);
      ++owner->counters_.received;
      if (r != MessageRejection::kNone) ++owner->counters_.rejected[ToString(r)];
      if (dropped) ++owner->counters_.dropped;
    }
    if (r != MessageRejection::kNone && r != MessageRejection::kPriming) {
      LogRejection(ToString(r), "rejected a message on " + owner->options_.input_channel + " (" + ToString(r) + "): " + why);
    }
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

EstimationDaemon::EstimationDaemon(RobotDynamics model, DaemonOptions options) : options_(std::move(options)) {
  CheckOptions(options_);
  const int n = model.num_dofs(), P = model.num_parameters();
  JointMessageDecoder decoder(options_.format, model.dof_names());
  estimator_ = std::make_unique<OnlineJointEstimator>(std::move(model), Eigen::VectorXd::Zero(P), options_.estimator);
  Sample prototype;
  prototype.joint.q = prototype.joint.qd = prototype.joint.qdd = prototype.joint.tau = Eigen::VectorXd::Zero(n);
  impl_ = std::make_unique<Impl>(options_, std::move(decoder), prototype);
  Start(n);
}

EstimationDaemon::EstimationDaemon(const InertialParams& prior, DaemonOptions options) : options_(std::move(options)) {
  CheckOptions(options_);
  body_ = std::make_unique<OnlineBodyEstimator>(prior, options_.estimator);
  impl_ = std::make_unique<Impl>(options_, std::nullopt, Sample{});
  Start(6);
}

EstimationDaemon::EstimationDaemon(RobotDynamics model, DaemonOptions options, CanConfig can, std::unique_ptr<CanBus> bus)
    : options_(std::move(options)) {
  CheckOptions(options_);
  if (!bus) throw std::invalid_argument("inertiald: no CAN bus");
  const int n = model.num_dofs(), P = model.num_parameters();
  CanJointAssembler assembler(std::move(can), model.dof_names());
  estimator_ = std::make_unique<OnlineJointEstimator>(std::move(model), Eigen::VectorXd::Zero(P), options_.estimator);
  Sample prototype;
  prototype.joint.q = prototype.joint.qd = prototype.joint.qdd = prototype.joint.tau = Eigen::VectorXd::Zero(n);
  impl_ = std::make_unique<Impl>(options_, std::nullopt, prototype);
  std::vector<CanId> ids;
  for (const MotorConfig& m : assembler.config().motors) ids.push_back({m.can_id, m.extended});
  bus->SetFilters(ids);
  impl_->assembler.emplace(std::move(assembler));
  impl_->bus = std::move(bus);
  Start(n);
}

void EstimationDaemon::Start(int num_channels) {
  impl_->owner = this;
  if (!impl_->lcm.good()) {
    throw std::runtime_error("LCM could not start on '" + (options_.lcm_url.empty() ? "the default URL" : options_.lcm_url) +
                             "'");
  }
  window_sum_ = window_rms_ = Eigen::VectorXd::Zero(num_channels);
  RecursiveEstimator& est = body_ ? body_->estimator() : estimator_->estimator();
  if (!options_.checkpoint_path.empty()) {
    const std::filesystem::path path(options_.checkpoint_path);
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
      throw std::runtime_error("--checkpoint '" + options_.checkpoint_path + "' is a directory, not a file");
    }
    // Refused now rather than failing at every interval: the directory must take new files.
    const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
    if (!std::filesystem::is_directory(dir, ec) || ::access(dir.c_str(), W_OK | X_OK) != 0) {
      throw std::runtime_error("--checkpoint '" + options_.checkpoint_path + "': cannot write files in '" + dir.string() +
                               "' (" + (std::filesystem::exists(dir, ec) ? "permission denied" : "no such directory") +
                               ")");
    }
  }
  if (!options_.checkpoint_path.empty() && std::filesystem::exists(options_.checkpoint_path)) {
    // Not restored: refuse to start (the file is left as it is) unless told to start afresh.
    auto unusable = [&](const std::string& why) {
      if (!options_.start_fresh) {
        throw std::runtime_error("--checkpoint '" + options_.checkpoint_path + "' " + why +
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
    if (!state) {
      // already reported
    } else if (description != Description()) {
      unusable("is a checkpoint of another model or estimator (" + description + ")");
    } else if (!est.Restore(*state, &why)) {
      unusable("cannot be restored: " + why);
    } else {
      restored_ = true;
      Log(LogLevel::kInfo, "restored " + options_.checkpoint_path + " (" + std::to_string(state->counters.accepted()) +
                               " samples, last at t = " + std::to_string(state->last_time) + " s)");
    }
  }
  if (!impl_->bus) impl_->lcm.subscribe(options_.input_channel, &Impl::OnMessage, impl_.get());
}

EstimationDaemon::~EstimationDaemon() = default;

const RecursiveEstimator& EstimationDaemon::recursive_estimator() const {
  return body_ ? body_->estimator() : estimator_->estimator();
}

lcm::LCM& EstimationDaemon::lcm() { return impl_->lcm; }

std::string EstimationDaemon::Description() const {
  if (body_) {
    return std::string(body_->estimator().kind()) + " estimator; single body";
  }
  return CheckpointDescription(*estimator_);
}

std::string CheckpointDescription(const OnlineJointEstimator& estimator) {
  std::string d = std::string(ToString(estimator.kind())) + " estimator; joints";
  for (const std::string& j : estimator.model().dof_names()) d += " " + j;
  d += "; parameters";
  for (const std::string& p : estimator.model().ParameterNames()) d += " " + p;
  return d;
}

void EstimationDaemon::WriteModel() {
  if (!model_sink_ || !estimator_) return;
  try {
    model_sink_(*estimator_);
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

void EstimationDaemon::Account(UpdateStatus status, double t, const Eigen::VectorXd& residual) {
  {
    std::lock_guard<std::mutex> lock(counters_mutex_);
    if (status == UpdateStatus::kAccepted) {
      ++counters_.accepted;
    } else if (const char* name = RejectionName(status)) {
      ++counters_.rejected[name];
    }
  }
  if (status != UpdateStatus::kAccepted) return;
  if (window_start_ < 0 || t >= window_start_ + options_.residual_window_s) {
    if (window_count_ > 0) {
      window_rms_ = (window_sum_ / window_count_).cwiseSqrt();
      window_completed_ = true;
    }
    window_sum_.setZero();
    window_count_ = 0;
    window_start_ = t;
  }
  window_sum_ += residual.cwiseAbs2();
  ++window_count_;
  last_t_ = t;
}

void EstimationDaemon::Process(const Sample& sample) {
  if (body_) {
    // The residual of the estimate before this sample (samples with an acceleration only; pairs
    // by the midpoint rule have none of their own).
    const BodySample& b = sample.body;
    Vector6 residual = Vector6::Zero();
    if (b.has_acceleration) residual = b.wrench - RigidBodyRegressor(b.twist, b.acceleration, b.gravity) * body_->Body().vector();
    const UpdateStatus status = body_->Update(b);
    if (status != UpdateStatus::kBuffered) Account(status, b.t, residual);
    return;
  }
  const JointSample& j = sample.joint;
  const UpdateStatus status = estimator_->Update(j);
  Account(status, j.t, estimator_->residual());
  if (!options_.residual_channel.empty()) {
    inertial::residual_t m;
    m.utime = static_cast<std::int64_t>(std::llround(j.t * 1e6));
    m.status = std::string(ToString(status));
    m.num_channels = static_cast<std::int32_t>(j.tau.size());
    m.channel_names = estimator_->model().dof_names();
    m.measured.assign(j.tau.data(), j.tau.data() + j.tau.size());
    const Eigen::VectorXd& p = estimator_->predicted();
    m.predicted.assign(p.data(), p.data() + p.size());
    m.residual.resize(m.measured.size());
    for (size_t k = 0; k < m.measured.size(); ++k) m.residual[k] = m.measured[k] - m.predicted[k];
    impl_->lcm.publish(options_.residual_channel, &m);
  }
}

void EstimationDaemon::Publish(std::int64_t utime) {
  // The last complete window; before the first is complete, the samples so far.
  const Eigen::VectorXd rms =
      !window_completed_ && window_count_ > 0 ? Eigen::VectorXd((window_sum_ / window_count_).cwiseSqrt()) : window_rms_;
  const std::vector<std::uint8_t> bytes =
      body_ ? EncodeBodyEstimate(*body_, "body", utime, rms, options_.residual_window_s, counters())
            : EncodeEstimate(*estimator_, utime, rms, options_.residual_window_s, counters());
  const bool sent = impl_->lcm.publish(options_.estimate_channel, bytes.data(), static_cast<unsigned>(bytes.size())) == 0;
  {
    std::lock_guard<std::mutex> lock(counters_mutex_);
    ++(sent ? counters_.published : counters_.publish_failures);
  }
  if (!sent && FirstTime("publish")) {
    Log(LogLevel::kError, "cannot publish on " + options_.estimate_channel + " (" + options_.lcm_url +
                              "): LCM refused the message; estimation goes on, further failures are counted");
  } else if (sent && Recovered("publish")) {
    Log(LogLevel::kInfo, "publishing on " + options_.estimate_channel + " again");
  }
}

void EstimationDaemon::Checkpoint() {
  if (options_.checkpoint_path.empty()) return;
  try {
    SaveEstimatorState(options_.checkpoint_path, recursive_estimator().State(), Description());
    {
      std::lock_guard<std::mutex> lock(counters_mutex_);
      ++counters_.checkpoints;
    }
    if (Recovered("checkpoint")) Log(LogLevel::kInfo, "checkpoint " + options_.checkpoint_path + " written again");
  } catch (const std::exception& e) {
    {
      std::lock_guard<std::mutex> lock(counters_mutex_);
      ++counters_.checkpoint_failures;
    }
    const bool first = FirstTime("checkpoint");
    Log(first ? LogLevel::kError : LogLevel::kDebug,
        std::string("checkpoint failed: ") + e.what() +
            (first ? " (estimation goes on; further failures are counted, and a success is logged)" : ""));
  }
}

int EstimationDaemon::Run(const std::atomic<bool>& stop) {
  std::atomic<bool> receiver_failed{false}, receiver_stop{false};
  Sample sample = impl_->scratch;  // before the receiver thread writes scratch
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
  auto utime = [&] { return static_cast<std::int64_t>(std::llround(last_t_ * 1e6)); };
  bool failed = false;
  try {
    while (!stop && !receiver_failed) {
      if (impl_->queue.PopWait(&sample, std::chrono::milliseconds(20))) Process(sample);
      const double now = NowSeconds();
      if (now >= next_publish) {
        Publish(utime());
        next_publish = now + 1.0 / options_.publish_rate_hz;
      }
      if (now >= next_checkpoint) {
        Checkpoint();
        next_checkpoint = now + options_.checkpoint_interval_s;
      }
      if (model_request_ != nullptr && model_request_->exchange(false)) WriteModel();
    }
  } catch (const std::exception& e) {
    Log(LogLevel::kError, std::string("estimation stopped: ") + e.what());
    failed = true;
  }
  receiver_stop = true;
  receiver.join();
  if (failed) return 1;
  while (impl_->queue.PopWait(&sample, std::chrono::milliseconds(0))) Process(sample);
  Publish(utime());
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
  std::lock_guard<std::mutex> lock(counters_mutex_);
  return counters_;
}

std::string EstimationDaemon::CountersText() const {
  const DaemonCounters c = counters();
  std::ostringstream out;
  out << "received " << c.received << ", accepted " << c.accepted << ", rejected " << c.total_rejected();
  if (!c.rejected.empty()) {
    out << " (";
    bool first = true;
    for (const auto& [reason, count] : c.rejected) {
      out << (first ? "" : ", ") << reason << " " << count;
      first = false;
    }
    out << ")";
  }
  out << ", dropped " << c.dropped << "; published " << c.published << " estimates, " << c.checkpoints
      << " checkpoints";
  if (c.publish_failures > 0) out << "; " << c.publish_failures << " estimates LCM could not send";
  if (c.checkpoint_failures > 0) out << "; " << c.checkpoint_failures << " checkpoints that could not be written";
  return out.str();
}

namespace {

// One body's part of estimate_t.
inertial::body_estimate_t BodyEstimate(const std::string& name, const InertialParams& body, const Vector10* theta,
                                       const BodyUncertainty* uncertainty) {
  inertial::body_estimate_t b;
  b.name = name;
  const Vector10 pi = body.vector();
  for (int i = 0; i < 10; ++i) {
    b.pi[i] = pi[i];
    b.theta[i] = theta != nullptr ? (*theta)[i] : 0.0;
  }
  b.mass = body.mass();
  const Vector3 com = body.mass() > 0 ? body.com() : Vector3::Zero();
  for (int i = 0; i < 3; ++i) b.com[i] = com[i];
  b.mass_std = 0;
  for (int i = 0; i < 3; ++i) b.com_std[i] = 0;
  for (int i = 0; i < 6; ++i) b.inertia_std[i] = 0;
  if (uncertainty != nullptr && body.mass() > 0) {
    const BodyUncertainty& u = *uncertainty;
    b.mass_std = u.mass;
    for (int i = 0; i < 3; ++i) b.com_std[i] = u.com[i];
    for (int i = 0; i < 6; ++i) b.inertia_std[i] = u.inertia_about_com[i];  // about the COM, as estimate_t says
  }
  const ConsistencyReport c = CheckConsistency(body);
  b.min_triangle_margin = c.min_triangle_margin;
  b.min_pseudo_inertia_eigenvalue = c.min_pseudo_inertia_eigenvalue;
  b.physically_consistent = c.fully_consistent();
  return b;
}

void SetCounters(const DaemonCounters& counters, inertial::estimate_t* m) {
  m->received = static_cast<std::int64_t>(counters.received);
  m->accepted = static_cast<std::int64_t>(counters.accepted);
  m->rejected = static_cast<std::int64_t>(counters.total_rejected());
  m->dropped = static_cast<std::int64_t>(counters.dropped);
  for (const auto& [reason, count] : counters.rejected) {
    m->reject_reasons.push_back(reason);
    m->reject_counts.push_back(static_cast<std::int64_t>(count));
  }
  m->num_reasons = static_cast<std::int32_t>(m->reject_reasons.size());
}

std::vector<std::uint8_t> Encode(const inertial::estimate_t& m) {
  std::vector<std::uint8_t> bytes(static_cast<size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

}  // namespace

std::vector<std::uint8_t> EncodeBodyEstimate(const OnlineBodyEstimator& est, const std::string& name, std::int64_t utime,
                                             const Eigen::VectorXd& residual_rms, double residual_window,
                                             const DaemonCounters& counters) {
  inertial::estimate_t m;
  m.utime = utime;
  m.estimator = std::string(est.estimator().kind());
  const Eigen::VectorXd& x = est.estimator().parameters();
  const Eigen::MatrixXd P = est.estimator().Covariance();
  const bool per_body = m.estimator != "linear_rls";
  const Vector10 theta = per_body ? Vector10(x.head<10>()) : Vector10::Zero();
  const bool with_cov = per_body && P.rows() == x.size() && est.Body().mass() > 0;
  BodyUncertainty u;
  if (with_cov) u = UncertaintyOf(est.Body(), est.layout().BodyCovariance(0, x, P));
  m.bodies.push_back(BodyEstimate(name, est.Body(), per_body ? &theta : nullptr, with_cov ? &u : nullptr));
  m.num_bodies = 1;
  m.num_effects = 0;
  m.channel_names = {"mx", "my", "mz", "fx", "fy", "fz"};
  m.num_channels = 6;
  m.residual_rms.assign(residual_rms.data(), residual_rms.data() + residual_rms.size());
  m.residual_rms.resize(6, 0.0);
  m.residual_window = residual_window;
  SetCounters(counters, &m);
  return Encode(m);
}

std::vector<std::uint8_t> EncodeEstimate(const OnlineJointEstimator& est, std::int64_t utime,
                                         const Eigen::VectorXd& residual_rms, double residual_window,
                                         const DaemonCounters& counters) {
  const RobotDynamics& model = est.model();
  inertial::estimate_t m;
  m.utime = utime;
  m.estimator = std::string(ToString(est.kind()));
  const Eigen::VectorXd& x = est.estimator().parameters();
  const bool per_body = est.kind() != EstimatorKind::kLinearRls;
  // The same standard deviations as replay's and the model file's (uncertainty_report.hpp): each
  // body's in its report frame (a payload's in its link's frame).
  const std::optional<ModelUncertainty> uncertainty = per_body ? FromOnlineEstimator(est) : std::nullopt;
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    const InertialParams body = est.Body(e);
    const Vector10 theta = per_body ? Vector10(x.segment<10>(10 * e)) : Vector10::Zero();
    m.bodies.push_back(BodyEstimate(model.bodies()[e].name, body, per_body ? &theta : nullptr,
                                    uncertainty && body.mass() > 0 ? &uncertainty->bodies[e] : nullptr));
  }
  m.num_bodies = static_cast<std::int32_t>(m.bodies.size());
  const std::vector<std::string> names = model.FeatureNames();
  const Eigen::VectorXd& w = est.coefficients();
  for (int f = model.num_inertia_features(); f < model.num_features(); ++f) {
    m.effect_names.push_back(names[f]);
    m.effect_values.push_back(w[f]);
  }
  m.num_effects = static_cast<std::int32_t>(m.effect_names.size());
  m.channel_names = model.dof_names();
  m.num_channels = static_cast<std::int32_t>(m.channel_names.size());
  m.residual_rms.assign(residual_rms.data(), residual_rms.data() + residual_rms.size());
  m.residual_rms.resize(m.channel_names.size(), 0.0);
  m.residual_window = residual_window;
  SetCounters(counters, &m);
  return Encode(m);
}

}  // namespace inertial
