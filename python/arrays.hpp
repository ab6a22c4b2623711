// NumPy arrays in and out of the binding: shapes checked with messages naming the argument, as the
// CLI names an option ("theta: expected 10 numbers, got an array of shape (3,)").
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>  // every file: std::optional and vectors cast alike (one definition)

#include <string>

#include "inertial/inertia/types.hpp"

namespace inertial::python {

namespace py = pybind11;
/// Any array-like of numbers, as a C-contiguous array of doubles (a copy only if it is not one).
using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// A file path from a str or any os.PathLike (pathlib.Path); ValueError naming `what` for an
/// empty path or one with a NUL character, TypeError for anything else.
std::string PathOf(const py::object& path, const std::string& what);
/// Whether `o` is a path (str or os.PathLike) rather than, say, a dict of arrays.
bool IsPath(const py::object& o);

/// "(3,)", "(2, 4)".
std::string ShapeText(const Array& a);

/// A vector of n numbers; ValueError naming `what` otherwise (and if not finite, when `finite`).
Eigen::VectorXd VectorOf(const Array& a, Eigen::Index n, const std::string& what, bool finite = true);
/// An rows x cols matrix; rows < 0 takes any number of rows. ValueError naming `what` otherwise.
Eigen::MatrixXd MatrixOf(const Array& a, Eigen::Index rows, Eigen::Index cols, const std::string& what,
                         bool finite = true);

}  // namespace inertial::python
