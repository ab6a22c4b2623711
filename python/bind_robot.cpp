// inertial.Robot: a URDF robot's joint-space model on arrays.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <filesystem>

#include "arrays.hpp"
#include "bindings.hpp"
#include "inertial/estimation/batch/joint_identification.hpp"
#include "inertial/model/fourier_trajectory.hpp"
#include "inertial/model/joint_limits.hpp"
#include "inertial/model/joint_simulation.hpp"
#include "robot.hpp"

namespace inertial::python {

Robot Robot::FromUrdf(const std::string& path, const std::string& effects_text, const Vector3& gravity) {
  std::vector<EffectSpec> extra;
  try {
    extra = ParseEffectList(effects_text);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(std::string("effects: ") + e.what());
  }
  RobotModel model;
  try {
    model = LoadUrdf(path);
  } catch (const UrdfError& e) {
    throw py::value_error(e.what());
  }
  if (model.dof_names.empty()) {
    throw py::value_error("'" + path + "' has no moving joint, so its joints' torques show nothing to identify");
  }
  std::vector<EffectSpec> effects = MergeEffects(model.DeclaredEffects(), extra);
  try {
    RobotDynamics dynamics = MakeRobotDynamics(model, effects, gravity);
    return Robot{path, std::move(model), std::move(effects), std::move(dynamics)};
  } catch (const std::invalid_argument& e) {
    throw py::value_error(std::string("effects: ") + e.what());
  }
}

void Robot::WriteUrdf(const Eigen::VectorXd& x, const std::string& path, const std::string& origin) const {
  std::error_code ec;
  if (std::filesystem::equivalent(path, urdf, ec)) {
    throw py::value_error("'" + path + "' is the robot's own URDF: write the model elsewhere (no output overwrites an input)");
  }
  try {
    WriteModelUrdf(urdf, path, model, dynamics, SnapshotAt(dynamics, x), origin);
  } catch (const std::exception& e) {
    throw py::value_error(e.what());
  }
}

namespace {

// Rows of q, qd, qdd: one sample (n,) or N samples (N, n); their count (0 for one sample).
struct States {
  Eigen::MatrixXd q, qd, qdd;
  bool single = false;
};

States StatesOf(const Robot& r, const Array& q, const Array& qd, const Array& qdd) {
  const int n = r.dynamics.num_dofs();
  States s;
  s.single = q.ndim() == 1;
  auto rows = [&](const Array& a, const char* what) -> Eigen::MatrixXd {
    if (s.single) return VectorOf(a, n, what).transpose();
    return MatrixOf(a, q.ndim() == 2 ? q.shape(0) : -1, n, what);
  };
  s.q = rows(q, "q");
  s.qd = rows(qd, "qd");
  s.qdd = rows(qdd, "qdd");
  return s;
}

Eigen::VectorXd ParametersOf(const Robot& r, const std::optional<Array>& x) {
  if (x) return VectorOf(*x, r.dynamics.num_parameters(), "x");
  return PriorParametersWithoutEffects(r.dynamics);
}

// w(x), refused where it overflows (a theta or log-coefficient too large for a double).
Eigen::VectorXd CoefficientsOf(const Robot& r, const Eigen::VectorXd& x) {
  const Eigen::VectorXd w = r.dynamics.Coefficients(x);
  if (!w.allFinite()) {
    throw py::value_error("x: gives coefficients beyond the range of double precision (e^{2 alpha} or e^s overflows)");
  }
  return w;
}

// The robot at x tracking a random Fourier excitation, as `inertial simulate` does (its limits kept,
// computed-torque control at 5 Hz, RK4); a dict of arrays t, q, qd, qdd, tau.
py::dict Simulate(const Robot& r, const std::optional<Array>& x_in, double duration, double rate, int seed,
                  double noise_tau, double amplitude) {
  if (!(duration > 0) || !(rate > 0) || !std::isfinite(duration) || !std::isfinite(rate)) {
    throw py::value_error("duration and rate: must be positive");
  }
  const Eigen::VectorXd w = CoefficientsOf(r, ParametersOf(r, x_in));
  FourierTrajectory reference = RandomFourierTrajectory(r.dynamics.num_dofs(), 5, 0.1, amplitude, seed);
  const int n = static_cast<int>(std::floor(duration * rate + 1e-9)) + 1;
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(n, 0.0, (n - 1) / rate);
  FitExcitationToLimits(r.model.dof_limits, t, 0.05, &reference);  // simulate's margin (simulate_command.cpp)
  const JointDynamicsFn plant = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    return r.dynamics.InverseDynamicsFromCoefficients(w, q, qd, qdd);
  };
  JointSimulationOptions options;
  options.duration = duration;
  options.sample_rate_hz = rate;
  options.internal_step = std::min(5e-4, 1.0 / rate);
  const double bandwidth = 2 * M_PI * 5.0;
  options.kp = Eigen::VectorXd::Constant(1, bandwidth * bandwidth);
  options.kd = Eigen::VectorXd::Constant(1, 2 * 0.7 * bandwidth);
  JointSamples s;
  try {
    py::gil_scoped_release release;
    s = SimulateTracking(plant, plant, [&](double time) { return reference.Evaluate(time); }, options,
                         r.dynamics.dof_names());
  } catch (const std::exception& e) {
    throw py::value_error(std::string("simulation failed: ") + e.what());
  }
  if (noise_tau > 0) s = AddGaussianNoise(s, SampleNoise{0, 0, 0, noise_tau}, static_cast<std::uint64_t>(seed) + 1);
  py::dict d;
  d["t"] = s.t;
  d["q"] = s.q;
  d["qd"] = s.qd;
  d["qdd"] = s.qdd;
  d["tau"] = s.tau;
  return d;
}

}  // namespace

