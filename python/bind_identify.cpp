// inertial.identify: the batch fit of `inertial identify` (eq. 14) on a CSV file or on arrays,
// returning what `identify --json` prints.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <cmath>

#include "arrays.hpp"
#include "bindings.hpp"
#include "inertial/formats/joint_csv.hpp"
#include "inertial/diagnosis/joint_diagnosis.hpp"
#include "inertial/report/diagnosis_report.hpp"
#include "inertial/report/identification_report.hpp"
#include "inertial/formats/model_plausibility.hpp"
#include "inertial/report/plausibility_report.hpp"
#include "inertial/report/validation_report.hpp"
#include "robot.hpp"

namespace inertial::python {
namespace {

// A log: a CSV path (read and differentiated as the CLI reads --data) or a dict of arrays t (N),
// q, qd, qdd, tau (N x n).
JointSamples SamplesOf(const Robot& r, const py::object& data, const std::string& what) {
  if (IsPath(data)) {
    try {
      return ReadJointLog(PathOf(data, what), r.model.dof_names);
    } catch (const CsvError& e) {
      throw py::value_error(e.what());
    }
  }
  if (!py::isinstance<py::dict>(data)) {
    throw py::type_error(what + ": give a CSV path or a dict of arrays t, q, qd, qdd, tau");
  }
  const py::dict d = data.cast<py::dict>();
  const int n = r.dynamics.num_dofs();
  JointSamples s;
  s.joint_names = r.model.dof_names;
  for (const char* key : {"t", "q", "qd", "qdd", "tau"}) {
    if (!d.contains(key)) throw py::value_error(what + ": no array '" + key + "' (t, q, qd, qdd, tau)");
  }
  const auto checked = [&](const char* key) {
    // A view where the array is float64 and C-ordered, else a converted copy; null if not numbers.
    Array a = Array::ensure(py::object(d[key]));
    if (!a) throw py::value_error(what + "['" + key + "']: not an array of numbers");
    return a;
  };
  const Array t = checked("t");
  if (t.ndim() != 1) throw py::value_error(what + "['t']: expected shape (N,), got " + ShapeText(t));
  s.t = VectorOf(t, t.shape(0), what + "['t']");
  s.q = MatrixOf(checked("q"), s.size(), n, what + "['q']");
  s.qd = MatrixOf(checked("qd"), s.size(), n, what + "['qd']");
  s.qdd = MatrixOf(checked("qdd"), s.size(), n, what + "['qdd']");
  s.tau = MatrixOf(checked("tau"), s.size(), n, what + "['tau']");
  for (int i = 1; i < s.size(); ++i) {
    if (!(s.t[i] > s.t[i - 1])) {
      throw py::value_error(what + "['t']: time must increase strictly (row " + std::to_string(i) + ": " +
                            std::to_string(s.t[i]) + " after " + std::to_string(s.t[i - 1]) + ")");
    }
  }
  return s;
}

// nlohmann::json -> Python objects, through the json module (numbers round-trip exactly).
py::object ToPython(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

// diagnose: the model fitted on the training data and judged on held-out data (validate, or the
// last `holdout` of data), the missing effects ranked (`inertial diagnose --json`).
py::dict Diagnose(const Robot& robot, const py::object& data, const py::object& validate, double holdout,
                  double min_explained) {
  JointSamples train, validation;
  std::string source = "validate";
  if (validate.is_none()) {
    if (!(holdout > 0.0 && holdout < 1.0)) throw py::value_error("holdout: must be between 0 and 1");
    SplitHoldout(SamplesOf(robot, data, "data"), holdout, &train, &validation);
    source = "the last " + std::to_string(static_cast<int>(std::lround(100 * holdout))) + " % of data";
  } else {
    train = SamplesOf(robot, data, "data");
    validation = SamplesOf(robot, validate, "validate");
  }
  if (!(min_explained > 0.0 && min_explained <= 1.0)) {
    throw py::value_error("min_explained: must be in (0, 1], the share of the held-out error an effect must explain");
  }
  JointDiagnosisOptions options;
  options.min_explained = min_explained;
  const RobotModel& model = robot.model;
  const Vector3 gravity = robot.dynamics.gravity();
  const RobotModelFactory make = [&](const std::vector<EffectSpec>& e) { return MakeRobotDynamics(model, e, gravity); };
  try {
    JointDiagnosis d;
    {
      py::gil_scoped_release release;
      d = DiagnoseJointModel(make, robot.effects, model.body_links, train, validation, options);
    }
    return ToPython(JointDiagnosisJson(MakeJointDiagnosisContext(robot.dynamics, d, source, min_explained)));
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
}

// validate: the model at x (default: the URDF with the effect values it states) judged on data.
py::dict Validate(const Robot& robot, const py::object& data, const std::optional<Array>& x_in) {
  const JointSamples samples = SamplesOf(robot, data, "data");
  try {
    const Eigen::VectorXd x = x_in ? VectorOf(*x_in, robot.dynamics.num_parameters(), "x")
                                   : robot.dynamics.ParametersFromEffectValues(robot.model.effects);
    ModelValidation v = ValidateJointModel(robot.dynamics, x, samples);
    v.model_source = robot.urdf;  // named as `inertial validate` names them
    for (const ModelEffect& e : robot.model.effects) {
      v.model_source += (&e == &robot.model.effects.front() ? " with " : ", ") + std::string(ToString(e.spec.kind)) +
                        "@" + e.spec.target;
    }
    v.data_source = IsPath(data) ? PathOf(data, "data") : std::string("arrays");
    nlohmann::json j = ValidationJson(v);
    // The bodies' plausibility, as `inertial validate --json` adds it (without --total-mass).
    const nlohmann::json judged = ModelPlausibilityJson(JudgeModelBodies(robot.model, robot.dynamics, x));
    j["plausibility"] = judged["bodies"];
    j["plausible"] = judged["plausible"];
    return ToPython(j);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
}

}  // namespace

void BindIdentify(py::module_& m) {
  m.def("diagnose", &Diagnose, py::arg("robot"), py::arg("data"), py::arg("validate") = py::none(),
        py::arg("holdout") = 0.3, py::arg("min_explained") = 0.02,
        "Compares the robot's model, fitted to data, with held-out data (validate, or the last `holdout` of data), "
        "shows where it fails and ranks the physical effects it lacks (friction, armature, springs, offsets, payloads) "
        "by the held-out error each removes: the fields of `inertial diagnose --json`.");
  m.def("validate", &Validate, py::arg("robot"), py::arg("data"), py::arg("x") = py::none(),
        "Judges the model at x (default: the URDF with the effect values it states) on data, no fit: errors per "
        "joint [N m or N] and where it fails, the fields of `inertial validate --json`.");
  m.def(
      "identify",
      [](const Robot& robot, const py::object& data, const py::object& validate, double prior_weight,
         int max_iterations, bool outlier_rejection) {
        const JointSamples train = SamplesOf(robot, data, "data");
        JointSamples validation;
        if (!validate.is_none()) validation = SamplesOf(robot, validate, "validate");
        if (!(prior_weight >= 0.0) || !std::isfinite(prior_weight)) {
          throw py::value_error("prior_weight: must be finite and >= 0");
        }
        if (max_iterations < 1) throw py::value_error("max_iterations: must be at least 1");
        JointIdentificationOptions options;
        options.prior_weight = prior_weight;
        options.lm.max_iterations = max_iterations;
        OutlierOptions outliers;
        outliers.enabled = outlier_rejection;
        IdentificationRun run;
        {
          py::gil_scoped_release release;
          try {
            run = RunIdentification(robot.dynamics, train, validate.is_none() ? nullptr : &validation, options, outliers);
          } catch (const std::invalid_argument& e) {
            py::gil_scoped_acquire acquire;
            throw py::value_error(e.what());
          }
        }
        py::dict out = ToPython(IdentificationJson(robot.dynamics, run));
        out["x"] = run.fit.x;
        return out;
      },
      py::arg("robot"), py::arg("data"), py::arg("validate") = py::none(), py::arg("prior_weight") = 0.01,
      py::arg("max_iterations") = 1000, py::arg("outlier_rejection") = true,
      "Identifies the robot's links and effects from a log (a CSV path, read as `inertial identify --data` reads it, "
      "or a dict of arrays t [s] (N), q, qd, qdd (N x n, rad or m and their rates), tau (N x n, N m or N)): "
      "Levenberg-Marquardt over log-Cholesky theta relative to the URDF (Rucker and Wensing 2022, eq. 14), every body "
      "physically consistent. Returns the fields of `identify --json` (bodies with standard deviations, effects, "
      "per-joint errors on the training and validation data, rejected rows) plus x, the identified parameters.");
}

}  // namespace inertial::python
