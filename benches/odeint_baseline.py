#!/usr/bin/env python3
"""Throughput of the workflow rigfit replaces: one SciPy `odeint` call per candidate.

Integrates the tensile4 model (the equations of rigs/tensile4.json, velocity
drive, fracture by a flag set inside the right-hand side, as hand-written GA scripts
do) for a batch of candidates around the reference values over the shipped
example's record (2500 samples of 1 µs), and prints candidate-steps per second,
counting one step per measurement sample as rigfit does with substeps = 1.

    pip install numpy scipy
    python3 benches/odeint_baseline.py [candidates]
"""
import math
import sys
import time

import numpy as np
from scipy.integrate import odeint

REF = dict(m1=7.9, m2=0.14, m3=0.48, k1=8.4e9, c1=5.51e5, c1_post=9.22e3, k_lin=8.63e7,
           e_yield=5.4e-5, a=[4.56e3, 1.97e6, -9.26e8, 1.36e11], e_fracture=1e-3, c2=0.0,
           k3=4.4e8, c3=0.0, sa=4.43e3, sb=4.87e5, sc=1.94e7, k4=1.19e8, c4=1.57e4,
           gap=1.87e-5, v=2.0, r=1.76e-6)


def make_rhs(p):
    d_star = math.log((p["k4"] - p["sc"]) / p["sa"]) / p["sb"] if p["k4"] > p["sa"] + p["sc"] else 0.0
    g_star = p["sa"] / p["sb"] * math.expm1(p["sb"] * d_star) + p["sc"] * d_star
    state = {"broken": False}

    def rhs(y, t):
        y1, y2, y3, v1, v2, v3 = y
        if t > 0:
            m = math.expm1(-p["v"] * t / p["r"])
            y4, v4 = p["v"] * t + p["r"] * m, -p["v"] * m
        else:
            y4 = v4 = 0.0
        e = y2 - y1
        if e >= p["e_fracture"]:
            state["broken"] = True
        c1 = p["c1_post"] if state["broken"] else p["c1"]
        f1 = p["k1"] * y1 + c1 * v1
        if state["broken"]:
            f2 = 0.0
        else:
            s = p["k_lin"] * e if e <= p["e_yield"] else sum(a * e**i for i, a in enumerate(p["a"]))
            f2 = s + p["c2"] * (v2 - v1)
        f3 = p["k3"] * (y3 - y2) + p["c3"] * (v3 - v2)
        d = y4 - y3 - p["gap"]
        if d <= 0:
            f4 = 0.0
        else:
            g = (p["sa"] / p["sb"] * math.expm1(p["sb"] * d) + p["sc"] * d) if d <= d_star \
                else g_star + p["k4"] * (d - d_star)
            f4 = g + p["c4"] * (v4 - v3)
        return [v1, v2, v3, (f2 - f1) / p["m1"], (f3 - f2) / p["m2"], (f4 - f3) / p["m3"]]

    return rhs


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 8
    samples = 2501
    t = np.arange(samples) * 1e-6
    rng = np.random.default_rng(1)
    start = time.perf_counter()
    for _ in range(n):
        p = dict(REF)
        for k in ("k1", "c1", "c1_post", "k_lin", "c4"):
            p[k] = REF[k] * math.exp(rng.uniform(-0.3, 0.3))
        odeint(make_rhs(p), [0.0] * 6, t, mxstep=100000)
    elapsed = time.perf_counter() - start
    rate = n * (samples - 1) / elapsed
    print(f"odeint: {n} candidates in {elapsed:.2f} s: {elapsed / n * 1e3:.1f} ms per candidate, "
          f"{rate:.3e} candidate-steps/s")


if __name__ == "__main__":
    main()
