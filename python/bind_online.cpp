// inertial.OnlineEstimator: the per-sample estimator of `inertiald` and `replay` (the same
// SamplePipeline: preprocessing, the estimator's update, solves of the online fit when due).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <memory>

#include "arrays.hpp"
#include "bindings.hpp"
#include "inertial/formats/estimator_state_file.hpp"
#include "inertial/formats/model_file.hpp"
#include "inertial/report/online_estimate_text.hpp"
#include "inertial/runtime/estimate_message.hpp"
#include "inertial/runtime/log_replay.hpp"
#include "inertial/runtime/sample_pipeline.hpp"
#include "robot.hpp"

namespace inertial::python {
namespace {

class OnlineEstimator {
 public:
  OnlineEstimator(const Robot& robot, const std::string& kind, double accel_cutoff_hz, double residual_window_s)
      : robot_(robot),
        estimator_(robot.dynamics, Eigen::VectorXd::Zero(robot.dynamics.num_parameters()), Options(kind)),
        pipeline_(&estimator_, accel_cutoff_hz, residual_window_s),
        sample_(Sample::ForJoints(robot.dynamics.num_dofs())) {}

  std::string Update(double t, const Array& q, const Array& qd, const std::optional<Array>& qdd, const Array& tau) {
    const int n = estimator_.model().num_dofs();
    if (!std::isfinite(t)) throw py::value_error("t: not finite (" + std::to_string(t) + ")");
    JointSample& s = sample_.joint;
    s.t = t;
    s.q = VectorOf(q, n, "q", false);  // NaN: refused by the pipeline, counted, as in inertiald
    s.qd = VectorOf(qd, n, "qd", false);
    s.has_qdd = qdd.has_value();
    s.qdd_measured = qdd.has_value();
    s.qdd = qdd ? VectorOf(*qdd, n, "qdd", false) : Eigen::VectorXd::Zero(n);
    s.tau = VectorOf(tau, n, "tau", false);
    const SamplePipeline::Outcome outcome = pipeline_.Process(&sample_);
    pipeline_.Solve();  // the online fit's solve when due (in line, as replay)
    return std::string(outcome.rejection != Rejection::kNone ? ToString(outcome.rejection) : ToString(outcome.status));
  }

  py::dict Estimate() {
    py::dict d = py::module_::import("json").attr("loads")(OnlineEstimateJson(estimator_).dump());
    d["x"] = estimator_.estimator().parameters();
    return d;
  }

  py::object Predict(const Array& q, const Array& qd, const Array& qdd) const {
    const RobotDynamics& m = estimator_.model();
    const int n = m.num_dofs();
    const bool single = q.ndim() == 1;  // one state: (n,) out, as Robot.inverse_dynamics
    const Eigen::MatrixXd Q = single ? Eigen::MatrixXd(VectorOf(q, n, "q").transpose()) : MatrixOf(q, -1, n, "q");
    const Eigen::MatrixXd Qd = single ? Eigen::MatrixXd(VectorOf(qd, n, "qd").transpose()) : MatrixOf(qd, Q.rows(), n, "qd");
    const Eigen::MatrixXd Qdd =
        single ? Eigen::MatrixXd(VectorOf(qdd, n, "qdd").transpose()) : MatrixOf(qdd, Q.rows(), n, "qdd");
    Eigen::MatrixXd tau(Q.rows(), n);
    for (Eigen::Index i = 0; i < Q.rows(); ++i) {
      tau.row(i) = m.InverseDynamicsFromCoefficients(estimator_.coefficients(), Q.row(i).transpose(),
                                                     Qd.row(i).transpose(), Qdd.row(i).transpose()).transpose();
    }
    return single ? py::cast(Eigen::VectorXd(tau.row(0).transpose())) : py::cast(tau);
  }

  py::dict Counters() const {
    const SampleCounters& c = pipeline_.counters();
    py::dict d;
    d["received"] = c.received;
    d["accepted"] = c.accepted;
    d["buffered"] = c.buffered;
    return d;
  }

  void Finish() { pipeline_.Solve(true); }

  // A checkpoint as inertiald writes one (--checkpoint), and back.
  void Save(const py::object& where) const {
    const std::string path = PathOf(where, "path");
    RefuseInput(path);
    try {
      SaveEstimatorState(path, pipeline_.estimator().State(), CheckpointDescription(estimator_));
    } catch (const std::exception& e) {
      throw py::value_error(e.what());
    }
  }
  void Restore(const py::object& where) {
    const std::string path = PathOf(where, "path");
    if (pipeline_.counters().received > 0) {
      throw py::value_error("restore into a new OnlineEstimator: this one has seen " +
                            std::to_string(pipeline_.counters().received) + " samples");
    }
    std::string description, why;
    EstimatorState state;
    try {
      state = LoadEstimatorState(path, &description);
    } catch (const std::exception& e) {
      throw py::value_error(e.what());
    }
    if (description != CheckpointDescription(estimator_)) {
      throw py::value_error("'" + path + "' is a checkpoint of another model or estimator (" + description + ")");
    }
    if (!estimator_.Restore(state, &why)) throw py::value_error("'" + path + "' cannot be restored: " + why);
  }

