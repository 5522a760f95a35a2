#!/usr/bin/env bash
# Throughput of `rigfit sweep` on the shipped tensile example: a 64 × 64
# design grid (slack-adapter damping c4, log 2e3–1.6e5 N·s/m × load-cell mass
# m1, 4–8 kg) × 32 runs per point (the point and 31 draws of the calibration's
# uncertainty): 131 072 runs of the record's 2 501 samples, on the CPU lanes
# and on the GPU (lavapipe here), and the same runs as a loop of `rigfit
# simulate` processes, timed over the first LOOP points (each with its 31
# draws as parameter files) and scaled to the whole sweep for the ratio.
#
#   benches/sweep_throughput.sh [grid side, default 64] [draws, default 31] [loop points, default 4]
#
# Uses target/release/rigfit (build it first: cargo build --release). The
# calibration it sweeps is made first (`rigfit run` of the shipped campaign).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
side=${1:-64}
draws=${2:-31}
loop=${3:-4}
bin=$repo/target/release/rigfit
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
campaign=$repo/campaigns/aa2024_t3_synthetic.json
"$bin" -q run "$campaign" --backend cpu --out "$work/fit"
cat > "$work/bench.sweep.json" <<JSON
{"campaign": "$campaign", "params": "$work/fit/result.json",
 "variables": {"c4": {"log": [2e3, 1.6e5, $side]}, "m1": {"linear": [4, 8, $side]}},
 "metrics": [
   {"name": "ringing", "metric": "ringing", "output": "load_cell_force", "against": "specimen_force",
    "gate": {"output": "specimen_force", "above": 0.5}},
   {"name": "ringing_hz", "metric": "ringing_hz", "output": "load_cell_force", "against": "specimen_force"},
   {"name": "peak", "metric": "peak", "output": "load_cell_force"}],
 "uncertainty": {"samples": $draws, "seed": 1}}
JSON
cpu=$("$bin" -q --json sweep "$work/bench.sweep.json" --out "$work/cpu.csv" --backend cpu)
gpu=$("$bin" -q --json sweep "$work/bench.sweep.json" --out "$work/gpu.csv" --backend gpu 2> "$work/gpu.err" || cat "$work/gpu.err")
# The loop: as many `rigfit simulate` processes as the first $loop points
# have runs (1 + draws each), at the sweep's step, each point's values
# written out as a parameter file (a draw's run costs what the point's does).
substeps=$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["substeps"][0])' "$cpu")
python3 - "$work" "$loop" "$draws" "$side" <<'PY'
import json, math, sys, random
work, loop, draws, side = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
fit = json.load(open(f"{work}/fit/result.json"))
values = dict(fit["params"])
c4 = [math.exp(math.log(2e3) + i * (math.log(1.6e5) - math.log(2e3)) / (side - 1)) for i in range(side)]
n = 0
for p in range(loop):
    point = dict(values, c4=c4[p // side], m1=4 + (p % side) * 4 / (side - 1))
    for d in range(draws + 1):
        json.dump({"params": point}, open(f"{work}/p{n}.json", "w"))
        n += 1
print(n)
PY
t0=$(date +%s.%N)
for f in "$work"/p*.json; do
  "$bin" -q simulate "$campaign" --params "$f" --substeps "$substeps" --out "$work/sim.csv" --overwrite
done
t1=$(date +%s.%N)
python3 - "$cpu" "$gpu" "$t0" "$t1" "$loop" "$draws" "$side" <<'PY'
import json, sys, subprocess
cpu, gpu_text = json.loads(sys.argv[1]), sys.argv[2]
t0, t1, loop, draws, side = float(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5]), int(sys.argv[6]), int(sys.argv[7])
model = next((l.split(":", 1)[1].strip() for l in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines() if l.startswith("Model name")), "?")
runs = cpu["runs"]
per = (t1 - t0) / (loop * (draws + 1))
print(f"processor: {model}")
print(f"{'path':<34}{'runs':>9}{'wall s':>10}{'runs/s':>10}")
print(f"{'sweep, CPU lanes (' + cpu['device'] + ')':<34}{runs:>9}{cpu['wall_s']:>10.1f}{cpu['runs_per_s']:>10.0f}")
try:
    gpu = json.loads(gpu_text)
    print(f"{'sweep, GPU':<34}{gpu['runs']:>9}{gpu['wall_s']:>10.1f}{gpu['runs_per_s']:>10.0f}   {gpu['device']}")
except Exception:
    print(f"sweep, GPU: did not run ({gpu_text.strip()[:200]})")
print(f"{'loop of rigfit simulate (scaled)':<34}{runs:>9}{per * runs:>10.0f}{1 / per:>10.1f}   timed over {loop * (draws + 1)} processes")
print(f"CPU sweep against the loop: {per * runs / cpu['wall_s']:.0f}× faster")
try:
    print(f"GPU sweep against the CPU sweep: {cpu['wall_s'] / gpu['wall_s']:.2f}×")
except Exception:
    pass
PY
