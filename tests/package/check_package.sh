#!/usr/bin/env bash
# The core as a package, checked as a controller's developer would use it (CTest's
# package.CoreInstallsAndBuildsTheExampleOutOfTree):
# 1. `cmake -DINERTIAL_CORE_ONLY=ON` configures with Eigen and threads alone (no other package is
#    looked up);
# 2. the core component of this build installs by itself (headers, libraries, inertialConfig.cmake
#    and its version file, nothing of the I/O layer);
# 3. every installed header compiles against the prefix and Eigen only (so none includes a header
#    that is not installed);
# 4. examples/adaptive_control.cpp builds out of tree with find_package(inertial 0.1) and
#    inertial::estimation, and runs: the tracking error falls as the payload is learned;
# 5. the full install adds the I/O layer (inertial::io, with its dependencies found again) and the
#    programs: a small tool links inertial::io and loads a URDF.
# usage: check_package.sh SOURCE_DIR BUILD_DIR WORK_DIR CXX "CXX_FLAGS" EIGEN_INCLUDE_DIRS [GENERATOR]
# GENERATOR: CMake's generator for the configures here, the build's own (Ninja needs no make).
set -euo pipefail
src=$1 build=$2 work=$3 cxx=$4 flags=$5 eigen=$6
if [ -n "${7:-}" ]; then export CMAKE_GENERATOR=$7; fi
rm -rf "$work"
mkdir -p "$work"

echo "== 1. core-only configure"
cmake -S "$src" -B "$work/core-only" -DINERTIAL_CORE_ONLY=ON -DINERTIAL_BUILD_TESTS=OFF \
  -DINERTIAL_BUILD_BENCHMARKS=OFF >"$work/core-only.log"
for found in nlohmann_json_DIR CLI11_DIR urdfdom_DIR tinyxml2_DIR yaml-cpp_DIR GTest_DIR benchmark_DIR \
             LCM_LIBRARY LCM_GEN KDL_LIBRARY; do
  if grep -q "^$found:" "$work/core-only/CMakeCache.txt"; then
    echo "FAIL: the core-only configure looked up $found"
    exit 1
  fi
done
echo "looked up: $(grep -o '^[A-Za-z0-9_]*_DIR:PATH=[^ ]*' "$work/core-only/CMakeCache.txt" | tr '\n' ' ')"

echo "== 2. install the core component alone"
cmake --install "$build" --prefix "$work/prefix" --component core >"$work/install.log"
for f in lib/libinertial_inertia.a lib/libinertial_model.a lib/libinertial_signal.a lib/libinertial_estimation.a \
         lib/libinertial_diagnosis.a lib/libinertial_study.a \
         lib/cmake/inertial/inertialConfig.cmake lib/cmake/inertial/inertialConfigVersion.cmake \
         lib/cmake/inertial/inertialCoreTargets.cmake include/inertial/estimation/online/online_joint_estimator.hpp; do
  [ -e "$work/prefix/$f" ] || { echo "FAIL: $f was not installed"; exit 1; }
done
if ls -d "$work"/prefix/include/inertial/{formats,transport,config,report,runtime} "$work"/prefix/lib/libinertial_{formats,transport,config,report,runtime}.a 2>/dev/null | grep -q .; then
  echo "FAIL: the core component installed the I/O layer"
  exit 1
fi
echo "installed $(find "$work/prefix" -type f | wc -l) files"

echo "== 3. every installed header against the prefix and Eigen only"
# The compiler still searches /usr/include (where this machine has JSON, YAML and LCM headers), so
# first every include of the installed headers by name: the standard library (no slash), Eigen, or
# a header of the installed layers.
bad=$(cd "$work/prefix/include" && grep -rhoE '^[[:space:]]*#[[:space:]]*include[[:space:]]*[<"][^>"]+[>"]' inertial |
  sed -E 's/.*include[[:space:]]*//' |
  grep -vE '^<[A-Za-z0-9_]+>$|^<Eigen/[A-Za-z]+>$|^"inertial/(inertia|model|signal|estimation|diagnosis|study)/([a-z]+/)?[a-z0-9_]+\.hpp"$' | sort -u || true)
if [ -n "$bad" ]; then
  echo "FAIL: installed headers include what is not the standard library, Eigen or the core: $bad"
  exit 1
fi
(cd "$work/prefix/include" && find inertial -name '*.hpp' | sort | sed 's/.*/#include "&"/') >"$work/all_headers.cpp"
includes=(-I"$work/prefix/include")
IFS=';' read -r -a eigen_dirs <<<"$eigen"
for d in "${eigen_dirs[@]}"; do includes+=(-isystem "$d"); done
"$cxx" -std=c++17 -fsyntax-only "${includes[@]}" "$work/all_headers.cpp"
echo "$(wc -l <"$work/all_headers.cpp") headers compile"

echo "== 4. the example out of tree, against the installed package"
cmake -S "$src/tests/package/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_BUILD_TYPE=Release \
  -DINERTIAL_EXAMPLE="$src/examples/adaptive_control.cpp" >"$work/consumer-configure.log"
cmake --build "$work/consumer" >"$work/consumer-build.log"
"$work/consumer/adaptive_control" 2 >"$work/adaptive.txt"
head -1 "$work/adaptive.txt"
# Columns: time, fixed-prior RMS, adaptive RMS, estimated mass. The last window: the adaptive error
# far below the fixed prior's and the mass within 1 % of the truth (as tools' AdaptiveControlExample).
awk 'NR == 1 { truth = $3 } NR > 2 { t = $1; fixed = $2; adaptive = $3; mass = $4 }
     END { ok = adaptive < 0.01 * fixed && (mass - truth) ^ 2 < (0.01 * truth) ^ 2;
           printf "at %.2f s: tracking RMS fixed %.6f, adaptive %.6f; mass %.4f of %.4f kg: %s\n",
                  t, fixed, adaptive, mass, truth, ok ? "ok" : "FAIL"; exit !ok }' "$work/adaptive.txt"
echo "== 5. the full install: the I/O layer and the programs"
cmake --install "$build" --prefix "$work/full" >"$work/install-full.log"
for f in bin/inertial bin/inertiald lib/libinertial_formats.a lib/libinertial_runtime.a lib/cmake/inertial/inertialIoTargets.cmake \
         include/inertial/formats/urdf_model.hpp; do
  [ -e "$work/full/$f" ] || { echo "FAIL: the full install has no $f"; exit 1; }
done
cmake -S "$src/tests/package/consumer_io" -B "$work/consumer_io" -DCMAKE_PREFIX_PATH="$work/full" \
  -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_BUILD_TYPE=Release >"$work/consumer_io-configure.log"
cmake --build "$work/consumer_io" >"$work/consumer_io-build.log"
joints=$("$work/consumer_io/count_joints" "$src/examples/arm7.urdf")
[ "$joints" = 7 ] || { echo "FAIL: inertial::io loaded $joints joints of arm7.urdf, not 7"; exit 1; }
echo "inertial::io from the full install: arm7.urdf has $joints joints"
echo "PASS"
