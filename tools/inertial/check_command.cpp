// `inertial check`: physical consistency of every link of a URDF, and repair.
#include <cstdio>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inertial/inertia/nearest_consistent.hpp"
#include "inertial/formats/urdf_model.hpp"
#include "inertial/formats/urdf_writer.hpp"

namespace inertial::cli {

CLI::App* AddCheckCommand(CLI::App& app, CheckCommand* c) {
  CLI::App* sub = app.add_subcommand(
      "check",
      "Check every link's <inertial> of a URDF for full physical consistency (mass > 0, inertia at the COM "
      "positive definite, triangle inequalities of the principal moments, pseudo-inertia positive definite), "
      "with margins. Exit 0 if every link is consistent, 4 if any is not (also with --repair, which fixes the "
      "written copy, not the file checked).");
  sub->add_option("--model", c->model, "URDF robot description")->required();
  sub->add_option("--repair", c->repair,
                  "write a copy whose impossible links get the nearest consistent inertia: same mass and COM, "
                  "the second moments about the COM clipped from below (the Frobenius-nearest pseudo-inertia at "
                  "the COM), never thinner than 1 mm of spread or 1e-3 of the largest second moment");
  sub->add_flag("--json", c->json, "print the report as JSON on stdout");
  return sub;
}

namespace {

std::string Number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", x);
  return buf;
}

bool IsZero(const InertialParams& pi) { return (pi.vector().array() == 0.0).all(); }

}  // namespace

int RunCheckCommand(const CheckCommand& c) {
  RobotModel robot;
  UrdfLoadOptions load;
  load.require_consistent_inertials = false;
  try {
    robot = LoadUrdf(c.model, load);
  } catch (const UrdfError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kIoError;
  }
  int impossible = 0, checked = 0;
  std::map<std::string, InertialParams> repairs;
  std::vector<std::string> unrepairable;
  nlohmann::json links = nlohmann::json::array();
  std::ostringstream text;
  text << c.model << ": robot '" << robot.name << "', " << robot.links.size() << " links, " << robot.dof_names.size()
       << " moving joints\n";
  for (const UrdfLinkInertial& link : robot.links) {
    nlohmann::json j;
    j["link"] = link.link;
    const bool used = robot.BodyIndex(link.link) >= 0;
    j["used_by_dynamics"] = used;
    const std::string where = used ? "" : " (fixed to the base: not used by the dynamics)";
    if (!link.present || IsZero(link.pi)) {
      j["inertial"] = link.present ? "zero" : "absent";
      j["physically_consistent"] = nullptr;
      text << "  " << link.link << ": " << (link.present ? "zero <inertial> (massless frame)" : "no <inertial>") << where
           << "\n";
      links.push_back(j);
      continue;
    }
    ++checked;
    const ConsistencyReport r = CheckConsistency(link.pi);
    j["inertial"] = "present";
    j["physically_consistent"] = r.fully_consistent();
    j["mass"] = r.mass;
    j["min_inertia_eigenvalue_com"] = r.min_inertia_eigenvalue_com;
    j["min_triangle_margin"] = r.min_triangle_margin;
    j["min_pseudo_inertia_eigenvalue"] = r.min_pseudo_inertia_eigenvalue;
    if (!r.fully_consistent()) j["reason"] = r.reason;
    text << "  " << link.link << ": " << (r.fully_consistent() ? "consistent" : "IMPOSSIBLE") << where << "\n"
         << "    mass " << Number(r.mass) << " kg; at the COM: min inertia eigenvalue "
         << Number(r.min_inertia_eigenvalue_com) << " kg m^2, min triangle margin " << Number(r.min_triangle_margin)
         << " kg m^2; min pseudo-inertia eigenvalue " << Number(r.min_pseudo_inertia_eigenvalue) << "\n";
    if (!r.fully_consistent()) {
      ++impossible;
      text << "    " << r.reason << "\n";
      InertialParams repaired;
      std::string why;
      if (NearestConsistentBody(link.pi, &repaired, &why)) {
        repairs[link.link] = repaired;
        const Matrix3 I = repaired.rotational_inertia_about_com();
        j["repaired_inertia_about_com"] = {I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(1, 2), I(0, 2)};
        text << "    nearest consistent (same mass and COM): inertia about the COM [Ixx Iyy Izz Ixy Iyz Ixz] = ["
             << Number(I(0, 0)) << " " << Number(I(1, 1)) << " " << Number(I(2, 2)) << " " << Number(I(0, 1)) << " "
             << Number(I(1, 2)) << " " << Number(I(0, 2)) << "] kg m^2\n";
      } else {
        unrepairable.push_back(link.link);
        j["repair"] = why;
        text << "    cannot be repaired: " << why << "\n";
      }
    }
    links.push_back(j);
  }
  text << checked << " inertials checked: " << (impossible == 0 ? "all physically consistent" : std::to_string(impossible) + " impossible") << "\n";

  if (!c.repair.empty()) {
    try {
      WriteUrdfWithInertias(c.model, c.repair, repairs, {}, {});
      // Verify the written file independently: every inertial must now pass.
      const RobotModel fixed = LoadUrdf(c.repair, load);
      int still = 0;
      for (const UrdfLinkInertial& link : fixed.links) {
        if (link.present && !IsZero(link.pi) && !CheckConsistency(link.pi).fully_consistent()) ++still;
      }
      text << "wrote " << c.repair << ": " << repairs.size() << " links repaired; "
           << (still == 0 ? "every inertial in it is physically consistent" : std::to_string(still) + " still impossible (mass <= 0)")
           << "\n";
    } catch (const UrdfError& e) {
      std::cerr << "Error: " << e.what() << "\n";
      return kIoError;
    }
  }
  if (c.json) {
    nlohmann::json j;
    j["model"] = c.model;
    j["links"] = links;
    j["checked"] = checked;
    j["impossible"] = impossible;
    j["all_consistent"] = impossible == 0;
    if (!c.repair.empty()) j["repaired"] = repairs.size();
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << text.str();
  }
  return impossible == 0 ? kOk : kInconsistentBody;
}

}  // namespace inertial::cli
