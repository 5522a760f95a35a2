#!/usr/bin/env python3
"""Cuts the slices of the EMPS estimation record that campaigns/emps*.json read.

Usage: scripts/emps_slices.py PATH/emps_estimation.csv
(the benchmark's DATA_EMPS.mat as CSV: time_s, position_m, reference_position_m,
controller_voltage_V; see campaigns/emps/PROVENANCE.md). Writes campaigns/emps/.
"""
import csv
import sys

WINDOWS = [1.0, 4.0, 7.5, 11.0, 14.5, 18.0, 21.5]  # open-loop window starts (s)
LENGTH = 1000  # samples per open-loop window (1 s)
HALF = 5  # central difference over ±HALF samples for the start velocity

rows = list(csv.reader(open(sys.argv[1])))
head, body = rows[0], rows[1:]
assert head == ["time_s", "position_m", "reference_position_m", "controller_voltage_V"], head
note = "# EMPS estimation record (Janot, Gautier, Brunot 2019); see PROVENANCE.md\n"

with open("campaigns/emps/closed_loop.csv", "w") as f:
    f.write(note)
    f.write("time_s,position_m,reference_position_m,controller_voltage_V\n")
    for r in body:
        f.write(f"{r[0]},{r[1]},{r[2]},{r[3]}\n")

starts = []
for w in WINDOWS:
    k = round(w * 1000)
    t0, q0 = float(body[k][0]), float(body[k][1])
    v0 = (float(body[k + HALF][1]) - float(body[k - HALF][1])) / (
        float(body[k + HALF][0]) - float(body[k - HALF][0]))
    name = f"campaigns/emps/open_loop_{w:04.1f}s.csv".replace(".", "_", 1).replace("_csv", ".csv")
    with open(name, "w") as f:
        f.write(note)
        f.write(f"# window from record time {body[k][0]} s; position relative to {body[k][1]} m\n")
        f.write("time_s,position_m,controller_voltage_V\n")
        for r in body[k:k + LENGTH]:
            f.write(f"{float(r[0]) - t0:.9g},{float(r[1]) - q0:.9g},{r[3]}\n")
    starts.append((name, body[k][0], q0, v0))
for s in starts:
    print("%s  t0 = %s s  q0 = %.8g m  v0 = %.8g m/s" % s)
