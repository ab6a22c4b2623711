#include "inertial/formats/link_inertial_check.hpp"

#include "inertial/formats/urdf_writer.hpp"
#include "inertial/inertia/nearest_consistent.hpp"

namespace inertial {
namespace {

LinkInertialCheck CheckLink(const RobotModel& robot, const UrdfLinkInertial& link) {
  LinkInertialCheck c;
  c.link = link.link;
  c.used_by_dynamics = robot.BodyIndex(link.link) >= 0;
  if (!link.present) return c;
  if ((link.pi.vector().array() == 0.0).all()) {
    c.kind = LinkInertialKind::kZero;
    return c;
  }
  c.kind = LinkInertialKind::kPresent;
  c.consistency = CheckConsistency(link.pi);
  if (c.consistency.fully_consistent()) return c;
  InertialParams repaired;
  if (NearestConsistentBody(link.pi, &repaired, &c.unrepairable)) {
    c.repaired = repaired;
    c.unrepairable.clear();
  }
  return c;
}

}  // namespace

int UrdfInertialCheck::checked() const {
  int n = 0;
  for (const LinkInertialCheck& l : links) n += l.kind == LinkInertialKind::kPresent;
  return n;
}

int UrdfInertialCheck::impossible() const {
  int n = 0;
  for (const LinkInertialCheck& l : links) n += l.impossible();
  return n;
}

std::map<std::string, InertialParams> UrdfInertialCheck::Repairs() const {
  std::map<std::string, InertialParams> repairs;
  for (const LinkInertialCheck& l : links) {
    if (l.repaired) repairs[l.link] = *l.repaired;
  }
  return repairs;
}

UrdfInertialCheck CheckLinkInertials(const std::string& path, const RobotModel& robot) {
  UrdfInertialCheck check;
  check.path = path;
  check.robot = robot.name;
  check.moving_joints = static_cast<int>(robot.dof_names.size());
  for (const UrdfLinkInertial& link : robot.links) check.links.push_back(CheckLink(robot, link));
  return check;
}

UrdfInertialCheck CheckUrdfInertials(const std::string& path) {
  UrdfLoadOptions load;
  load.require_consistent_inertials = false;
  return CheckLinkInertials(path, LoadUrdf(path, load));
}

UrdfRepair WriteRepairedUrdf(const UrdfInertialCheck& check, const std::string& out_path) {
  const std::map<std::string, InertialParams> repairs = check.Repairs();
  WriteUrdfWithInertias(check.path, out_path, repairs, {}, {});
  UrdfRepair repair;
  repair.path = out_path;
  repair.repaired = static_cast<int>(repairs.size());
  repair.still_impossible = CheckUrdfInertials(out_path).impossible();
  return repair;
}

}  // namespace inertial
