"""Writes the MAT-file (level 5) test records under tests/data/records/.

Run from the repository root with numpy and scipy installed:

    python tests/data/records/make_mat.py

Every value is made of IEEE additions and multiplications of small integers
so that the reader's unit tests can recompute them bit for bit (see
`src/record/mat.rs`). `mat_be.mat` is `mat_v5.mat` with every number
byte-swapped and the header's endian indicator set to `MI` (scipy writes
native byte order only); the swap follows the "MAT-File Format" (level 5)
element layout.
"""

import os
import struct

import numpy as np
import scipy.io as sio
import scipy.sparse as sp

HERE = os.path.dirname(os.path.abspath(__file__))
N = 16
k = np.arange(N, dtype=np.float64)


def t_s():
    return k * 1e-3


def force_n():
    return k * 0.5 - 2.25 + k * k * 1e-2


def path(name):
    return os.path.join(HERE, name)


def write_v5():
    sio.savemat(
        path("mat_v5.mat"),
        {
            "t_s": t_s().reshape(-1, 1),
            "force_N": force_n().reshape(1, -1),
            "gain": 2.0,
            "notes": np.array([["a", np.array([1.0, 2.0, 3.0])]], dtype=object),
            "label": "run 7",
        },
        do_compression=False,
        oned_as="row",
    )


def write_compressed():
    counts = np.empty((N, 2), dtype=np.int16)
    counts[:, 0] = np.arange(N) * 3 - 20
    counts[:, 1] = -np.arange(N) * 1000
    sio.savemat(
        path("mat_compressed.mat"),
        {
            "t_s": t_s().reshape(-1, 1),
            "counts": counts,
            "flag": np.array([True, False, True]),
            "z": np.array([1 + 2j, 3 - 1j]),
            "sp": sp.csc_matrix(np.eye(3)),
            "v32": (k * 0.25).astype(np.float32),
            "big": (np.arange(N, dtype=np.uint64) * np.uint64(2**40)),
        },
        do_compression=True,
        oned_as="column",
    )


def write_struct():
    sio.savemat(
        path("mat_struct.mat"),
        {
            "rec": {"t": t_s(), "force": force_n(), "units": "N"},
            "wave": {"dt": 1e-3, "t0": 0.5, "x": k * 2.0, "label": "x"},
            "s": {
                "a": k + 1.0,
                "b": k - 1.0,
                "units": {"a": "N", "b": "mm"},
                "inner": {"y": k * 3.0, "unit": "V"},
            },
        },
        do_compression=False,
        oned_as="row",
    )


SIZES = {1: 1, 2: 1, 3: 2, 4: 2, 5: 4, 6: 4, 7: 4, 9: 8, 12: 8, 13: 8, 16: 1, 17: 2, 18: 4}


def swap_data(data, mi_type):
    size = SIZES[mi_type]
    if size == 1:
        return data
    out = bytearray()
    for i in range(0, len(data) - len(data) % size, size):
        out += data[i : i + size][::-1]
    return bytes(out + data[len(data) - len(data) % size :])


def swap_elements(data):
    """Byte-swaps a run of little-endian data elements."""
    out = bytearray()
    pos = 0
    while pos < len(data):
        (word,) = struct.unpack_from("<I", data, pos)
        if word >> 16:
            mi_type, n = word & 0xFFFF, word >> 16
            out += struct.pack(">I", word)
            out += swap_data(data[pos + 4 : pos + 4 + n], mi_type) + data[pos + 4 + n : pos + 8]
            pos += 8
            continue
        mi_type, n = struct.unpack_from("<II", data, pos)
        out += struct.pack(">II", mi_type, n)
        body = data[pos + 8 : pos + 8 + n]
        out += swap_elements(body) if mi_type == 14 else swap_data(body, mi_type)
        padded = (n + 7) // 8 * 8
        out += data[pos + 8 + n : pos + 8 + padded]
        pos += 8 + padded
    return bytes(out)


def write_big_endian():
    with open(path("mat_v5.mat"), "rb") as f:
        data = f.read()
    assert data[126:128] == b"IM"
    header = data[:124] + data[124:126][::-1] + b"MI"
    with open(path("mat_be.mat"), "wb") as f:
        f.write(header + swap_elements(data[128:]))


if __name__ == "__main__":
    write_v5()
    write_compressed()
    write_struct()
    write_big_endian()
