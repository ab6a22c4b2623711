#include "inertial/inertia/parameterization.hpp"

#include "inertial/inertia/consistency.hpp"
#include "inertial/inertia/inertial_params.hpp"

namespace inertial {

bool Parameterization::YieldsConsistentBody(const Vector10& x) const {
  return x.allFinite() && IsPhysicallyConsistent(InertialParams::FromVector(ToPi(x)));
}

}  // namespace inertial
