#!/usr/bin/env bash
# Installs everything inertial needs from Debian's packages. Idempotent: when every package is
# already installed it only checks (well under a second) and touches nothing.
set -euo pipefail

packages=(
  g++ cmake make            # compiler and build system
  libeigen3-dev             # Eigen 3.4: all linear algebra in the core
  googletest libgtest-dev   # GoogleTest: the test suite
  libbenchmark-dev          # Google Benchmark: bench/
  libcli11-dev              # CLI11: argument parsing of the tools
  nlohmann-json3-dev        # nlohmann-json: --json output
  gnuplot-nox               # gnuplot: figures of --report
  chromium                  # headless Chromium: the test that the diagnose report renders
  liburdfdom-dev            # urdfdom: reading URDF robot models
  libtinyxml2-dev           # tinyxml2: writing URDF back with identified inertias
  liborocos-kdl-dev         # Orocos KDL: independent inverse dynamics, tests only
  libkdl-parser-dev         # ROS kdl_parser: another URDF reader loads our model files, tests only
  liblcm-dev liblcm-bin     # LCM: messages, inertiald, log replay; lcm-gen, lcm-logger
  iproute2                  # ip: the multicast end-to-end test sets up its own network namespace
  libyaml-cpp-dev           # yaml-cpp: motors.yaml of the CAN motor drivers
  can-utils                 # log2asc, log2long: cross-checks of the candump parser, tests only
  clang libclang-rt-14-dev  # clang with libFuzzer and the ASan/UBSan runtimes: sanitizer build, fuzzing (checks only)
)

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
