#!/usr/bin/env bash
# Writes the SYNTHETIC records of the shipped series (rates.series.json):
# 5 rates x 4 repeats of the tensile test of tensile_rate.json, each
# simulated by `rigfit simulate` at the truth of truth.json (the rig of
# aa2024_t3_reference_params.json; the specimen's elastic stiffness
# scattering by specimen, its fracture elongation rising with the rate)
# over 2 ms at 1 us, with Gaussian noise of 20 N, seed 100 + the row.
#
#   campaigns/series/make_records.sh [path/to/rigfit]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${1:-$here/../../target/release/rigfit}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$here/records"
python3 - "$here" "$work" <<'PY'
import json, sys
here, work = sys.argv[1:3]
campaign = json.load(open(f"{here}/tensile_rate.json"))
truth = json.load(open(f"{here}/truth.json"))
rig = {"k1": 8.4e9, "c1": 5.51e5, "c1_post": 9.22e3, "c4": 1.57e4, "gap": 1.87e-5}
for i, (tid, t) in enumerate(truth.items()):
    c = json.loads(json.dumps(campaign))
    c["experiments"][0]["params"]["velocity"] = t["velocity"]
    c["experiments"][0]["data"]["file"] = f"{here}/records/{tid}.csv"
    json.dump(c, open(f"{work}/{tid}.json", "w"))
    p = dict(rig, **{"test.k_lin": t["k_lin"], "test.e_fracture": t["e_fracture"]})
    json.dump({"params": p}, open(f"{work}/{tid}.params.json", "w"))
    print(tid, 100 + i, file=open(f"{work}/list", "a"))
PY
while read -r tid seed; do
  "$bin" -q simulate "$work/$tid.json" --params "$work/$tid.params.json" \
    --duration 2e-3 --dt 1e-6 --noise 20 --seed "$seed" --out "$here/records/$tid.csv" --overwrite
done < "$work/list"
