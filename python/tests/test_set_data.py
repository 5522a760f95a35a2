"""A record set from a DataFrame (or a dict of arrays) without a CSV on disk
equals its CSV-fed twin."""

import json

import numpy as np
import pandas as pd
import pytest

import rigfit
from conftest import CAMPAIGNS


def test_dataframe_fed_experiment_equals_its_csv_fed_twin(bearing):
    twin = rigfit.Campaign.from_json(bearing)
    c = rigfit.Campaign.from_json(bearing)
    raw = json.loads(bearing.read_text())
    for x in raw["experiments"]:
        # numpy parses each number to the nearest double, as rigfit does.
        text = (bearing.parent / x["data"]["file"]).read_text().splitlines()
        rows = [r for r in text if r and not r.startswith("#")]
        frame = pd.DataFrame(np.loadtxt(rows[1:], delimiter=",", ndmin=2), columns=rows[0].split(","))
        c.set_data(x["name"], frame)
    assert all(x["data"]["file"].startswith("<memory:") for x in c.to_dict()["experiments"])
    theta = (twin.bounds[:, 0] + twin.bounds[:, 1])[None, :] / 2
    assert np.array_equal(rigfit.simulate(c, theta), rigfit.simulate(twin, theta))
    a = rigfit.fit(c, backend="cpu", seed=5)
    b = rigfit.fit(twin, backend="cpu", seed=5)
    assert json.loads(a.files["result.json"])["params"] == json.loads(b.files["result.json"])["params"]
    assert a.files["hx.csv"] == b.files["hx.csv"] and a.files["hy.csv"] == b.files["hy.csv"]
    # result.json names each record set from memory, with what was read.
    summary = json.loads(a.files["result.json"])
    inputs = {i["path"]: i["sha256"] for i in summary["inputs"]}
    assert sorted(r["path"] for r in summary["records"]) == ["<memory:hx>.csv", "<memory:hy>.csv"]
    for r in summary["records"]:
        assert r["format"] == "memory" and inputs[r["path"]] == r["sha256"], r


def test_column_names_no_csv_header_could_hold():
    path = CAMPAIGNS / "bearing_2dof_synthetic.json"
    c = rigfit.Campaign.from_json(path)
    t = np.arange(500) * 2.56e-4
    y = np.sin(2 * np.pi * 50 * t)
    name = 'x, "hx" [m]'
    c.set_data("hx", {"time; s": t, name: y}, time_column="time; s", column=name)
    assert c.experiment_info("hx")["samples"] == 500
    # The unit in its brackets is checked as a CSV header's is.
    with pytest.raises(rigfit.CampaignError, match=r"scale"):
        c.set_data("hx", {"t_s": t, "x [mV]": y}, time_column="t_s", column="x [mV]")


def test_dict_of_arrays_and_a_bad_column_name():
    path = CAMPAIGNS / "bearing_2dof_synthetic.json"
    c = rigfit.Campaign.from_json(path)
    t = np.arange(500) * 2.56e-4
    y = np.sin(2 * np.pi * 50 * t)
    c.set_data("hx", {"t_s": t, "force_N": y})
    assert c.experiment_info("hx")["samples"] > 0
    with pytest.raises(rigfit.DataError, match=r"<memory:hy>\.csv.*force_N"):
        c.set_data("hy", {"t_s": t, "x": y})
    with pytest.raises(rigfit.DataError, match="no experiment 'nope'"):
        c.set_data("nope", {"t_s": t, "force_N": y})


class _FrameWithToPandas:
    """A polars- or pyarrow-like frame: only `to_pandas()`."""

    def __init__(self, df):
        self._df = df

    def to_pandas(self):
        return self._df


def test_a_frame_with_to_pandas_is_read_through_it():
    path = CAMPAIGNS / "bearing_2dof_synthetic.json"
    a, b = rigfit.Campaign.from_json(path), rigfit.Campaign.from_json(path)
    t = np.arange(500) * 2.56e-4
    df = pd.DataFrame({"t_s": t, "force_N": np.cos(2 * np.pi * 40 * t)})
    a.set_data("hx", df)
    b.set_data("hx", _FrameWithToPandas(df))
    theta = a.bounds.mean(axis=1)[None, :]
    assert np.array_equal(rigfit.simulate(a, theta), rigfit.simulate(b, theta))
    assert a.objective()(theta.T) == b.objective()(theta.T)