void BindRobot(py::module_& m) {
  py::class_<Robot>(m, "Robot",
                    "A URDF robot's joint-space dynamics tau = A(q, qd, qdd) w(x): its links (and rotors, payloads) "
                    "and the joint effects given (viscous, coulomb, armature, spring, offset, ...), as the CLI's "
                    "--model and --effects load them. SI units; joints in joint_names order.")
      .def_static(
          "from_urdf",
          [](const py::object& path, const std::string& effects, const Array& gravity) {
            return Robot::FromUrdf(PathOf(path, "path"), effects, VectorOf(gravity, 3, "gravity"));
          },
          py::arg("path"), py::arg("effects") = "", py::arg("gravity") = Eigen::Vector3d(0, 0, -9.81),
          "Loads a URDF; effects as the CLI's --effects (e.g. 'viscous,coulomb@knee,payload@tool0:mass=2'), gravity "
          "[m/s^2] in the base frame.")
      .def_property_readonly("joint_names", [](const Robot& r) { return r.dynamics.dof_names(); },
                             "The moving joints, in the order of every array's joint axis.")
      .def_property_readonly("body_names", [](const Robot& r) {
        std::vector<std::string> names;
        for (const EstimatedBody& b : r.dynamics.bodies()) names.push_back(b.name);
        return names;
      }, "The estimated bodies: links, then rotors and payloads.")
      .def_property_readonly("parameter_names", [](const Robot& r) { return r.dynamics.ParameterNames(); },
                             "Names of the entries of x (log-Cholesky theta of each body relative to its URDF "
                             "prior, then effect parameters).")
      .def_property_readonly("feature_names", [](const Robot& r) { return r.dynamics.FeatureNames(); },
                             "Names of the columns of the regressor A (each body's pi, then effect coefficients).")
      .def_property_readonly("num_parameters", [](const Robot& r) { return r.dynamics.num_parameters(); })
      .def_property_readonly("num_features", [](const Robot& r) { return r.dynamics.num_features(); })
      .def("prior_parameters", [](const Robot& r) { return Eigen::VectorXd(PriorParametersWithoutEffects(r.dynamics)); },
           "x of the URDF as it is: every body at its prior, every effect coefficient zero.")
      .def("coefficients", [](const Robot& r, const Array& x) {
        return CoefficientsOf(r, VectorOf(x, r.dynamics.num_parameters(), "x"));
      }, py::arg("x"), "w(x): each body's pi (10) and the effect coefficients, the columns of the regressor's order.")
      .def(
          "regressor",
          [](const Robot& r, const Array& q, const Array& qd, const Array& qdd) -> py::array_t<double> {
            const States s = StatesOf(r, q, qd, qdd);
            const int n = r.dynamics.num_dofs(), F = r.dynamics.num_features();
            const py::ssize_t N = s.q.rows();
            py::array_t<double> out(s.single ? std::vector<py::ssize_t>{n, F} : std::vector<py::ssize_t>{N, n, F});
            Eigen::MatrixXd A(n, F);
            TreeWorkspace ws = r.dynamics.MakeWorkspace();
            for (py::ssize_t i = 0; i < N; ++i) {
              r.dynamics.Features(s.q.row(i).transpose(), s.qd.row(i).transpose(), s.qdd.row(i).transpose(), &ws, A);
              Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
                  out.mutable_data() + i * n * F, n, F) = A;
            }
            return out;
          },
          py::arg("q"), py::arg("qd"), py::arg("qdd"),
          "The regressor A (n x num_features) at one state (q, qd, qdd of shape (n,)), or one per row for arrays of "
          "shape (N, n): (N, n, num_features). tau = A @ coefficients(x).")
      .def(
          "inverse_dynamics",
          [](const Robot& r, const Array& q, const Array& qd, const Array& qdd, const std::optional<Array>& x) {
            const States s = StatesOf(r, q, qd, qdd);
            const Eigen::VectorXd w = CoefficientsOf(r, ParametersOf(r, x));
            Eigen::MatrixXd tau(s.q.rows(), r.dynamics.num_dofs());
            for (Eigen::Index i = 0; i < s.q.rows(); ++i) {
              tau.row(i) = r.dynamics.InverseDynamicsFromCoefficients(w, s.q.row(i).transpose(), s.qd.row(i).transpose(),
                                                                      s.qdd.row(i).transpose()).transpose();
            }
            return s.single ? py::cast(Eigen::VectorXd(tau.row(0).transpose())) : py::cast(tau);
          },
          py::arg("q"), py::arg("qd"), py::arg("qdd"), py::arg("x") = py::none(),
          "Joint torques [N m or N] by recursive Newton-Euler plus the effects, at x (default: the URDF as it is); "
          "(n,) for one state, (N, n) for N.")
      .def(
          "write_urdf",
          [](const Robot& r, const Array& x, const py::object& path) {
            r.WriteUrdf(VectorOf(x, r.dynamics.num_parameters(), "x"), PathOf(path, "path"), "identified (Python)");
          },
          py::arg("x"), py::arg("path"),
          "Writes the model at x (e.g. identify()['x']) as a model file: the URDF with the identified inertias and "
          "every effect, as `identify --write-urdf` does; `validate --model` and Robot.from_urdf read it back.")
      .def("simulate", &Simulate, py::arg("x") = py::none(), py::arg("duration") = 20.0, py::arg("rate") = 500.0,
           py::arg("seed") = 1, py::arg("noise_tau") = 0.0, py::arg("amplitude") = 0.9,
           "The robot at x (default: the URDF as it is, no effect) tracking a random Fourier excitation (seed) under "
           "computed-torque control, as `inertial simulate` does, within the URDF's limits: a dict of arrays t [s] "
           "(N), q, qd, qdd, tau (N x n), tau with Gaussian noise of standard deviation noise_tau [N m or N]. The "
           "dict is what identify() takes.");
}

}  // namespace inertial::python
