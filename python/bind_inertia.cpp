// inertial.log_cholesky and friends: the parameterizations and consistency checks on arrays.
#include <pybind11/eigen.h>

#include "arrays.hpp"
#include "bindings.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inertial/inertia/log_cholesky.hpp"

namespace inertial::python {
namespace {

InertialParams BodyOf(const Array& pi, const std::string& what, bool finite = true) {
  return InertialParams::FromVector(VectorOf(pi, 10, what, finite));
}

// The map relative to `reference` (pi of a fully consistent body), or to J0 = 1 (None).
LogCholeskyParameterization MapOf(const std::optional<Array>& reference) {
  if (!reference) return LogCholeskyParameterization();
  try {
    return LogCholeskyParameterization(BodyOf(*reference, "reference"));
  } catch (const std::invalid_argument& e) {
    throw py::value_error(std::string("reference: ") + e.what());
  }
}

constexpr const char* kPiOrder =
    "pi = [m, hx, hy, hz, Ixx, Iyy, Izz, Ixy, Iyz, Ixz]: mass [kg], first moment h = m c [kg m] and rotational "
    "inertia about the frame origin [kg m^2]";

// pi of a map, refused where it overflows (as `inertial convert` refuses it).
Eigen::VectorXd FinitePi(const Vector10& pi) {
  if (!pi.allFinite()) throw py::value_error("theta gives a body beyond the range of double precision (e^{2 alpha} or a product overflows)");
  return pi;
}

}  // namespace

void BindInertia(py::module_& m) {
  m.def(
      "log_cholesky",
      [](const Array& theta, const std::optional<Array>& reference) {
        return FinitePi(MapOf(reference).ToPi(VectorOf(theta, 10, "theta")));
      },
      py::arg("theta"), py::arg("reference") = py::none(),
      (std::string("The inertial parameters pi (10) of log-Cholesky coordinates theta = [alpha, d1, d2, d3, s12, s23, "
                   "s13, t1, t2, t3] (Rucker and Wensing 2022, eq. 8; relative to the body `reference` (its pi) by eq. "
                   "11, theta = 0 being the reference). Every finite theta gives a fully physically consistent body. ") +
       kPiOrder)
          .c_str());
  m.def(
      "log_cholesky_jacobian",
      [](const Array& theta, const std::optional<Array>& reference) {
        Matrix10 J;
        FinitePi(MapOf(reference).ToPi(VectorOf(theta, 10, "theta"), &J));
        return Eigen::MatrixXd(J);
      },
      py::arg("theta"), py::arg("reference") = py::none(),
      "d pi / d theta (10 x 10) of log_cholesky at theta, analytic.");
  m.def(
      "log_cholesky_inverse",
      [](const Array& pi, const std::optional<Array>& reference) {
        try {
          return Eigen::VectorXd(MapOf(reference).ThetaOf(BodyOf(pi, "pi")));
        } catch (const std::invalid_argument& e) {
          throw py::value_error(std::string("pi: ") + e.what());
        }
      },
      py::arg("pi"), py::arg("reference") = py::none(),
      "theta of a fully physically consistent body pi (the inverse of log_cholesky); ValueError saying which "
      "condition fails otherwise.");
  m.def(
      "pi_from_mass_com_inertia",
      [](double mass, const Array& com, const Array& inertia) {
        const Eigen::VectorXd c = VectorOf(com, 3, "com");
        const Matrix3 I = MatrixOf(inertia, 3, 3, "inertia");
        if (!std::isfinite(mass)) throw py::value_error("mass: not finite");
        if (!I.isApprox(I.transpose(), 1e-12) && (I - I.transpose()).norm() > 1e-300) {
          throw py::value_error("inertia: not symmetric (Ixy = I[0, 1] = I[1, 0], and so on)");
        }
        return Eigen::VectorXd(InertialParams::FromMassComInertia(mass, c, I).vector());
      },
      py::arg("mass"), py::arg("com"), py::arg("inertia"),
      (std::string("pi of a body of mass [kg], centre of mass com [m] and rotational inertia about the COM [kg m^2] "
                   "(3 x 3), all in the body's frame. ") +
       kPiOrder)
          .c_str());
  m.def(
      "mass_com_inertia",
      [](const Array& pi) {
        const InertialParams b = BodyOf(pi, "pi");
        if (!(b.mass() != 0.0)) throw py::value_error("pi: the mass is zero, so the body has no centre of mass");
        const Vector3 c = b.com();
        const Matrix3 I = b.rotational_inertia_about_com();
        if (!c.allFinite() || !I.allFinite()) {
          throw py::value_error("pi: the centre of mass is beyond the range of double precision (mass near zero)");
        }
        return py::make_tuple(b.mass(), Eigen::VectorXd(c), Eigen::MatrixXd(I));
      },
      py::arg("pi"), "(mass [kg], com [m] (3), rotational inertia about the COM [kg m^2] (3 x 3)) of pi.");
  m.def(
      "pseudo_inertia", [](const Array& pi) { return Eigen::MatrixXd(BodyOf(pi, "pi").pseudo_inertia()); },
      py::arg("pi"),
      "The 4 x 4 pseudo-inertia J = [[Sigma, h], [h^T, m]] of pi (Sigma: second moments about the origin [kg m^2]); "
      "the body is fully physically consistent exactly when J is positive definite.");
  m.def(
      "pi_from_pseudo_inertia",
      [](const Array& J) {
        try {
          return Eigen::VectorXd(InertialParams::FromPseudoInertia(MatrixOf(J, 4, 4, "J")).vector());
        } catch (const std::invalid_argument& e) {
          throw py::value_error(std::string("J: ") + e.what());
        }
      },
      py::arg("J"), "pi of a symmetric 4 x 4 pseudo-inertia J.");
  m.def(
      "check_consistency",
      [](const Array& pi) {
        const ConsistencyReport r = CheckConsistency(BodyOf(pi, "pi", false));
        py::dict d;
        d["fully_consistent"] = r.fully_consistent();
        d["finite"] = r.finite;
        d["mass_positive"] = r.mass_positive;
        d["inertia_positive_definite_origin"] = r.inertia_positive_definite_origin;
        d["inertia_positive_definite_com"] = r.inertia_positive_definite_com;
        d["triangle_inequalities"] = r.triangle_inequalities;
        d["pseudo_inertia_positive_definite"] = r.pseudo_inertia_positive_definite;
        d["mass"] = r.mass;
        d["min_inertia_eigenvalue_origin"] = r.min_inertia_eigenvalue_origin;
        d["min_inertia_eigenvalue_com"] = r.min_inertia_eigenvalue_com;
        d["principal_moments_com"] = Eigen::VectorXd(r.principal_moments_com);
        d["min_triangle_margin"] = r.min_triangle_margin;
        d["min_pseudo_inertia_eigenvalue"] = r.min_pseudo_inertia_eigenvalue;
        return d;
      },
      py::arg("pi"),
      "Which physical-consistency conditions pi meets, with their margins (Wensing et al. 2017; the paper's Section "
      "III): mass > 0, rotational inertia positive definite about the origin and the COM, the triangle inequalities "
      "of the principal moments (min_triangle_margin [kg m^2], eq. 4), pseudo-inertia positive definite "
      "(min_pseudo_inertia_eigenvalue). NaN or infinite numbers are reported, not raised.");
}

}  // namespace inertial::python
