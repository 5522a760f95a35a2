"""rigfit.sweep: the table `rigfit sweep` writes, as a DataFrame, from a
sweep file or a dict; its refusals with the CLI's message."""

import json
import math
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pandas as pd
import pytest

import rigfit
from conftest import cli_binary

# A one-mass rig (spring and damper to ground) under a unit force step from
# t = 0, as tests/sweep_metrics_closed_form.rs sweeps it, on a shorter
# placeholder record (0.4 s at 0.1 ms, never scored).
RIG = {
    "id": "sdof_step",
    "doc": "One mass on a spring and a viscous damper, a unit force step from t = 0.",
    "params": [
        {"name": "m", "unit": "kg", "doc": "mass"},
        {"name": "k", "unit": "N/m", "doc": "stiffness"},
        {"name": "c", "unit": "N·s/m", "doc": "damping"},
    ],
    "nodes": [{"name": "mass", "mass": "m"}],
    "elements": [{"name": "support", "between": ["ground", "mass"],
                  "spring": {"law": "linear", "k": "k"},
                  "damper": {"law": "viscous", "c": "c"}}],
    "drives": [{"node": "mass",
                "law": {"type": "force_table", "t": [0.0, 10.0], "value": [1.0, 1.0]}}],
    "outputs": [{"name": "x", "unit": "m", "sum": [{"displacement": "mass"}]}],
    "reach": {"elongation": 0.01, "rate": 1.0},
}

ZETA, WD = 0.2, 20 * math.pi
WN = WD / math.sqrt(1 - ZETA ** 2)
K, C = WN * WN, 2 * ZETA * WN

METRICS = [
    {"name": "os", "metric": "overshoot", "output": "x"},
    {"name": "pk", "metric": "peak", "output": "x"},
    {"name": "x1", "metric": "first_crossing", "output": "x", "threshold": 1.0 / K},
    {"name": "late", "metric": "first_crossing", "output": "x", "threshold": 1.0},  # never: NaN
    {"name": "hz", "metric": "ringing_hz", "output": "x", "window_s": 0.1},
]


@pytest.fixture
def sdof(tmp_path):
    """The rig, its record and campaign in tmp_path; returns the folder."""
    (tmp_path / "rig.json").write_text(json.dumps(RIG))
    rows = "".join(f"{i * 1e-4:e},0\n" for i in range(4001))
    (tmp_path / "rec.csv").write_text("t_s,x_m\n" + rows)
    campaign = {"name": "sdof-step", "rig": "rig.json", "params": {"m": 1.0, "k": K, "c": C},
                "experiments": [{"name": "step", "drive": "velocity",
                                 "data": {"file": "rec.csv", "time_column": "t_s",
                                          "force_column": "x_m"}}]}
    (tmp_path / "c.json").write_text(json.dumps(campaign))
    return tmp_path


def _grid(**extra):
    raw = {"campaign": "c.json",
           "variables": {"m": {"values": [1.0, 1.5, 2.0]}, "c": {"linear": [C, 2 * C, 2]}},
           "metrics": METRICS}
    raw.update(extra)
    return raw


def _write(folder, raw, name="s.json"):
    path = folder / name
    path.write_text(json.dumps(raw))
    return path


