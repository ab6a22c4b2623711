#!/usr/bin/env bash
# The layering holds in the code: every #include of a library header (include/inertial/<layer>/ and
# src/<layer>/) names only its own layer, the layers below it, and the outside libraries that layer
# is given in CMakeLists.txt. Prints each offending include (file:line) and fails if there is one.
# Usage: check_layers.sh SOURCE_DIR
set -euo pipefail
cd "${1:?usage: check_layers.sh SOURCE_DIR}"

core="inertia model signal estimation diagnosis study"
declare -A allowed=(
  [inertia]="inertia" [model]="inertia model" [signal]="inertia model signal"
  [estimation]="inertia model signal estimation" [diagnosis]="inertia model signal estimation diagnosis"
  [study]="inertia model signal estimation study"
  [formats]="$core formats" [transport]="$core formats transport" [config]="$core formats transport config"
  [report]="$core formats report" [runtime]="$core formats transport config report runtime")
# Outside libraries (an include's leading path) and the layers that may use them.
declare -A library=(
  ["urdf_model/|urdf_parser/|tinyxml2.h|console_bridge"]="formats"
  ["nlohmann/"]="formats config report"
  ["yaml-cpp/"]="config"
  ["lcm/"]="transport runtime"
  ["linux/can|sys/socket.h|net/if.h|sys/ioctl.h"]="transport")

bad=0
for layer in "${!allowed[@]}"; do
  for f in $(find "include/inertial/$layer" "src/$layer" -name '*.[ch]pp' 2>/dev/null | sort); do
    while IFS=: read -r line text; do
      if [[ $text =~ \"inertial/([a-z_]+)/ ]]; then
        used=${BASH_REMATCH[1]}
        if [[ " ${allowed[$layer]} " != *" $used "* ]]; then
          echo "$f:$line: layer $layer includes layer $used ($text)"; bad=1
        fi
      elif [[ $text =~ \"inertial/[a-z_]+_t\.hpp\" ]]; then  # lcm-gen's message types
        if [[ " transport runtime " != *" $layer "* || $f == include/* ]]; then
          echo "$f:$line: only transport and runtime sources use the generated LCM types ($text)"; bad=1
        fi
      elif [[ $text =~ \<([^\>]+)\> ]]; then
        header=${BASH_REMATCH[1]}
        for pattern in "${!library[@]}"; do
          if [[ $header =~ ^($pattern) && " ${library[$pattern]} " != *" $layer "* ]]; then
            echo "$f:$line: layer $layer uses <$header>, an outside library given only to: ${library[$pattern]}"; bad=1
          fi
        done
      fi
    done < <(grep -n '^[[:space:]]*#[[:space:]]*include' "$f" || true)
  done
done
if [ -d include/inertial/io ] || [ -d src/io ]; then echo "include/inertial/io or src/io exists: it was split into layers"; bad=1; fi
[ $bad = 0 ] && echo "every include of the ${#allowed[@]} layers follows the layering"
exit $bad
