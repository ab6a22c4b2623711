#include "inertial/formats/body_representation.hpp"

#include <stdexcept>

#include "inertial/inertia/log_cholesky.hpp"

namespace inertial {
namespace {

using RowMajor4 = Eigen::Matrix<double, 4, 4, Eigen::RowMajor>;
using RowMajor6 = Eigen::Matrix<double, 6, 6, Eigen::RowMajor>;

Vector10 PiOf(const std::string& from, const std::vector<double>& v, const LogCholeskyParameterization& lc) {
  const Eigen::Map<const Vector10> ten(v.data());
  if (from == "pi") return ten;
  if (from == "theta") return lc.ToPi(ten);
  if (from == "mci") {
    Matrix3 I;
    I << ten[4], ten[7], ten[9], ten[7], ten[5], ten[8], ten[9], ten[8], ten[6];
    if (!(ten[0] != 0.0)) throw std::invalid_argument("mci: mass is zero, the center of mass is undefined");
    return InertialParams::FromMassComInertia(ten[0], ten.segment<3>(1), I).vector();
  }
  if (from == "pseudo") return InertialParams::FromPseudoInertia(Eigen::Map<const RowMajor4>(v.data())).vector();
  return InertialParams::FromSpatialInertia(Eigen::Map<const RowMajor6>(v.data())).vector();
}

Eigen::MatrixXd Represent(const InertialParams& body, const BodyConversionRequest& request,
                          const LogCholeskyParameterization& lc) {
  const std::string& to = request.to;
  if (to == "pi") return body.vector();
  if (to == "theta") {
    Vector10 theta;
    if (request.from == "theta" && request.reference) {
      theta = Eigen::Map<const Vector10>(request.values.data());  // identity conversion
    } else if (!lc.FromPi(body.vector(), &theta)) {
      throw std::invalid_argument("the body has no log-Cholesky parameters (its pseudo-inertia has no Cholesky factor)");
    }
    return theta;
  }
  if (to == "mci") {
    if (!(body.mass() != 0.0)) throw std::invalid_argument("--to mci: the mass is zero, so there is no center of mass");
    const Matrix3 I = body.rotational_inertia_about_com();
    Vector10 m;
    m << body.mass(), body.com(), I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(1, 2), I(0, 2);
    return m;
  }
  if (to == "pseudo") return body.pseudo_inertia();
  return body.spatial_inertia();
}

}  // namespace

const std::map<std::string, int>& BodyRepresentationSizes() {
  static const std::map<std::string, int> sizes = {
      {"pi", 10}, {"theta", 10}, {"mci", 10}, {"pseudo", 16}, {"spatial", 36}};
  return sizes;
}

BodyConversion ConvertBody(const BodyConversionRequest& request) {
  const std::string& from = request.from;
  const std::size_t size = static_cast<std::size_t>(BodyRepresentationSizes().at(from));
  if (BodyRepresentationSizes().count(request.to) == 0) throw std::out_of_range("unknown representation " + request.to);
  if (request.values.size() != size) {
    throw std::invalid_argument(from + " takes " + std::to_string(size) + " numbers, got " +
                                std::to_string(request.values.size()));
  }
  const LogCholeskyParameterization lc = request.reference ? LogCholeskyParameterization(*request.reference)
                                                           : LogCholeskyParameterization();
  const InertialParams body = InertialParams::FromVector(PiOf(from, request.values, lc));
  if (from == "theta" && !body.AllFinite()) {
    throw std::invalid_argument("theta gives a body beyond the range of double precision (e^{2 alpha} or a product overflows)");
  }
  BodyConversion out;
  out.to = request.to;
  out.consistency = CheckConsistency(body);
  out.consistent = out.consistency.fully_consistent() ||
                   (from == "theta" && lc.YieldsConsistentBody(Eigen::Map<const Vector10>(request.values.data())));
  if (!out.consistent && (!request.allow_inconsistent || request.to == "theta")) {
    throw std::invalid_argument("input (" + from + ") is not a fully physically consistent body: " +
                                out.consistency.reason);
  }
  out.value = Represent(body, request, lc);
  return out;
}

}  // namespace inertial
