// The parts of the `inertial` Python module, each defined in its own file.
#pragma once

#include <pybind11/pybind11.h>

namespace inertial::python {

void BindInertia(pybind11::module_& m);   // bind_inertia.cpp: parameterizations, consistency
void BindRobot(pybind11::module_& m);     // bind_robot.cpp: Robot (URDF, regressor, dynamics)
void BindIdentify(pybind11::module_& m);  // bind_identify.cpp: identify on files or arrays
void BindOnline(pybind11::module_& m);    // bind_online.cpp: OnlineEstimator

}  // namespace inertial::python
