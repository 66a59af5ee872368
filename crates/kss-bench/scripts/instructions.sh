#!/usr/bin/env bash
# The instruction counts of `kss run -q` on the six reference scenes of the
# cost per event (results/cost-per-event.md), under callgrind: counts that do
# not vary from run to run, unlike wall time.
#
#   crates/kss-bench/scripts/instructions.sh [OUT_DIR]
#
# Builds the release `kss` binary and the `workload` example, writes the six
# scenes (the workloads of `kss-bench --workload perf`) into OUT_DIR (default
# target/instructions), runs each under `valgrind --tool=callgrind` and prints
# one Markdown row per scene: instructions, events and instructions per event.
# The flypast's events alone are counted again with
# `--toggle-collect=kss::runner::drive`. Needs valgrind; takes about ten
# minutes on two cores (the 256-gon swarm alone about six).
set -euo pipefail

root="$(cd "$(dirname "$0")/../../.." && pwd)"
out="${1:-$root/target/instructions}"
mkdir -p "$out"
command -v valgrind >/dev/null || { echo "instructions.sh: valgrind is not installed" >&2; exit 2; }

cd "$root"
cargo build --release -q -p kss-cli
cargo build --release -q -p kss-bench --example workload
target="${CARGO_TARGET_DIR:-$root/target}"
kss="$target/release/kss"
workload="$target/release/examples/workload"

# name, workload, extra arguments of `kss run`
scenes=(
  "sw16|walls-k1000-n16-bounce|--until 0.6"
  "sw256|walls-k300-n256-bounce|"
  "sw64r|walls-k2000-n64-remove|"
  "gasmix|gasmix-k1000-n3to16|"
  "gas10k|gas-k10000-n8-c1000|--until 0.4348"
  "fp|flypast-n65536-r1e3|"
)

count() { # LOG: the instructions callgrind collected
  grep -o 'Collected : [0-9]*' "$1" | grep -o '[0-9]*$'
}

echo "| scene | workload | kss run arguments | instructions | events | per event |"
echo "| --- | --- | --- | ---: | ---: | ---: |"
for entry in "${scenes[@]}"; do
  IFS='|' read -r name wl extra <<<"$entry"
  scene="$out/$name.json"
  [ -s "$scene" ] || "$workload" "$wl" >"$scene"
  # shellcheck disable=SC2086
  "$kss" run -q "$scene" $extra --stats "$out/$name.stats.json" >/dev/null
  events=$(grep -o '"events_processed": *[0-9]*' "$out/$name.stats.json" | grep -o '[0-9]*$')
  # shellcheck disable=SC2086
  valgrind --tool=callgrind --callgrind-out-file="$out/$name.callgrind" \
    "$kss" run -q "$scene" $extra >/dev/null 2>"$out/$name.log"
  n=$(count "$out/$name.log")
  echo "| $name | $wl | ${extra:-} | $n | $events | $((n / events)) |"
done
valgrind --tool=callgrind --toggle-collect='kss::runner::drive' \
  --callgrind-out-file="$out/fp-events.callgrind" \
  "$kss" run -q "$out/fp.json" >/dev/null 2>"$out/fp-events.log"
n=$(count "$out/fp-events.log")
events=$(grep -o '"events_processed": *[0-9]*' "$out/fp.stats.json" | grep -o '[0-9]*$')
echo "| fp, the events alone | flypast-n65536-r1e3 | --toggle-collect=kss::runner::drive | $n | $events | $((n / events)) |"
