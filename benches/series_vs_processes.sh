#!/usr/bin/env bash
# Wall time of a series run as one `rigfit series` (its tests side by side
# on one device) against the same tests as `rigfit run` processes back to
# back, on one backend; checks that every test's result is the same bits
# both ways, and prints the ratio.
#
#   benches/series_vs_processes.sh [backend cpu|gpu] [series file] [jobs]
#
# Default series: the shipped one, campaigns/series/rates.series.json (20
# records of the shipped tensile example). Uses target/release/rigfit (build
# it first: cargo build --release).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
backend=${1:-cpu}
series=${2:-$repo/campaigns/series/rates.series.json}
jobs=${3:-2}
bin=$repo/target/release/rigfit
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The tests' campaigns, prepared without running them (a plan, never submitted).
"$bin" -q series "$series" --slurm "$work/plan" > /dev/null
# Warm-up, untimed: the first test once, so that neither side pays alone for
# what is kept between runs (the lanes' native build, the driver's shader cache).
first=$(ls "$work"/plan/campaigns/*.json | head -1)
"$bin" -q run "$first" --backend "$backend" --out "$work/warm-up" || true
t0=$(date +%s.%N)
"$bin" -q series "$series" --out "$work/series" --backend "$backend" --jobs "$jobs" || true
t1=$(date +%s.%N)
for c in "$work"/plan/campaigns/*.json; do
  "$bin" -q run "$c" --backend "$backend" --out "$work/runs/$(basename "$c" .json)" || true
done
t2=$(date +%s.%N)
python3 - "$work" "$backend" "$jobs" "$t0" "$t1" "$t2" <<'PY'
import json, sys, glob, os
work, backend, jobs = sys.argv[1:4]
t0, t1, t2 = map(float, sys.argv[4:7])
same = n = 0
for d in sorted(glob.glob(f"{work}/runs/*")):
    t = os.path.basename(d)
    n += 1
    try:
        a = json.load(open(f"{d}/result.json"))
        b = json.load(open(f"{work}/series/tests/{t}/result.json"))
    except OSError:
        continue
    same += a["params"] == b["params"] and a["fitness"] == b["fitness"]
series, procs = t1 - t0, t2 - t1
print(f"{n} tests on {backend}, --jobs {jobs}: series {series:.1f} s, processes back to back "
      f"{procs:.1f} s, series/processes {series / procs:.3f}; same bits {same}/{n}")
PY