def _cli_tables(path, tmp_path, *extra):
    """The CSV(s) `rigfit sweep` writes for `path`, as DataFrames, or None
    where the binary is not there (the caller compares with a second call
    then)."""
    try:
        binary = cli_binary()
    except AssertionError:
        return None
    out = tmp_path / "cli.csv"
    args = [binary, "--quiet", "sweep", str(path), "--out", str(out), "--overwrite", *extra]
    r = subprocess.run(args, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return _read_csv(out)


def _read_csv(path):
    """A CSV the CLI wrote, each value read with float() (exactly: the CLI
    writes the shortest form that reads back to the same number), an empty
    cell as NaN."""
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    rows = [[_cell(c) for c in line.split(",")] for line in lines[1:]]
    return pd.DataFrame(rows, columns=header)


def _cell(text):
    if text == "":
        return float("nan")
    try:
        return float(text)
    except ValueError:
        return text  # a metric's or a variable's name


def _same(a, b):
    assert list(a.columns) == list(b.columns)
    assert len(a) == len(b)
    for col in a.columns:
        x = a[col].to_numpy(dtype=float)
        y = b[col].to_numpy(dtype=float)
        # Bit for bit, NaN where the other is NaN.
        assert np.array_equal(x, y, equal_nan=True), (col, x, y)


def test_the_table_is_the_cli_csv(sdof, tmp_path):
    path = _write(sdof, _grid())
    df = rigfit.sweep(path)
    assert list(df.columns) == ["point", "m", "c", "os", "pk", "x1", "late", "hz"]
    assert len(df) == 6
    assert df["point"].dtype == np.int64
    assert df["point"].tolist() == list(range(6))
    # Row-major: the first variable slowest.
    assert df["m"].tolist() == [1.0, 1.0, 1.5, 1.5, 2.0, 2.0]
    assert df["c"].tolist() == [C, 2 * C] * 3
    assert df["late"].isna().all()
    assert np.isfinite(df[["os", "pk", "x1", "hz"]].to_numpy()).all()
    # The first point's peak (m = 1 kg, the closed-form oscillator's values)
    # falls on a sample: (1 + overshoot)/k with the overshoot exp(−ζπ/√(1−ζ²)).
    os1 = math.exp(-ZETA * math.pi / math.sqrt(1 - ZETA ** 2))
    assert df["pk"][0] == pytest.approx((1 + os1) / K, rel=1e-6)
    for key in ("wall_s", "runs_per_s", "runs", "device", "substeps"):
        assert key in df.attrs
    assert df.attrs["runs"] == 6 and df.attrs["runs_per_s"] > 0
    assert "indices" not in df.attrs
    cli = _cli_tables(path, tmp_path)
    if cli is None:
        cli = rigfit.sweep(path)
    _same(df, cli)


def test_a_dict_is_the_file_its_paths_relative_to_the_cwd(sdof, tmp_path, monkeypatch):
    raw = _grid(substeps=4)
    from_file = rigfit.sweep(_write(sdof, raw))
    monkeypatch.chdir(sdof)
    from_dict = rigfit.sweep(raw, threads=np.int64(1))
    _same(from_file, from_dict)
    assert from_file.attrs["substeps"] == [4]


def test_progress_true_without_tqdm_prints_a_plain_line(sdof, monkeypatch, capsys):
    for name in ("tqdm", "tqdm.auto"):
        monkeypatch.setitem(sys.modules, name, None)  # import fails
    df = rigfit.sweep(_write(sdof, _grid(substeps=4)), threads=1, progress=True)
    err = capsys.readouterr().err
    assert f"sweep: {len(df)}/{len(df)} point" in err, err


def test_sobol_indices_are_the_cli_indices(sdof, tmp_path):
    raw = {"campaign": "c.json", "substeps": 4,
           "variables": {"m": {"uniform": [1.0, 2.0]}, "c": {"uniform": [C, 2 * C]}},
           "sampling": {"method": "sobol", "points": 16, "seed": 3, "indices": True},
           "metrics": METRICS[:3]}
    path = _write(sdof, raw)
    calls = []
    df = rigfit.sweep(path, threads=1, progress=calls.append)
    assert len(df) == 16 * (2 + 2)
    assert calls and calls[-1]["done"] == calls[-1]["total"] == len(df)
    ix = df.attrs["indices"]
    assert list(ix.columns) == ["metric", "variable", "first", "first_lo", "first_hi",
                                "total", "total_lo", "total_hi"]
    assert ix[["metric", "variable"]].values.tolist() == [
        [m, v] for m in ("os", "pk", "x1") for v in ("m", "c")]
    try:
        binary = cli_binary()
    except AssertionError:
        binary = None
    if binary is not None:
        out, ixf = tmp_path / "cli.csv", tmp_path / "ix.csv"
        r = subprocess.run([binary, "--quiet", "sweep", str(path), "--out", str(out),
                            "--indices", str(ixf)], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        _same(df, _read_csv(out))
        cli_ix = _read_csv(ixf)
        assert cli_ix[["metric", "variable"]].values.tolist() == \
            ix[["metric", "variable"]].values.tolist()
        _same(ix.drop(columns=["metric", "variable"]),
              cli_ix.drop(columns=["metric", "variable"]))


def test_a_refused_sweep_names_the_file_and_the_json_path(sdof, monkeypatch):
    bad = _grid(variables={"zz": {"values": [1.0]}})
    path = _write(sdof, bad)
    with pytest.raises(rigfit.CampaignError, match="variables.zz") as e:
        rigfit.sweep(path)
    assert str(path) in str(e.value)
    assert isinstance(e.value, ValueError)
    monkeypatch.chdir(sdof)
    unknown_output = _grid(metrics=[{"name": "p", "metric": "peak", "output": "nope"}])
    with pytest.raises(rigfit.CampaignError, match=r"metrics\[0\]\.output") as e:
        rigfit.sweep(unknown_output)
    assert os.path.join(os.getcwd(), "<sweep dict>") in str(e.value)
    with pytest.raises(rigfit.CampaignError, match="cannot read"):
        rigfit.sweep(sdof / "missing.json")
    with pytest.raises(rigfit.CampaignError, match="unknown field"):
        rigfit.sweep(_grid(colour="red"))


def test_arguments_are_checked_before_any_run(sdof):
    path = _write(sdof, _grid())
    with pytest.raises(TypeError, match="path of a sweep file"):
        rigfit.sweep(42)
    with pytest.raises(TypeError, match="path of a sweep file"):
        rigfit.sweep([path])
    with pytest.raises(TypeError, match="threads"):
        rigfit.sweep(path, threads="2")
    with pytest.raises(TypeError, match="threads"):
        rigfit.sweep(path, threads=True)
    with pytest.raises(ValueError, match="threads=-1"):
        rigfit.sweep(path, threads=-1)
    with pytest.raises(ValueError, match="'cpu', 'gpu'"):
        rigfit.sweep(path, backend="tpu")
    with pytest.raises(ValueError, match="'auto', 'f32', 'f64'"):
        rigfit.sweep(path, backend="gpu", precision="f16")
    with pytest.raises(ValueError, match="backend=\"gpu\""):
        rigfit.sweep(path, precision="f32")
    with pytest.raises(ValueError, match="backend=\"gpu\""):
        rigfit.sweep(path, adapter="0")


INTERRUPT = """
import signal, sys, rigfit
# As in a terminal or Jupyter, even where the test runner was started with
# SIGINT ignored (a background job of a non-interactive shell).
signal.signal(signal.SIGINT, signal.default_int_handler)
def progress(p):
    if p["done"] == 0:
        print("started", flush=True)
try:
    rigfit.sweep(sys.argv[1], progress=progress)
except KeyboardInterrupt:
    print("interrupted", flush=True)
    sys.exit(130)
print("finished", flush=True)
"""


def test_ctrl_c_stops_the_sweep_at_once(sdof):
    # 50 000 points, each choosing its own step: far longer than the test.
    path = _write(sdof, _grid(variables={"m": {"linear": [1.0, 2.0, 250]},
                                         "c": {"linear": [C, 2 * C, 200]}}))
    p = subprocess.Popen([sys.executable, "-c", INTERRUPT, str(path)],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = p.stdout.readline()
    assert line.startswith("started"), (line, p.stderr.read())
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    rest, err = p.communicate(timeout=30)
    took = time.monotonic() - sent
    assert p.returncode == 130, (rest, err)
    assert rest.startswith("interrupted"), rest
    assert took < 2.0, f"took {took:.2f} s to stop"


def test_the_gpu_agrees_with_the_cpu_lanes(sdof):
    # As tests/test_gpu.py: lavapipe in CI; f64 where the adapter has it.
    path = _write(sdof, _grid(substeps=4))
    cpu = rigfit.sweep(path)
    gpu = rigfit.sweep(path, backend="gpu", precision="auto")
    assert list(gpu.columns) == list(cpu.columns)
    assert gpu["point"].tolist() == cpu["point"].tolist()
    np.testing.assert_allclose(gpu.to_numpy(dtype=float), cpu.to_numpy(dtype=float),
                               rtol=1e-3, equal_nan=True)
    with pytest.raises(rigfit.DeviceError, match='adapter="no such adapter"'):
        rigfit.sweep(path, backend="gpu", adapter="no such adapter")
