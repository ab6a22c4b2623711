#include "inertial/report/link_inertial_report.hpp"
#include "inertial/model/number_text.hpp"

#include <cstdio>
#include <sstream>

namespace inertial {
namespace {

// [Ixx Iyy Izz Ixy Iyz Ixz] about the COM.
std::vector<double> InertiaAboutCom(const InertialParams& body) {
  const Matrix3 I = body.rotational_inertia_about_com();
  return {I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(1, 2), I(0, 2)};
}

void LinkText(const LinkInertialCheck& l, std::ostream& out) {
  const std::string where = l.used_by_dynamics ? "" : " (fixed to the base: not used by the dynamics)";
  if (l.kind != LinkInertialKind::kPresent) {
    out << "  " << l.link << ": " << (l.kind == LinkInertialKind::kZero ? "zero <inertial> (massless frame)" : "no <inertial>")
        << where << "\n";
    return;
  }
  const ConsistencyReport& r = l.consistency;
  out << "  " << l.link << ": " << (r.fully_consistent() ? "consistent" : "IMPOSSIBLE") << where << "\n"
      << "    mass " << FormatNumber(r.mass, 4) << " kg; at the COM: min inertia eigenvalue " << FormatNumber(r.min_inertia_eigenvalue_com, 4)
      << " kg m^2, min triangle margin " << FormatNumber(r.min_triangle_margin, 4) << " kg m^2; min pseudo-inertia eigenvalue "
      << FormatNumber(r.min_pseudo_inertia_eigenvalue, 4) << "\n";
  if (!l.impossible()) return;
  out << "    " << r.reason << "\n";
  if (!l.repaired) {
    out << "    cannot be repaired: " << l.unrepairable << "\n";
    return;
  }
  out << "    nearest consistent (same mass and COM): inertia about the COM [Ixx Iyy Izz Ixy Iyz Ixz] = [";
  const std::vector<double> I = InertiaAboutCom(*l.repaired);
  for (std::size_t k = 0; k < I.size(); ++k) out << (k ? " " : "") << FormatNumber(I[k], 4);
  out << "] kg m^2\n";
}

nlohmann::json LinkJson(const LinkInertialCheck& l) {
  nlohmann::json j;
  j["link"] = l.link;
  j["used_by_dynamics"] = l.used_by_dynamics;
  if (l.kind != LinkInertialKind::kPresent) {
    j["inertial"] = l.kind == LinkInertialKind::kZero ? "zero" : "absent";
    j["physically_consistent"] = nullptr;
    return j;
  }
  const ConsistencyReport& r = l.consistency;
  j["inertial"] = "present";
  j["physically_consistent"] = r.fully_consistent();
  j["mass"] = r.mass;
  j["min_inertia_eigenvalue_com"] = r.min_inertia_eigenvalue_com;
  j["min_triangle_margin"] = r.min_triangle_margin;
  j["min_pseudo_inertia_eigenvalue"] = r.min_pseudo_inertia_eigenvalue;
  if (!l.impossible()) return j;
  j["reason"] = r.reason;
  if (l.repaired) {
    j["repaired_inertia_about_com"] = InertiaAboutCom(*l.repaired);
  } else {
    j["repair"] = l.unrepairable;
  }
  return j;
}

}  // namespace

std::string LinkInertialText(const UrdfInertialCheck& check, const UrdfRepair* repair) {
  std::ostringstream out;
  out << check.path << ": robot '" << check.robot << "', " << check.links.size() << " links, " << check.moving_joints
      << " moving joints\n";
  for (const LinkInertialCheck& l : check.links) LinkText(l, out);
  const int impossible = check.impossible();
  out << check.checked() << " inertials checked: "
      << (impossible == 0 ? "all physically consistent" : std::to_string(impossible) + " impossible") << "\n";
  if (repair) {
    out << "wrote " << repair->path << ": " << repair->repaired << " links repaired; "
        << (repair->still_impossible == 0 ? "every inertial in it is physically consistent"
                                          : std::to_string(repair->still_impossible) + " still impossible (mass <= 0)")
        << "\n";
  }
  return out.str();
}

nlohmann::json LinkInertialJson(const UrdfInertialCheck& check, const UrdfRepair* repair) {
  nlohmann::json links = nlohmann::json::array();
  for (const LinkInertialCheck& l : check.links) links.push_back(LinkJson(l));
  nlohmann::json j;
  j["model"] = check.path;
  j["links"] = links;
  j["checked"] = check.checked();
  j["impossible"] = check.impossible();
  j["all_consistent"] = check.impossible() == 0;
  if (repair) j["repaired"] = repair->repaired;
  return j;
}

}  // namespace inertial