  void WriteUrdf(const py::object& path) const {
    robot_.WriteUrdf(estimator_.estimator().parameters(), PathOf(path, "path"), "estimated online (Python)");
  }

 private:
  // No output overwrites an input: the robot's URDF.
  void RefuseInput(const std::string& path) const {
    std::error_code ec;
    if (std::filesystem::equivalent(path, robot_.urdf, ec)) {
      throw py::value_error("'" + path + "' is the robot's own URDF: write elsewhere (no output overwrites an input)");
    }
  }

  static OnlineEstimatorOptions Options(const std::string& kind) {
    OnlineEstimatorOptions o;
    try {
      o.kind = ParseEstimatorKind(kind);
    } catch (const std::invalid_argument& e) {
      throw py::value_error(std::string("estimator: ") + e.what());
    }
    return o;
  }

  Robot robot_;  // its URDF and model (write_urdf)
  OnlineJointEstimator estimator_;
  SamplePipeline pipeline_;
  Sample sample_;
};

// A whole log through a new estimator, as `inertial replay` does: the estimate and the counts.
py::dict Replay(const Robot& robot, const py::object& where, const std::string& kind) {
  const std::string log = PathOf(where, "log");
  OnlineEstimatorOptions o;
  try {
    o.kind = ParseEstimatorKind(kind);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(std::string("estimator: ") + e.what());
  }
  OnlineJointEstimator estimator(robot.dynamics, Eigen::VectorXd::Zero(robot.dynamics.num_parameters()), o);
  ReplayOptions options;
  options.log_gains = StatedLogGains(robot.model, robot.model.effects);
  ReplayResult r;
  try {
    py::gil_scoped_release release;
    r = ReplayLog(log, &estimator, options);
  } catch (const std::exception& e) {
    throw py::value_error(e.what());
  }
  py::dict d = py::module_::import("json").attr("loads")(OnlineEstimateJson(estimator).dump());
  py::dict out;
  out["estimate"] = d;
  out["events"] = r.events;
  out["samples"] = r.samples;
  out["received"] = r.counters.received;
  out["accepted"] = r.counters.accepted;
  out["x"] = estimator.estimator().parameters();
  return out;
}

}  // namespace

void BindOnline(py::module_& m) {
  m.def("replay", &Replay, py::arg("robot"), py::arg("log"), py::arg("estimator") = "gauss_newton",
        "Replays a log through a new online estimator, as `inertial replay --log` does: an lcm-logger log of "
        "inertial.joint_state_t or a joint CSV (.csv). Returns the final estimate (as OnlineEstimator.estimate()), "
        "x, and the events, samples, received and accepted counts.");
  py::class_<OnlineEstimator>(
      m, "OnlineEstimator",
      "The online estimator of `inertiald` and `replay`, sample by sample: each update goes through the same "
      "pipeline (time order, where qdd is not given the estimator fits filtered momentum rows, which need none, the glitch gate) into the estimator; "
      "gauss_newton (default) keeps identify's objective (eq. 14) and re-solves it when due, so that after a log it "
      "equals the batch fit; also ekf, gradient, linear_rls.")
      .def(py::init<const Robot&, const std::string&, double, double>(), py::arg("robot"),
           py::arg("estimator") = "gauss_newton", py::arg("accel_cutoff_hz") = 20.0, py::arg("residual_window_s") = 1.0)
      .def("update", &OnlineEstimator::Update, py::arg("t"), py::arg("q"), py::arg("qd"), py::arg("qdd") = py::none(),
           py::arg("tau"),
           "One sample: t [s], q, qd (and qdd if measured; else rows without qdd are fitted) and tau [N m or N] per joint. Returns what became of it: "
           "'accepted', 'held' (the gate waits to see), or the reason it was refused (e.g. 'out_of_order', "
           "'not_finite').")
      .def("estimate", &OnlineEstimator::Estimate,
           "The current estimate: bodies (mass, COM, inertia about the COM, with standard deviations where the "
           "estimator keeps them) and effect coefficients, as `replay --json`'s estimate; x, the parameters.")
      .def("predict", &OnlineEstimator::Predict, py::arg("q"), py::arg("qd"), py::arg("qdd"),
           "Torques [N m or N] the current estimate predicts: (n,) at one state (q, qd, qdd of shape (n,)), (N, n) "
           "at N.")
      .def("counters", &OnlineEstimator::Counters, "Samples received, accepted and buffered so far.")
      .def("save", &OnlineEstimator::Save, py::arg("path"),
           "Writes the estimator's state as inertiald's --checkpoint does (JSON).")
      .def("restore", &OnlineEstimator::Restore, py::arg("path"),
           "Restores, into a new estimator, a state save() (or inertiald) wrote for the same model and estimator; "
           "ValueError saying why not.")
      .def("write_urdf", &OnlineEstimator::WriteUrdf, py::arg("path"),
           "Writes the current estimate as a model file (the robot's URDF with its bodies and effects), as "
           "`identify --write-urdf` does; `validate --model` reads it back.")
      .def("finish", &OnlineEstimator::Finish,
           "Solves identify's objective on every sample seen, from identify's start (what replay does at the end of "
           "a log).");
}

}  // namespace inertial::python
