// Prints the number of joints of a URDF as the installed I/O layer loads it.
#include <cstdio>

#include "inertial/formats/urdf_model.hpp"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  std::printf("%d\n", inertial::LoadUrdf(argv[1]).tree.num_dofs());
  return 0;
}
