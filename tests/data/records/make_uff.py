"""Writes the universal-file (dataset 58 / 58b) test records of rigfit's UFF
reader, and beside each `uff_*.uff` a `uff_*.expected` listing the channels
the reader must produce, one per line:

    name <TAB> unit or - <TAB> start,increment or - <TAB> values (repr, space-separated)

Run with pyuff and numpy installed:  python make_uff.py
"""

import math
import os
import struct

import numpy as np
import pyuff

HERE = os.path.dirname(os.path.abspath(__file__))
DATE = {"date_db_created": "01-Jan-26", "time_db_created": "00:00:00",
        "date_db_saved": "01-Jan-26", "time_db_saved": "00:00:00",
        "date_file_written": "01-Jan-26", "time_file_written": "00:00:00"}


def dset58(id1, x, data, spacing, abscissa=(17, "Time", "s"), ordinate=(0, "NONE", "NONE"), binary=0):
    d = {"type": 58, "binary": binary, "func_type": 1, "rsp_node": 1, "rsp_dir": 3,
         "ref_node": 0, "ref_dir": 0, "x": np.asarray(x, dtype=float), "data": np.asarray(data),
         "abscissa_spacing": spacing,
         "abscissa_spec_data_type": abscissa[0], "abscissa_axis_lab": abscissa[1],
         "abscissa_axis_units_lab": abscissa[2],
         "ordinate_spec_data_type": ordinate[0], "ordinate_axis_lab": ordinate[1],
         "ordinate_axis_units_lab": ordinate[2],
         "orddenom_spec_data_type": 0, "z_axis_spec_data_type": 0}
    if id1 is not None:
        d["id1"] = id1
    return d


def line(name, unit, timing, values):
    t = "-" if timing is None else "%r,%r" % timing
    return "%s\t%s\t%s\t%s\n" % (name, unit or "-", t, " ".join(repr(float(v)) for v in values))


def write(name, dsets, expected):
    path = os.path.join(HERE, name + ".uff")
    if os.path.exists(path):
        os.remove(path)
    pyuff.UFF(path).write_sets(dsets, mode="add")
    with open(os.path.join(HERE, name + ".expected"), "w") as f:
        f.writelines(expected)


# 1. ASCII, even spacing, real double: a force in N and a displacement in m.
n = 21
t = [k * 0.001 for k in range(n)]
force = [round(250.0 * math.sin(2 * math.pi * 40 * tk), 6) for tk in t]
disp = [round(1.5e-4 * math.cos(2 * math.pi * 40 * tk) + 1e-9 * k, 12) for k, tk in enumerate(t)]
write("uff_even_double", [
    dset58("load cell", t, force, 1, ordinate=(13, "Force", "N")),
    dset58("stroke", t, disp, 1, abscissa=(0, "Time", "s"), ordinate=(8, "Displacement", "m")),
], [line("load cell", "N", (0.0, 0.001), force), line("stroke", "m", (0.0, 0.001), disp)])

# 2. ASCII, uneven spacing: explicit time values (6 significant digits, as
#    pyuff writes abscissae with E13.5), twice under one ID line 1; then a
#    complex uneven function over frequency.
tu = [0.0, 0.001, 0.0025, 0.004, 0.0075, 0.01, 0.0125, 0.02, 0.03]
a1 = [round(9.81 * math.sin(7 * tk * 100), 9) for tk in tu]
a2 = [round(-3.5 + 0.25 * k, 6) for k in range(len(tu))]
f = [10.0, 12.5, 20.0, 31.25, 50.0]
h = [complex(round(1 / (k + 1), 9), round(-0.1 * k, 6)) for k in range(len(f))]
write("uff_uneven", [
    dset58("accel", tu, a1, 0, ordinate=(12, "Acceleration", "m/s^2")),
    dset58("accel", tu, a2, 0, ordinate=(12, "Acceleration", "m/s^2")),
    dset58("frf", f, np.asarray(h), 0, abscissa=(18, "Frequency", "Hz"), ordinate=(12, "Accelerance", "NONE")),
], [
    line("accel (1)/abscissa", "s", None, tu), line("accel (1)", "m/s^2", None, a1),
    line("accel (2)/abscissa", "s", None, tu), line("accel (2)", "m/s^2", None, a2),
    line("frf/abscissa", "Hz", None, f),
    line("frf/real", None, None, [c.real for c in h]), line("frf/imag", None, None, [c.imag for c in h]),
])

