#!/usr/bin/env bash
# Two builds of inertiald measured in one run, interleaved (issue 37, part 3; docs/daemon-load.md):
#   scripts/daemon-load.sh OLD_INERTIALD NEW_INERTIALD [OUT_DIR]
# Runs as root in a private network namespace (it re-executes itself under `unshare -n`): lo up,
# 224.0.0.0/4 routed to lo, LCM's UDP multicast with ttl=0, so nothing leaves the machine.
# The leg's 1 kHz log, 60 s (60,001 samples), is made with `inertial simulate --write-log`.
#  a. Latency: bench/daemon_probe plays the first LATENCY_SECONDS (default 20) of the log at 1x
#     and times each sample from its hand-over to LCM to the arrival of the first estimate that
#     used it (estimate_t.utime >= its time); the daemon publishes at 1000 Hz and checkpoints every
#     second on a slow file system: bench/slow_fsync.c, LD_PRELOAD'ed, sleeps SLOW_FSYNC_MS
#     (default 20) in every fsync (a checkpoint syncs twice). p50, p99, p99.9 of the samples after
#     the first second (the online fit holds its first samples until its first solve).
#  b. Load: lcm-logplayer plays the whole log at 10x and 20x into the daemon (checkpoints every
#     second, normal disk, estimates at 10 Hz); published = the log's samples, received / accepted /
#     dropped (queue full) / lost (gaps; the new build's only) from the daemon's exit summary, the
#     namespace's UDP receive-buffer drops (/proc/net/snmp RcvbufErrors), VmRSS after start-up and
#     at the end.
# Each measurement runs ROUNDS times (default 3), old and new alternating which goes first.
# Uses the build in $INERTIAL_BUILD_DIR (default build): inertial, bench/daemon_probe.
set -euo pipefail
if [ $# -lt 2 ]; then
  echo "usage: scripts/daemon-load.sh OLD_INERTIALD NEW_INERTIALD [OUT_DIR]" >&2
  exit 2
fi
root=$(cd "$(dirname "$0")/.." && pwd)
if [ -z "${DAEMON_LOAD_IN_NETNS:-}" ]; then
  exec unshare -n env DAEMON_LOAD_IN_NETNS=1 bash "$0" "$@"
fi
old=$(realpath "$1")
new=$(realpath "$2")
out=${3:-$(mktemp -d /tmp/daemon-load.XXXXXX)}
mkdir -p "$out"
out=$(realpath "$out")
build=$root/${INERTIAL_BUILD_DIR:-build}
probe=$build/bench/daemon_probe
rounds=${ROUNDS:-3}
latency_seconds=${LATENCY_SECONDS:-20}
ip link set lo up
ip route add 224.0.0.0/4 dev lo
URL="udpm://239.255.76.67:7667?ttl=0"
export LCM_DEFAULT_URL=$URL
log=$out/leg-1k.lcm
if [ ! -f "$log" ]; then
  "$build/inertial" simulate --model "$root/examples/leg3.urdf" --write-log "$log" --duration 60 --rate 1000 \
    --perturb 0.2 --noise-tau 0.3 --seed 1 >&2
fi
published=$("$probe" --count "$log")
cc -shared -fPIC -O2 -o "$out/slow_fsync.so" "$root/bench/slow_fsync.c" -ldl

DAEMON=""
# start NAME BINARY PRELOAD PUBLISH_RATE: the daemon in the background, ready once it listens.
start() {
  local name=$1 binary=$2 preload=$3 rate=$4
  rm -f "$out/$name.state.json" "$out/$name.err"
  local args=(--model "$root/examples/leg3.urdf" --checkpoint "$out/$name.state.json" --checkpoint-interval 1
              --publish-rate "$rate" --noise-tau 0.3 --lcm-url "$URL")
  if [ "$preload" = 1 ]; then
    LD_PRELOAD=$out/slow_fsync.so "$binary" "${args[@]}" 2> "$out/$name.err" &
  else
    "$binary" "${args[@]}" 2> "$out/$name.err" &
  fi
  DAEMON=$!
  for _ in $(seq 600); do grep -q 'listening on' "$out/$name.err" && break; sleep 0.05; done
  sleep 0.5
}
stop() {
  kill -INT "$DAEMON"
  wait "$DAEMON" || true
}
rss() { awk '/VmRSS/ {print $2}' "/proc/$DAEMON/status"; }
rcvbuf_errors() { awk '/^Udp:/ {n++; if (n == 2) print $6}' /proc/net/snmp; }
# From an exit summary: received, accepted, dropped (queue full), lost ("-" where not reported).
summary() {
  local line
  line=$(grep 'received [0-9]*, accepted' "$1" | tail -1)
  local received accepted dropped lost
  received=$(sed -E 's/.*received ([0-9]+),.*/\1/' <<< "$line")
  accepted=$(sed -E 's/.*accepted ([0-9]+),.*/\1/' <<< "$line")
  dropped=$(sed -E 's/.*dropped ([0-9]+).*/\1/' <<< "$line")
  lost=$(grep -q ' lost [0-9]* before' <<< "$line" && sed -E 's/.* lost ([0-9]+) before.*/\1/' <<< "$line" || echo "-")
  echo "$received $accepted $dropped $lost"
}
order() { if [ $(($1 % 2)) = 1 ]; then echo "old new"; else echo "new old"; fi; }
binary() { if [ "$1" = old ]; then echo "$old"; else echo "$new"; fi; }

latency=$out/latency.tsv
load=$out/load.tsv
echo -e "round\tbuild\tpublished\testimates\tsamples_with_estimate\tp50_ms\tp99_ms\tp999_ms\tmax_ms" > "$latency"
echo -e "round\tspeed\tbuild\tpublished\treceived\taccepted\tdropped\tlost\tudp_rcvbuf_errors\trss_start_kb\trss_end_kb" > "$load"
for round in $(seq "$rounds"); do
  for which in $(order "$round"); do
    start "latency-$which-$round" "$(binary "$which")" 1 1000
    json=$("$probe" --log "$log" --url "$URL" --speed 1 --seconds "$latency_seconds")
    stop
    echo "$json" > "$out/latency-$which-$round.json"
    python3 - "$round" "$which" "$json" >> "$latency" <<'PY'
import json, sys
j = json.loads(sys.argv[3])
print("\t".join([sys.argv[1], sys.argv[2]] + [str(j[k]) for k in
      ("published", "estimates", "samples_with_estimate", "p50_ms", "p99_ms", "p999_ms", "max_ms")]))
PY
    echo "latency round $round $which: $json" >&2
  done
  for speed in 10 20; do
    for which in $(order "$((round + speed / 10))"); do
      name=load-$which-$speed-$round
      start "$name" "$(binary "$which")" 0 10
      rss_start=$(rss)
      drops_before=$(rcvbuf_errors)
      lcm-logplayer -s "$speed" -l "$URL" "$log" > /dev/null
      sleep 2
      rss_end=$(rss)
      drops=$(($(rcvbuf_errors) - drops_before))
      stop
      read -r received accepted dropped lost <<< "$(summary "$out/$name.err")"
      echo -e "$round\t$speed\t$which\t$published\t$received\t$accepted\t$dropped\t$lost\t$drops\t$rss_start\t$rss_end" >> "$load"
      echo "load round $round ${speed}x $which: received $received accepted $accepted dropped $dropped lost $lost udp-drops $drops rss $rss_start -> $rss_end kB" >&2
    done
  done
done
echo "== latency (ms), slow fsync ${SLOW_FSYNC_MS:-20} ms, checkpoints every 1 s, estimates at 1000 Hz"
column -t "$latency"
echo "== load (lcm-logplayer, leg 1 kHz x 60 s)"
column -t "$load"
echo "results in $out"
