#include "arrays.hpp"

namespace inertial::python {

bool IsPath(const py::object& o) {
  return py::isinstance<py::str>(o) || py::hasattr(o, "__fspath__");
}

std::string PathOf(const py::object& path, const std::string& what) {
  if (!IsPath(path)) throw py::type_error(what + ": expected a path (str or os.PathLike)");
  const std::string s = py::module_::import("os").attr("fspath")(path).cast<std::string>();
  if (s.empty()) throw py::value_error(what + ": the path is empty");
  if (s.find('\0') != std::string::npos) throw py::value_error(what + ": the path holds a NUL character");
  return s;
}

std::string ShapeText(const Array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d > 0 ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

namespace {
void CheckFinite(const Eigen::Ref<const Eigen::MatrixXd>& m, const std::string& what) {
  if (!m.allFinite()) throw py::value_error(what + ": not every number is finite (NaN or infinity)");
}
}  // namespace

Eigen::VectorXd VectorOf(const Array& a, Eigen::Index n, const std::string& what, bool finite) {
  if (a.ndim() != 1 || a.shape(0) != n) {
    throw py::value_error(what + ": expected " + std::to_string(n) + " numbers, got an array of shape " + ShapeText(a));
  }
  const Eigen::VectorXd v = Eigen::Map<const Eigen::VectorXd>(a.data(), n);
  if (finite) CheckFinite(v, what);
  return v;
}

Eigen::MatrixXd MatrixOf(const Array& a, Eigen::Index rows, Eigen::Index cols, const std::string& what, bool finite) {
  if (a.ndim() != 2 || (rows >= 0 && a.shape(0) != rows) || a.shape(1) != cols) {
    throw py::value_error(what + ": expected an array of shape (" + (rows >= 0 ? std::to_string(rows) : "N") + ", " +
                          std::to_string(cols) + "), got " + ShapeText(a));
  }
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::MatrixXd m = Eigen::Map<const RowMajor>(a.data(), a.shape(0), cols);
  if (finite) CheckFinite(m, what);
  return m;
}

}  // namespace inertial::python