# 3. A dataset 151 header, then a complex even-spaced FRF (frequency
#    abscissa: no timing) whose ID line 1 is left to pyuff's "NONE".
hdr = {"type": 151, "model_name": "rig", "description": "test", "db_app": "pyuff",
       "program": "make_uff.py"}
hdr.update(DATE)
fe = [5.0 + 2.5 * k for k in range(6)]
he = [complex(round(math.cos(k), 9), round(math.sin(k), 9)) for k in range(6)]
write("uff_mixed", [hdr, dset58(None, fe, np.asarray(he), 1, abscissa=(18, "Frequency", "Hz"),
                                ordinate=(13, "Force", "N"))], [
    line("dataset 1/real", "N", None, [c.real for c in he]),
    line("dataset 1/imag", "N", None, [c.imag for c in he]),
])

# 4. Binary 58b as pyuff writes it (little-endian IEEE doubles; note pyuff's
#    byte count field holds points x 8 even where the data holds more values):
#    an even real time signal, then an uneven complex function.
tb = [k * 0.0005 for k in range(8)]
vb = [round(10 * math.sin(k), 9) for k in range(8)]
fb = [1.0, 2.0, 4.0, 8.0]
hb = [complex(0.5 * k, -0.25 * k) for k in range(4)]
write("uff_binary", [
    dset58("strain", tb, vb, 1, abscissa=(17, "Time", "s"), ordinate=(3, "Strain", "m/m"), binary=1),
    dset58("frf", fb, np.asarray(hb), 0, abscissa=(18, "Frequency", "Hz"), ordinate=(0, "NONE", "NONE"), binary=1),
], [
    line("strain", "m/m", (0.0, 0.0005), vb),
    line("frf/abscissa", "Hz", None, fb),
    line("frf/real", None, None, [c.real for c in hb]), line("frf/imag", None, None, [c.imag for c in hb]),
])

# 5. Hand-made 58b (pyuff writes only the machine's byte order and doubles):
#    big-endian IEEE single precision, even spacing over time, laid out as the
#    Universal File Format's binary dataset 58 describes (11 ASCII lines after
#    the 58b line, then exactly the stated bytes, then "    -1").
vs = [0.1 * k - 0.35 for k in range(7)]
vs32 = [float(np.float32(v)) for v in vs]
data = b"".join(struct.pack(">f", v) for v in vs)
head = ["%6i" % -1,
        "%6ib%6i%6i%12i%12i%6i%6i%12i%12i" % (58, 2, 2, 11, len(data), 0, 0, 0, 0),
        "%-80s" % "pressure", "%-80s" % "NONE", "%-80s" % "NONE", "%-80s" % "NONE", "%-80s" % "NONE",
        "%5i%10i%5i%10i %10s%10i%4i %10s%10i%4i" % (1, 0, 0, 0, "NONE", 4, 1, "NONE", 0, 0),
        "%10i%10i%10i%13.5e%13.5e%13.5e" % (2, len(vs), 1, 0.5, 0.25, 0.0),
        "%10i%5i%5i%5i %-20s %-20s" % (17, 0, 0, 0, "Time", "s"),
        "%10i%5i%5i%5i %-20s %-20s" % (15, 0, 0, 0, "Pressure", "bar"),
        "%10i%5i%5i%5i %-20s %-20s" % (0, 0, 0, 0, "NONE", "NONE"),
        "%10i%5i%5i%5i %-20s %-20s" % (0, 0, 0, 0, "NONE", "NONE")]
with open(os.path.join(HERE, "uff_binary_be32.uff"), "wb") as fh:
    fh.write(("\n".join(head) + "\n").encode("ascii") + data + b"%6i\n" % -1)
with open(os.path.join(HERE, "uff_binary_be32.expected"), "w") as fh:
    fh.write(line("pressure", "bar", (0.5, 0.25), vs32))
