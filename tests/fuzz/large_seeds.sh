#!/usr/bin/env bash
# Writes the large seeds of the fuzz harnesses into OUT/<harness>/ (scripts/fuzz.sh calls it; they
# are generated, not kept in the repository). libFuzzer grows inputs slowly from the small corpus
# seeds and by default never past 4096 bytes, so what only a large input reaches (100,000 levels of
# nesting, a million separators, a log of thousands of rows: issue 35) is given to it as seeds, next
# to the larger -max_len of fuzz.sh. Plain bash, printf and awk: no other tool.
#   tests/fuzz/large_seeds.sh OUT
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=${1:?usage: large_seeds.sh OUT}
repeat() { local text=$1 n=$2; local s; s=$(printf '%*s' "$n" ''); printf '%s' "${s// /$text}"; }
mkdir -p "$out"/{urdf,motors_yaml,daemon_config,checkpoint,joint_csv,body_csv,candump}

# URDF: the leg after a broken declaration swallowing 100,000 elements (the crash of issue 35), the
# same nesting inside <robot> and inside an extension element, and 99 levels (just within tinyxml2's
# depth limit) in a model file's extension.
leg=$(sed '1{/^<?xml/d}' "$here/../../examples/leg3.urdf")
{ printf '<?xml '; repeat '<a>' 100000; printf '?>'; printf '%s\n' "$leg"; } >"$out/urdf/broken_declaration_deep"
{ printf '%s\n' "${leg%</robot>*}"; repeat '<a>' 100000; printf '</robot>\n'; } >"$out/urdf/deep_in_robot"
{ printf '%s\n' "${leg%</robot>*}"; printf '<inertial_effects version="1">'; repeat '<a>' 97; repeat '</a>' 97;
  printf '</inertial_effects>\n'; repeat '<!-- padding -->' 20000; printf '</robot>\n'; } >"$out/urdf/nesting_97_and_comments"

# motors.yaml: one flow value of 2,000 commas (yaml-cpp spends about 4 us and 1 KB a comma, 10 times
# that under the sanitizers: a corpus grown from 8,000 ran 20 inputs a second), one over the limit
# (cut to fuzz.sh's 8 KiB: the limit itself is tested in tests/config/motors_yaml_test.cpp), and
# nested flow sequences.
{ printf 'motors:\n  - id: 0x141\n    joint: knee\n    protocol: linear\n    position: {byte: 0, width: 2, scale: ';
  repeat ',' 2000; printf '0.001}\n'; } >"$out/motors_yaml/commas_2000"
{ printf 'motors:\n  - {id: 1, joint: abad, position: '; repeat ',' 70000; printf '[-12.5, 12.5]}\n'; } >"$out/motors_yaml/commas_over_limit"
{ printf 'motors:\n  - {id: 1, joint: abad, position: '; repeat '[' 2000; repeat ']' 2000; printf '}\n'; } >"$out/motors_yaml/nested_flow_2000"

# inertiald --config: nesting and a long array inside a valid configuration.
{ printf '{"channel": "C", "format": '; repeat '[' 30000; repeat ']' 30000; printf '}\n'; } >"$out/daemon_config/nested"
{ printf '{"queue_capacity": 1e308, "tuning": {"max_consecutive_outliers": 1.9}, "channel": "'; repeat 'x' 60000; printf '"}\n'; } >"$out/daemon_config/long_string"

# Checkpoints: the issue's non-integer versions, deep nesting, and a covariance of 100 x 100.
printf '{"format": "inertial-estimator-state", "version": 1e308}\n' >"$out/checkpoint/version_1e308"
{ printf '{"format": "inertial-estimator-state", "version": 1, "kind": "gauss_newton", "x": '; repeat '[' 100000;
  repeat ']' 100000; printf '}\n'; } >"$out/checkpoint/nested"
awk 'BEGIN { n = 100; printf "{\"format\": \"inertial-estimator-state\", \"version\": 1, \"kind\": \"gauss_newton\", \"model\": \"m\", \"x\": [";
  for (i = 0; i < n; i++) printf "%s%.17g", (i ? "," : ""), 0.001 * i; printf "], \"P\": [";
  for (i = 0; i < n; i++) { printf "%s[", (i ? "," : ""); for (j = 0; j < n; j++) printf "%s%.17g", (j ? "," : ""), (i == j ? 1 : 1e-3 / (1 + i + j)); printf "]" }
  printf "], \"has_time\": true, \"last_time\": 1.5, \"counters\": {\"accepted\": 18446744073709551615}}\n" }' >"$out/checkpoint/covariance_100"

# Joint and body CSV logs of 1,000 rows (about 260 KB) (smooth signals, 1 kHz), from the corpus' headers.
awk -v rows=1000 'BEGIN { print "t,q_abad,q_hip,q_knee,qd_abad,qd_hip,qd_knee,qdd_abad,qdd_hip,qdd_knee,tau_abad,tau_hip,tau_knee";
  for (i = 0; i < rows; i++) { t = i * 0.001; printf "%.17g", t;
    for (k = 0; k < 12; k++) printf ",%.17g", sin(t * (k + 1) + k); printf "\n" } }' >"$out/joint_csv/rows_1000"
awk -v rows=1000 'BEGIN { print "t,wx,wy,wz,vx,vy,vz,mx,my,mz,fx,fy,fz";
  for (i = 0; i < rows; i++) { t = i * 0.001; printf "%.17g", t;
    for (k = 0; k < 12; k++) printf ",%.17g", cos(t * (k + 2) + k); printf "\n" } }' >"$out/body_csv/rows_1000"
# A candump log of 2,000 frames: the corpus' frames again and again, time increasing.
awk '{ lines[n++] = $0 } END { for (i = 0; i < 2000; i++) { l = lines[i % n]; sub(/^\([0-9.]*\)/, "", l);
  printf "(%.6f)%s\n", i * 0.0001, l } }' "$here/corpus/candump/leg_mini_cheetah" >"$out/candump/frames_2000"
