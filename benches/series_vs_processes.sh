#!/usr/bin/env bash
# Wall time of a series of N shipped-example records run as one
# `rigfit series` (tests side by side on one device) against the same N
# tests as `rigfit run` processes back to back, on one backend; checks that
# every test's parameters are the same bits both ways, and prints the ratio.
#
#   benches/series_vs_processes.sh [backend cpu|gpu] [tests N] [population P] [generations G] [jobs J]
#
# Uses target/release/rigfit (build it first: cargo build --release).
set -euo pipefail
backend=${1:-cpu}; n=${2:-20}; pop=${3:-256}; gens=${4:-40}; jobs=${5:-2}
repo=$(cd "$(dirname "$0")/.." && pwd)
bin=$repo/target/release/rigfit
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
{
  echo "test,record,repeat"
  for i in $(seq 1 "$n"); do
    echo "r$(printf %02d "$i"),$repo/campaigns/aa2024_t3_v2_synthetic.csv,$i"
  done
} > "$work/tests.csv"
cat > "$work/bench.series.json" <<JSON
{"name": "bench", "campaign": "$repo/campaigns/aa2024_t3_synthetic.json", "tests": "tests.csv",
 "search": {"population": $pop, "generations": $gens, "stall_generations": 100000}}
JSON
# The campaigns alone (prepared, nothing run), for the processes.
"$bin" -q series "$work/bench.series.json" --slurm "$work/plan" > /dev/null
t0=$(date +%s.%N)
"$bin" -q series "$work/bench.series.json" --out "$work/series" --backend "$backend" --jobs "$jobs"
t1=$(date +%s.%N)
for c in "$work"/plan/campaigns/*.json; do
  "$bin" -q run "$c" --backend "$backend" --out "$work/runs/$(basename "$c" .json)"
done
t2=$(date +%s.%N)
python3 - "$work" "$n" "$backend" "$pop" "$gens" "$jobs" "$t0" "$t1" "$t2" <<'PY'
import json, sys, glob, os
work, n, backend, pop, gens, jobs = sys.argv[1:7]
t0, t1, t2 = map(float, sys.argv[7:10])
same = 0
for d in sorted(glob.glob(f"{work}/runs/*")):
    t = os.path.basename(d)
    a = json.load(open(f"{d}/result.json"))
    b = json.load(open(f"{work}/series/tests/{t}/result.json"))
    same += a["params"] == b["params"] and a["fitness"] == b["fitness"]
series, procs = t1 - t0, t2 - t1
print(f"{n} tests, {backend}, population {pop}, {gens} generations, --jobs {jobs}: "
      f"series {series:.1f} s, processes {procs:.1f} s, series/processes {series/procs:.3f}; "
      f"same bits {same}/{n}")
PY
