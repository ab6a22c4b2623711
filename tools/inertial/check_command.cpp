// `inertial check`: physical consistency of every link of a URDF, and repair (link_inertial_check.hpp).
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "option_parsing.hpp"
#include "inertial/formats/link_inertial_check.hpp"
#include "inertial/report/link_inertial_report.hpp"

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

int RunCheckCommand(const CheckCommand& c) {
  if (const int status = RefuseOverwritingInputs({{"--repair", c.repair}}, {{"--model", c.model}}); status != kOk) {
    return status;
  }
  UrdfInertialCheck check;
  std::optional<UrdfRepair> repair;
  try {
    check = CheckUrdfInertials(c.model);
    if (!c.repair.empty()) repair = WriteRepairedUrdf(check, c.repair);
  } catch (const UrdfError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kIoError;
  }
  const UrdfRepair* written = repair ? &*repair : nullptr;
  if (c.json) {
    std::cout << LinkInertialJson(check, written).dump(2) << "\n";
  } else {
    std::cout << LinkInertialText(check, written);
  }
  return check.impossible() == 0 ? kOk : kInconsistentBody;
}

}  // namespace inertial::cli
