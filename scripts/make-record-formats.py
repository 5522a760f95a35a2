#!/usr/bin/env python3
"""Writes the shipped example's record in every record format rigfit reads.

Reads campaigns/aa2024_t3_v2_synthetic.csv (a SYNTHETIC record: see its
header) with Python's float() per cell, the f64 rigfit's CSV reader gets, and
writes the same two columns (time explicit as a channel of its own, so a fit
on any of the files sees bit-identical samples) to campaigns/formats/ with
each format's own ecosystem writer:

  aa2024_t3_v2.tdms      npTDMS        group "tensile", channels t_s and force_N
  aa2024_t3_v2.h5        h5py          /tensile/t_s, /tensile/force_N
  aa2024_t3_v2_v5.mat    scipy.io      MAT v5 (compressed), variables t_s, force_N
  aa2024_t3_v2_v73.mat   hdf5storage   MAT v7.3 (HDF5), variables t_s, force_N
  aa2024_t3_v2.uff       pyuff         ASCII dataset 58, double, uneven abscissa
  aa2024_t3_v2_58b.uff   pyuff         binary dataset 58b, the same

Each file is read back with the library that wrote it and compared bit for
bit with the CSV's values; any difference stops the script with exit code 1.

Usage (from the repository root):

  python3 -m venv /tmp/venv-formats
  /tmp/venv-formats/bin/pip install numpy npTDMS h5py scipy pyuff hdf5storage
  /tmp/venv-formats/bin/python scripts/make-record-formats.py
"""

import os
import struct
import sys

import h5py
import hdf5storage
import nptdms
import numpy as np
import pyuff
import scipy
import scipy.io

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CSV = os.path.join(ROOT, "campaigns", "aa2024_t3_v2_synthetic.csv")
OUT = os.path.join(ROOT, "campaigns", "formats")
STEM = "aa2024_t3_v2"
GROUP = "tensile"
TIME, FORCE = "t_s", "force_N"
# Each file must stay small: the CSV has ~2500 rows (two f64 columns, 40 kB).
MAX_BYTES = 300_000


def read_csv(path):
    """The CSV's time and force columns as float64 arrays, float() per cell."""
    header = None
    rows = []
    with open(path, encoding="utf-8") as fh:
        for n, line in enumerate(fh, 1):
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            cells = line.split(",")
            if header is None:
                header = cells
                continue
            if len(cells) != len(header):
                sys.exit(f"{path}:{n}: expected {len(header)} cells, found {len(cells)}")
            rows.append([float(c) for c in cells])
    if header != [TIME, FORCE]:
        sys.exit(f"{path}: expected the header {TIME},{FORCE}, found {header}")
    data = np.array(rows, dtype="<f8")
    return data[:, 0].copy(), data[:, 1].copy()


def same_bits(what, got, want):
    """Stops the script unless `got` holds exactly the f64 bits of `want`."""
    got = np.asarray(got)
    if got.dtype != np.float64:
        sys.exit(f"{what}: expected float64 values, read back {got.dtype}")
    got = got.reshape(-1)
    if got.shape != want.shape:
        sys.exit(f"{what}: expected {want.shape[0]} values, read back {got.shape[0]}")
    bad = np.flatnonzero(got.view(np.uint64) != want.view(np.uint64))
    if bad.size:
        i = int(bad[0])
        sys.exit(
            f"{what}: {bad.size} values differ from the CSV's; first at row {i}: "
            f"wrote {want[i]!r}, read back {got[i]!r}"
        )


def write_tdms(path, t, f):
    root = nptdms.RootObject(properties={"title": "SYNTHETIC record of the shipped example"})
    group = nptdms.GroupObject(GROUP)
    time = nptdms.ChannelObject(GROUP, TIME, t, properties={"unit_string": "s"})
    force = nptdms.ChannelObject(
        GROUP,
        FORCE,
        f,
        properties={
            "unit_string": "N",
            "wf_increment": float(t[1] - t[0]),
            "wf_start_offset": float(t[0]),
        },
    )
    with nptdms.TdmsWriter(path) as w:
        w.write_segment([root, group, time, force])
    back = nptdms.TdmsFile.read(path)
    same_bits(f"{path} {GROUP}/{TIME}", back[GROUP][TIME][:], t)
    same_bits(f"{path} {GROUP}/{FORCE}", back[GROUP][FORCE][:], f)
    for name, unit in [(TIME, "s"), (FORCE, "N")]:
        got = back[GROUP][name].properties.get("unit_string")
        if got != unit:
            sys.exit(f"{path} {GROUP}/{name}: expected unit_string {unit!r}, read back {got!r}")


def write_h5(path, t, f):
    with h5py.File(path, "w") as h:
        g = h.create_group(GROUP)
        for name, values, unit in [(TIME, t, "s"), (FORCE, f, "N")]:
            d = g.create_dataset(name, data=values, dtype="<f8")
            d.attrs["units"] = unit
    with h5py.File(path, "r") as h:
        for name, values, unit in [(TIME, t, "s"), (FORCE, f, "N")]:
            d = h[f"/{GROUP}/{name}"]
            same_bits(f"{path} /{GROUP}/{name}", d[()], values)
            got = d.attrs["units"]
            if got != unit:
                sys.exit(f"{path} /{GROUP}/{name}: expected units {unit!r}, read back {got!r}")


