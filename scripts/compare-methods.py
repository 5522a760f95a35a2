#!/usr/bin/env python3
"""Search methods compared on a shipped campaign: evaluations and wall time
to 1.01× the noise floor, GA against CMA-ES, each followed by the polish.

Two measures, per method and seed (median over the seeds):

- "search + polish": the fewest generations G (of 1, 2, 4, … 64) after which
  the search and then the polish end at or below 1.01× the floor; its
  evaluations (the search's and the polish's) and the job's wall time.
  Runs with a seed are prefixes of each other, so G is exact on that ladder.
- "search alone": the search with `--target-fitness` = 1.01× the floor, capped
  at --cap generations; the evaluations at which it stopped (or "not reached").

The floor is the joint cost at the generating values, from the campaign's
documentation (tensile three-rate: 4.4493e-5, docs/guide/uncertainty.md;
quarter car with friction: 8.917e-5, docs/rigs/quarter_car_friction.md).

    scripts/compare-methods.py target/release/rigfit \
        campaigns/tensile4_three_rates_synthetic.json 4.4493e-5 --backend cpu

Prints one table in Markdown, and every run's figures as JSON lines on stderr.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile


def run(binary, campaign, backend, extra, out):
    cmd = [binary, "run", campaign, "--backend", backend, "--out", out,
           "--overwrite", "-q", "--json"] + extra
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{done.stderr}")
    d = json.loads(done.stdout)
    p = d.get("polish") or {"evaluations": 0, "ga_fitness": d["fitness"]}
    return {
        "args": extra,
        "fitness": d["fitness"],
        "search_fitness": p["ga_fitness"],
        "search_evaluations": d["evaluations"],
        "polish_evaluations": p["evaluations"],
        "job_wall_time_s": d["job_wall_time_s"],
        "stop_reason": d["stop_reason"],
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("binary")
    ap.add_argument("campaign")
    ap.add_argument("floor", type=float)
    ap.add_argument("--backend", default="cpu")
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--cap", type=int, default=400,
                    help="generations at most for the search alone")
    ap.add_argument("--methods", default="ga,cmaes")
    a = ap.parse_args()
    target = 1.01 * a.floor
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out")
        for method in a.methods.split(","):
            ladder, alone = [], []
            for seed in range(1, a.seeds + 1):
                base = ["--method", method, "--seed", str(seed)]
                for g in [1, 2, 4, 8, 16, 32, 64]:
                    r = run(a.binary, a.campaign, a.backend,
                            base + ["--generations", str(g)], out)
                    print(json.dumps(r), file=sys.stderr)
                    if r["fitness"] <= target:
                        ladder.append(r)
                        break
                else:
                    ladder.append(None)
                r = run(a.binary, a.campaign, a.backend,
                        base + ["--generations", str(a.cap),
                                "--target-fitness", repr(target)], out)
                print(json.dumps(r), file=sys.stderr)
                alone.append(r if r["stop_reason"] == "target fitness reached" else None)
            rows.append((method, ladder, alone))

    def med(xs):
        xs = [x for x in xs if x is not None]
        return statistics.median(xs) if xs else float("nan")

    print(f"campaign {a.campaign}, backend {a.backend}, floor {a.floor:.4e}, "
          f"target {target:.4e}, seeds 1–{a.seeds}")
    print()
    print("| method | search + polish: generations | evaluations (search + polish) | job wall time | "
          "search alone: evaluations to target | reached |")
    print("| --- | --- | --- | --- | --- | --- |")
    for method, ladder, alone in rows:
        gens = [int(r["args"][r["args"].index("--generations") + 1]) if r else None for r in ladder]
        evals = [r["search_evaluations"] + r["polish_evaluations"] if r else None for r in ladder]
        wall = [r["job_wall_time_s"] if r else None for r in ladder]
        alone_evals = [r["search_evaluations"] if r else None for r in alone]
        reached = sum(r is not None for r in alone)
        print(f"| {method} | {med(gens):g} ({gens}) | {med(evals):.0f} ({evals}) | "
              f"{med(wall):.1f} s | {med(alone_evals):.0f} ({alone_evals}) | {reached} of {len(alone)} |")


if __name__ == "__main__":
    main()
