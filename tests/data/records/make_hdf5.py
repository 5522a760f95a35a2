"""Writes the HDF5 and MATLAB v7.3 test records of rigfit's HDF5 reader.

Run from the repository root with h5py, hdf5storage and numpy installed:
    python tests/data/records/make_hdf5.py
Every numeric value is built from integers with one correctly rounded
operation (a product or a quotient), so the reader's tests recompute it in
Rust and compare bit for bit.
"""

import os

import h5py
import hdf5storage
import numpy as np

OUT = "tests/data/records/"
N = 50
k = np.arange(N)
t_s = k * 0.002                      # (k as f64) * 0.002
force_N = ((k * k) % 97) / 7.0       # ((k*k) % 97) as f64 / 7.0

with h5py.File(OUT + "hdf5_tensile.h5", "w") as f:
    tensile = f.create_group("tensile")
    t = tensile.create_dataset("t_s", data=t_s)
    t.attrs["units"] = "s"
    force = tensile.create_dataset("force_N", data=force_N)
    force.attrs["units"] = "N"
    force.attrs["wf_increment"] = 0.002
    force.attrs["wf_start_offset"] = 0.25
    daq = f.create_group("daq")
    daq.attrs["sample_rate"] = 2000.0
    daq.attrs["start_time"] = "2026-01-02T03:04:05"  # not numeric: start 0
    strain = daq.create_dataset(
        "strain", data=((k * 37) % 200 - 100).astype(np.int16))
    strain.attrs["UNITS"] = np.bytes_(b"ue")          # fixed-length bytes
    i, j = np.meshgrid(np.arange(20), np.arange(3), indexing="ij")
    xyz = f.create_dataset("grid/xyz", data=((i * 10 + j) / 4).astype(np.float32))
    xyz.attrs["unit"] = "mm"
    r, c = np.meshgrid(np.arange(2), np.arange(80), indexing="ij")
    f.create_dataset("grid/wide", data=(r * 1000 + c).astype(np.int32))
    f.create_dataset("notes", data=np.array([b"pull", b"hold"]))  # strings
    f.create_dataset("gain", data=2.5)                            # scalar
    f.create_dataset("cube", data=np.zeros((2, 2, 2)))            # 3-D
    f.create_dataset("flags", data=np.array([True, False]))       # enum
    f["alias"] = h5py.SoftLink("/tensile/t_s")                    # not followed

with h5py.File(OUT + "hdf5_strings_only.h5", "w") as f:
    f.create_dataset("notes", data=np.array([b"pull", b"hold"]))
    f.create_dataset("gain", data=2.5)

with h5py.File(OUT + "hdf5_unwritten.h5", "w") as f:
    # Never written: no storage, a shape far larger than the file.
    f.create_dataset("big", shape=(1_000_000,), dtype="f8")

m = np.stack([t_s[:10], force_N[:10]], axis=1)  # MATLAB 10x2
if os.path.exists(OUT + "hdf5_mat73.mat"):  # savemat appends otherwise
    os.remove(OUT + "hdf5_mat73.mat")
hdf5storage.savemat(
    OUT + "hdf5_mat73.mat",
    {
        "t_s": t_s,
        "force_N": force_N,
        "m": m,
        "flag": np.array([True, False]),
        "label": "tensile",
        "empty": np.zeros((0,)),
        "counts": np.array([3, -4, 5], dtype=np.int16),
        "rec": {"t": t_s[:8], "force": force_N[:8], "units": "kN"},
    },
    format="7.3",
    matlab_compatible=True,
)
