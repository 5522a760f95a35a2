#!/usr/bin/env python3
"""The highest test speed at which the load cell's ringing stays below a limit.

Reads the table `rigfit sweep campaigns/design/speed_limit.sweep.json --out
speed.csv` writes and prints, for each slack-adapter damping `c4` and load-cell
mass `m1`, the speed (m/s) at which the ringing (at the fitted values, and at
the 95 % band's upper and lower ends) first reaches the limit, interpolated
linearly between the swept speeds; "above" where it stays below over the sweep.

    python3 campaigns/design/speed_limit.py speed.csv [limit, default 0.10]
"""
import csv
import sys
from collections import defaultdict


def first_reach(points, limit):
    """The speed where `value` first reaches `limit`, linear between points."""
    previous = None
    for v, y in points:
        if y >= limit:
            if previous is None:
                return v
            pv, py = previous
            return pv + (limit - py) * (v - pv) / (y - py)
        previous = (v, y)
    return None


def limits(path, limit=0.10):
    """(c4, m1, speed, band low, band high) per design, speeds as text."""
    rows = list(csv.DictReader(open(path, newline="")))
    speed = next(k for k in rows[0] if k.endswith(".velocity"))
    designs = defaultdict(list)
    for r in rows:
        designs[(float(r["c4"]), float(r["m1"]))].append(r)
    top = max(float(r[speed]) for r in rows)
    show = lambda v: f"> {top:g}" if v is None else f"{v:.2f}"
    out = []
    for (c4, m1), rs in sorted(designs.items()):
        rs.sort(key=lambda r: float(r[speed]))
        at = lambda key: first_reach([(float(r[speed]), float(r[key])) for r in rs if r[key]], limit)
        # The band's upper end reaches the limit first: the lower speed.
        out.append((c4, m1, show(at("ringing")), show(at("ringing.hi")), show(at("ringing.lo"))))
    return out


def main():
    limit = float(sys.argv[2]) if len(sys.argv) > 2 else 0.10
    print(f"{'c4 (N·s/m)':>11} {'m1 (kg)':>8} {'speed (m/s)':>12}   95 % band")
    for c4, m1, v, lo, hi in limits(sys.argv[1], limit):
        print(f"{c4:>11.0f} {m1:>8g} {v:>12}   [{lo}, {hi}]")


if __name__ == "__main__":
    main()
