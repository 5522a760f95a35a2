"""The numbers in docs/guide/python.md: the Python layer's overhead on a fit
(wall time of rigfit.fit vs the CLI's `rigfit run`, the same job) and the
ensemble's throughput through rigfit.simulate and the objective, in
candidate-steps per second (per wall second and per CPU-second of the
process, as docs/engineering/performance.md gives the bench's figures).

    python benches/measure.py [--rounds 3] [--cli target/release/rigfit]
"""

import argparse
import json
import os
import pathlib
import subprocess
import tempfile
import time

import numpy as np

import rigfit

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "campaigns" / "aa2024_t3_synthetic.json"


def timed(f):
    w, c = time.perf_counter(), time.process_time()
    out = f()
    return out, time.perf_counter() - w, time.process_time() - c


def fit_overhead(cli, rounds, population, generations):
    args = ["--backend", "cpu", "--population", str(population), "--generations",
            str(generations), "--seed", "1"]
    rows = []
    for r in range(rounds):
        with tempfile.TemporaryDirectory() as d:
            t = time.perf_counter()
            subprocess.run([cli, "--quiet", "run", str(EXAMPLE), *args, "--out", d], check=True)
            t_cli = time.perf_counter() - t
            cli_params = json.loads(pathlib.Path(d, "result.json").read_text())["params"]
        # As the CLI does: the campaign loaded (the rig compiled, its lanes
        # built) inside the timing; then a second fit of the loaded campaign,
        # as a notebook session does.
        t = time.perf_counter()
        c = rigfit.Campaign.from_json(EXAMPLE)
        res = rigfit.fit(c, backend="cpu", population=population, generations=generations, seed=1)
        t_py = time.perf_counter() - t
        assert res.best_values == cli_params, "Python and CLI disagree"
        t = time.perf_counter()
        rigfit.fit(c, backend="cpu", population=population, generations=generations, seed=1)
        t_again = time.perf_counter() - t
        rows.append((t_cli, t_py, t_again))
        print(f"fit round {r}: CLI {t_cli:.2f} s, Python with loading {t_py:.2f} s "
              f"({t_py / t_cli - 1:+.1%}), again on the loaded campaign {t_again:.2f} s")
    return rows


def throughput(sets, rounds, backend):
    c = rigfit.Campaign.from_json(EXAMPLE)
    steps = sum((c.experiment_info(x)["fit_window"][1] - 1) * c.substeps for x in c.experiments)
    lo, hi = c.bounds[:, 0], c.bounds[:, 1]
    theta = lo + (hi - lo) * np.random.default_rng(0).random((sets, len(c.genes)))
    f = c.objective(backend=backend)
    out = {}
    for name, call in (("simulate", lambda: rigfit.simulate(c, theta, backend=backend)),
                       ("objective", lambda: f(theta.T))):
        call()  # warm: native lanes built, pipelines compiled
        best = None
        for _ in range(rounds):
            _, wall, cpu = timed(call)
            rate = (sets * steps / wall, sets * steps / cpu)
            best = rate if best is None or rate[0] > best[0] else best
        out[name] = best
        print(f"{name} ({backend}, {sets} sets x {steps} steps): {best[0]:.3g} candidate-steps "
              f"per wall s, {best[1]:.3g} per CPU-s")
    return out


if __name__ == "__main__":
    p = argparse.ArgumentParser()
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--cli", default=os.environ.get("RIGFIT_BIN", str(ROOT / "target/release/rigfit")))
    p.add_argument("--population", type=int, default=512)
    p.add_argument("--generations", type=int, default=20)
    p.add_argument("--sets", type=int, default=4096)
    p.add_argument("--backend", default="cpu")
    a = p.parse_args()
    throughput(a.sets, a.rounds, a.backend)
    rows = fit_overhead(a.cli, a.rounds, a.population, a.generations)
    for i, what in enumerate(("CLI", "Python, campaign loaded inside", "Python, loaded campaign")):
        v = sorted(r[i] for r in rows)
        print(f"{what}: min {v[0]:.2f} s, median {v[len(v) // 2]:.2f} s")
