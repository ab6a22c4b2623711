# Cross-compiling for 64-bit Arm (aarch64, Debian's multiarch) on an x86-64 Debian machine:
#   cmake -S . -B build-aarch64 -DCMAKE_TOOLCHAIN_FILE=cmake/aarch64-linux-gnu.cmake -DINERTIAL_CORE_ONLY=ON
# Compiler: g++-aarch64-linux-gnu. Libraries (GoogleTest, Google Benchmark) are the arm64 packages
# installed through multiarch (dpkg --add-architecture arm64), found under /usr/lib/aarch64-linux-gnu;
# Eigen is headers only. Programs and tests run under qemu-aarch64 (CTest prepends the emulator),
# which finds the arm64 C and C++ runtimes of multiarch. scripts/test-aarch64.sh does all of it.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
# Packages and libraries of the target only (never the build machine's x86-64 ones); programs
# (lcm-gen and the like) of the build machine.
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu /usr)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
find_program(INERTIAL_QEMU_AARCH64 qemu-aarch64)
if(INERTIAL_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${INERTIAL_QEMU_AARCH64})
endif()
