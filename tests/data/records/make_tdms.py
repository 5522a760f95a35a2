"""Writes the TDMS test records under tests/data/records/ (see README-tdms.md).

Run from the repository root:  python tests/data/records/make_tdms.py
Needs numpy and npTDMS (pip install numpy npTDMS).

Every value is made with +, -, * and / only, so the Rust tests recompute
each one bit for bit with the same formula.
"""
import os
import struct
from datetime import datetime

import numpy as np
from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

HERE = os.path.dirname(os.path.abspath(__file__))


def tensile_two_segments():
    """Group `tensile`: t_s (unit s) and force_N (unit N, waveform timing),
    float64, written as two segments of 40 samples each."""
    k = np.arange(80, dtype=np.float64)
    t = k * 1e-6
    force = 250.0 + 0.75 * k - k * k / 64.0
    path = os.path.join(HERE, "tdms_tensile_two_segments.tdms")
    with TdmsWriter(path) as w:
        w.write_segment([
            RootObject(properties={
                "title": "tensile test", "operator_id": 7, "calibrated": True,
                "DateTime": datetime(2024, 5, 1, 12, 30, 0)}),
            GroupObject("tensile", properties={"specimen": "S-12"}),
            ChannelObject("tensile", "t_s", t[:40], properties={"unit_string": "s"}),
            ChannelObject("tensile", "force_N", force[:40], properties={
                "unit_string": "N", "wf_increment": 1e-6, "wf_start_offset": 0.0,
                "wf_samples": np.int32(40), "wf_xunit_string": "s"}),
        ])
        # The second segment repeats the channels without their properties:
        # the reader keeps the first segment's and appends the values.
        w.write_segment([
            ChannelObject("tensile", "t_s", t[40:]),
            ChannelObject("tensile", "force_N", force[40:]),
        ])


def mixed_types():
    """Group `rig`: one channel of each integer and float type, a string
    channel and a timestamp channel (both skipped), timing variants."""
    n = 12
    k = np.arange(n)
    path = os.path.join(HERE, "tdms_mixed_types.tdms")
    chans = [
        ChannelObject("rig", "label", np.array(["a", "bc", "", "déf"] * 3)),
        ChannelObject("rig", "i8", (k * 11 - 64).astype(np.int8)),
        ChannelObject("rig", "i16", (k * 2500 - 20000).astype(np.int16),
                      properties={"unit_string": "mV", "wf_increment": 0.5,
                                  "wf_start_offset": 2.0}),
        ChannelObject("rig", "i32", (k * 100000 - 7).astype(np.int32)),
        ChannelObject("rig", "i64", (k * 3000000000 - 5).astype(np.int64)),
        ChannelObject("rig", "u8", (k * 20 + 3).astype(np.uint8)),
        ChannelObject("rig", "u16", (k * 5000 + 1).astype(np.uint16),
                      properties={"unit_string": "", "wf_increment": 0.25,
                                  "wf_xunit_string": "Hz"}),
        ChannelObject("rig", "u32", (k * 300000000 + 9).astype(np.uint32)),
        ChannelObject("rig", "u64", (k * 1000000000000 + 1).astype(np.uint64)),
        ChannelObject("rig", "when", np.array(
            ["2024-05-01T12:00:00"] * n, dtype="datetime64[us]")),
        ChannelObject("rig", "f32", (k.astype(np.float32) * np.float32(0.125)
                                      - np.float32(1.5)),
                      properties={"wf_increment": 0.0}),
        ChannelObject("rig", "f64", k / 3.0),
    ]
    with TdmsWriter(path) as w:
        w.write_segment(chans)


def interleaved_big_endian():
    """Hand-made (npTDMS writes contiguous little-endian data only): group
    `rig`, channels `disp 'mm'` (int16) and `load` (float32), interleaved,
    big-endian, version 4713, in three segments:
      1. new object list, metadata, raw data of 2 chunks of 3 rows;
      2. raw data only (object list and index carried over), 1 chunk;
      3. metadata without a new object list: both objects "same index as
         before" (0x00000000), `load` gains unit kN; raw data of 1.5 chunks
         and next-segment offset 0xFFFF_FFFF_FFFF_FFFF, as a writer that
         crashed leaves it: the reader keeps the one complete chunk.
    disp[k] = 3k - 7, load[k] = k / 4 for k = 0..11."""
    META, NEWLIST, RAW, INTER, BIG = 1 << 1, 1 << 2, 1 << 3, 1 << 5, 1 << 6

    def s(text):
        b = text.encode("utf-8")
        return struct.pack(">I", len(b)) + b

    def rows(first, count):
        out = b""
        for k in range(first, first + count):
            out += struct.pack(">hf", 3 * k - 7, k / 4.0)
        return out

    def segment(toc, meta, raw, crashed=False):
        nxt = 0xFFFFFFFFFFFFFFFF if crashed else len(meta) + len(raw)
        lead = b"TDSm" + struct.pack("<I", toc) + struct.pack(">IQQ", 4713, nxt, len(meta))
        return lead + meta + raw

    disp, load = "/'rig'/'disp ''mm'''", "/'rig'/'load'"
    meta1 = struct.pack(">I", 4)
    meta1 += s("/") + struct.pack(">I", 0xFFFFFFFF) + struct.pack(">I", 0)
    meta1 += s("/'rig'") + struct.pack(">I", 0xFFFFFFFF) + struct.pack(">I", 0)
    meta1 += s(disp) + struct.pack(">IIIQ", 20, 2, 1, 3)
    meta1 += struct.pack(">I", 1) + s("unit_string") + struct.pack(">I", 0x20) + s("mm")
    meta1 += s(load) + struct.pack(">IIIQ", 20, 9, 1, 3)
    meta1 += struct.pack(">I", 1) + s("NI_ChannelLength") + struct.pack(">IQ", 8, 12)
    meta3 = struct.pack(">I", 2)
    meta3 += s(disp) + struct.pack(">II", 0, 0)
    meta3 += s(load) + struct.pack(">I", 0) + struct.pack(">I", 1)
    meta3 += s("unit_string") + struct.pack(">I", 0x20) + s("kN")
    data = segment(META | NEWLIST | RAW | INTER | BIG, meta1, rows(0, 6))
    data += segment(RAW | INTER | BIG, b"", rows(6, 3))
    partial = rows(9, 3) + rows(12, 1)[:3]
    data += segment(META | RAW | INTER | BIG, meta3, partial, crashed=True)
    with open(os.path.join(HERE, "tdms_interleaved_be.tdms"), "wb") as f:
        f.write(data)


if __name__ == "__main__":
    tensile_two_segments()
    mixed_types()
    interleaved_big_endian()
