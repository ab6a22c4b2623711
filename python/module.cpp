// The `inertial` Python module: the C++ libraries on NumPy arrays (no second implementation).
#include "bindings.hpp"

PYBIND11_MODULE(inertial, m) {
  m.doc() =
      "Physically consistent rigid-body inertia estimation (Rucker and Wensing, 'Smooth Parameterization of "
      "Rigid-Body Inertia', RA-L 2022): the log-Cholesky parameterization, URDF robots' regressors and dynamics, and "
      "the batch identification of the `inertial` command-line tool, on NumPy arrays. SI units throughout.";
  inertial::python::BindInertia(m);
  inertial::python::BindRobot(m);
  inertial::python::BindIdentify(m);
  inertial::python::BindOnline(m);
}
