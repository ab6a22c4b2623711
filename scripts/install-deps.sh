#!/usr/bin/env bash
# Installs what inertial needs from Debian's packages, in groups, so that each command installs only
# what it uses:
#   scripts/install-deps.sh               build the programs and configure the whole tree (README command 1)
#   scripts/install-deps.sh --tests       and what the test suite runs besides (README command 2)
#   scripts/install-deps.sh --sanitizers  and clang with libFuzzer and the sanitizer runtimes
# (scripts/test-aarch64.sh installs the cross compiler and qemu itself.) Idempotent: when every
# package is already installed it only checks (well under a second) and touches nothing.
set -euo pipefail

packages=(
  g++ cmake                 # compiler and build system
  ninja-build               # Ninja: the build tool CMake drives (schedules 2 cores better than make)
  ccache                    # ccache: every build reuses the objects of earlier builds, in any clone
  libeigen3-dev             # Eigen 3.4: all linear algebra in the core
  libcli11-dev              # CLI11: argument parsing of the tools
  nlohmann-json3-dev        # nlohmann-json: --json output
  gnuplot-nox               # gnuplot: figures of --report
  liburdfdom-dev            # urdfdom: reading URDF robot models
  libtinyxml2-dev           # tinyxml2: writing URDF back with identified inertias
  liblcm-dev liblcm-bin     # LCM: messages, inertiald, log replay; lcm-gen, lcm-logger
  libyaml-cpp-dev           # yaml-cpp: motors.yaml of the CAN motor drivers
  pybind11-dev python3-dev  # pybind11: the Python module `inertial` (python/), NumPy arrays in and out
  python3-numpy             # NumPy: the arrays the Python module takes and returns
  # Found when the tree is configured (the tests and benchmarks are part of it), small:
  googletest libgtest-dev   # GoogleTest: the test suite
  libbenchmark-dev          # Google Benchmark: bench/
  liborocos-kdl-dev         # Orocos KDL: independent inverse dynamics, tests only
  libkdl-parser-dev         # ROS kdl_parser: another URDF reader loads our model files, tests only
)
for group in "$@"; do
  case "$group" in
    --tests|--sanitizers)
      packages+=(
        chromium            # headless Chromium: the test that the diagnose report renders
        iproute2            # ip: the multicast end-to-end test sets up its own network namespace
        can-utils           # log2asc, log2long: cross-checks of the candump parser, tests only
        python3-pytest      # pytest: the Python module's tests
        python3-matplotlib  # matplotlib: the Python example's figures (examples/python/)
      ) ;;&
    --sanitizers)
      packages+=(clang libclang-rt-14-dev)  # libFuzzer and the ASan/UBSan runtimes (checks only)
      ;;
    --tests) ;;
    *) echo "install-deps: unknown group $group (--tests, --sanitizers)" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