def write_mat_v5(path, t, f):
    scipy.io.savemat(
        path, {TIME: t, FORCE: f}, format="5", do_compression=True, oned_as="column"
    )
    back = scipy.io.loadmat(path)
    same_bits(f"{path} {TIME}", back[TIME], t)
    same_bits(f"{path} {FORCE}", back[FORCE], f)


def write_mat_v73(path, t, f):
    hdf5storage.savemat(
        path,
        {TIME: t, FORCE: f},
        format="7.3",
        oned_as="column",
        store_python_metadata=False,
        truncate_existing=True,
    )
    back = hdf5storage.loadmat(path)
    same_bits(f"{path} {TIME}", back[TIME], t)
    same_bits(f"{path} {FORCE}", back[FORCE], f)


def write_uff(path, t, f, binary):
    ds = pyuff.prepare_58(
        binary=1 if binary else 0,
        id1=FORCE,
        id2="SYNTHETIC record of the shipped example (campaigns/aa2024_t3_v2_synthetic.csv)",
        id3="NONE",
        id4="NONE",
        id5="NONE",
        func_type=1,  # time response
        rsp_node=1,
        rsp_dir=1,
        ref_node=0,
        ref_dir=0,
        abscissa_spacing=0,  # uneven: the time values are written
        abscissa_spec_data_type=17,  # time
        abscissa_axis_units_lab="s",
        ordinate_spec_data_type=13,  # excitation force
        ordinate_axis_units_lab="N",
        orddenom_spec_data_type=0,  # no denominator
        z_axis_spec_data_type=0,
        data=f,
        x=t,
    )
    # Axis labels are not arguments of prepare_58; the writer takes them from the dict.
    ds["abscissa_axis_lab"] = "time"
    ds["ordinate_axis_lab"] = "force"
    # Written in "add" mode to a new file: pyuff 2.5's "overwrite" mode reopens
    # the file for the binary part of a 58b set and truncates its header.
    if os.path.exists(path):
        os.remove(path)
    pyuff.UFF(path).write_sets(ds, mode="add", force_double=True)
    back = pyuff.UFF(path).read_sets(0)
    if back["type"] != 58 or bool(back.get("binary")) != binary:
        sys.exit(f"{path}: read back dataset {back['type']} binary={back.get('binary')}")
    if back["id1"].strip() != FORCE or back["ordinate_axis_units_lab"].strip() != "N":
        sys.exit(
            f"{path}: read back ID line 1 {back['id1']!r}, "
            f"ordinate units {back['ordinate_axis_units_lab']!r}"
        )
    if back["ord_data_type"] != 4 or back["abscissa_spacing"] != 0:
        sys.exit(
            f"{path}: expected real double data (4) on an uneven abscissa (0), read back "
            f"{back['ord_data_type']}, {back['abscissa_spacing']}"
        )
    same_bits(f"{path} abscissa", back["x"], t)
    same_bits(f"{path} ordinate", back["data"], f)


def main():
    t, f = read_csv(CSV)
    os.makedirs(OUT, exist_ok=True)
    print(f"{os.path.relpath(CSV, ROOT)}: {t.size} rows")
    jobs = [
        (f"{STEM}.tdms", lambda p: write_tdms(p, t, f), f"npTDMS {nptdms.__version__}"),
        (
            f"{STEM}.h5",
            lambda p: write_h5(p, t, f),
            f"h5py {h5py.__version__} (HDF5 {h5py.version.hdf5_version})",
        ),
        (f"{STEM}_v5.mat", lambda p: write_mat_v5(p, t, f), f"scipy {scipy.__version__}"),
        (
            f"{STEM}_v73.mat",
            lambda p: write_mat_v73(p, t, f),
            f"hdf5storage {hdf5storage.__version__}, h5py {h5py.__version__}",
        ),
        (f"{STEM}.uff", lambda p: write_uff(p, t, f, False), f"pyuff {pyuff.__version__}"),
        (f"{STEM}_58b.uff", lambda p: write_uff(p, t, f, True), f"pyuff {pyuff.__version__}"),
    ]
    for name, write, by in jobs:
        path = os.path.join(OUT, name)
        write(path)
        size = os.path.getsize(path)
        if size > MAX_BYTES:
            sys.exit(f"{path}: {size} bytes, expected at most {MAX_BYTES}")
        print(f"{name:<22} {size:>8} bytes  {by}  read back bit-identical")
    print(f"numpy {np.__version__}, Python {sys.version.split()[0]}")
    # The f64 bits of the first force sample, to compare with other readers.
    print(f"first force sample: {f[0]!r} = 0x{struct.unpack('<Q', f[0].tobytes())[0]:016x}")


if __name__ == "__main__":
    main()
