"""Slips a Python user meets on their own: numpy values and paths in a
campaign dict, values JSON cannot hold, an unknown experiment, an unclosed
result.json, a damaged or hostile result folder. Each raises rigfit's own
one-line error naming where, never a bare TypeError, KeyError or
JSONDecodeError."""

import decimal
import gc
import json
import os
import pathlib
import shutil
import warnings

import numpy as np
import pytest

import rigfit

from conftest import CAMPAIGNS


def _bearing_raw():
    return json.loads((CAMPAIGNS / "bearing_2dof_synthetic.json").read_text())


def _from_dict(raw):
    return rigfit.Campaign.from_dict(raw, base_dir=CAMPAIGNS)


# -- 1. campaign dicts --------------------------------------------------------
def test_numpy_scalars_arrays_and_paths_are_plain_json():
    raw = _bearing_raw()
    want = _from_dict(raw).to_dict()
    free = next(k for k, v in raw["params"].items() if isinstance(v, dict))
    raw["params"][free]["min"] = np.float64(raw["params"][free]["min"])
    raw["params"][free]["max"] = np.array(raw["params"][free]["max"])  # 0-d
    fixed = next(k for k, v in raw["params"].items() if isinstance(v, (int, float)))
    raw["params"][fixed] = np.float64(raw["params"][fixed])
    raw["experiments"][0]["data"]["file"] = pathlib.Path(raw["experiments"][0]["data"]["file"])
    if "search" in raw and "seed" in raw["search"]:
        raw["search"]["seed"] = np.int64(raw["search"]["seed"])
    c = _from_dict(raw)
    assert c.to_dict() == want


def test_numpy_bool_is_a_boolean():
    from rigfit.campaign import _plain_json
    out = _plain_json({"a": np.bool_(True), "b": [np.int64(3), np.array(2.5)],
                       "c": np.array([1, 2])}, "", "<dict>")
    assert out == {"a": True, "b": [3, 2.5], "c": [1, 2]}
    assert type(out["a"]) is bool and type(out["b"][0]) is int
    json.dumps(out)


@pytest.mark.parametrize("bad", [{1.0, 2.0}, b"1e6", decimal.Decimal("1e6"), object()],
                         ids=["set", "bytes", "decimal", "object"])
def test_values_json_cannot_hold_name_their_path(bad):
    raw = _bearing_raw()
    free = next(k for k, v in raw["params"].items() if isinstance(v, dict))
    raw["params"][free]["min"] = bad
    with pytest.raises(rigfit.CampaignError, match=rf"params\.{free}\.min: expected a JSON value"):
        _from_dict(raw)


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), np.float64("-inf"), np.array(np.nan)],
                         ids=["nan", "inf", "np-inf", "0d-nan"])
def test_non_finite_numbers_name_their_path(bad):
    raw = _bearing_raw()
    raw["experiments"][1].setdefault("params", {})["tau"] = bad
    with pytest.raises(rigfit.CampaignError,
                       match=r"experiments\[1\]\.params\.tau: .*not a finite number") as e:
        _from_dict(raw)
    assert "malformed JSON" not in str(e.value)


# -- 2. unknown experiments, channels ------------------------------------------
def test_unknown_experiment_lists_the_names():
    c = _from_dict(_bearing_raw())
    names = c.experiments
    with pytest.raises(rigfit.CampaignError, match="no experiment 'nope'") as e:
        c.experiment_info("nope")
    for n in names:
        assert repr(n) in str(e.value)
    with pytest.raises(rigfit.CampaignError, match=f"did you mean '{names[0]}'"):
        c.experiment_info(names[0] + "x")


def test_repr_counts_experiments_not_channels():
    c = rigfit.Campaign.from_json(CAMPAIGNS / "bearing_2dof_channels_synthetic.json")
    raw = json.loads((CAMPAIGNS / "bearing_2dof_channels_synthetic.json").read_text())
    n = len(raw["experiments"])
    assert len(c.experiments) > n  # one per channel
    assert f" {n} experiment(s) ({len(c.experiments)} channels)," in repr(c)


# -- 3, 4. result folders -------------------------------------------------------
@pytest.fixture(scope="module")
def result_folder(tmp_path_factory, cli):
    tmp = tmp_path_factory.mktemp("slips")
    raw = _bearing_raw()
    raw["search"] = {"population": 16, "generations": 2, "seed": 3}
    raw["solver"]["backend"] = "cpu"
    raw["output"] = "results"
    for x in raw["experiments"]:
        shutil.copy(CAMPAIGNS / x["data"]["file"], tmp / x["data"]["file"])
    path = tmp / "bearing.json"
    path.write_text(json.dumps(raw, indent=1))
    cli("run", path)
    return tmp / "results"


@pytest.fixture
def folder(result_folder, tmp_path):
    out = tmp_path / "r"
    shutil.copytree(result_folder, out)
    return out


def test_reading_a_result_leaves_no_file_open(result_folder):
    # A file left to the garbage collector warns as it is freed, where an
    # "error" filter cannot raise: the warnings are recorded instead.
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always", ResourceWarning)
        r = rigfit.load_result(result_folder)
        gc.collect()
    assert r.experiments
    assert not [w for w in seen if issubclass(w.category, ResourceWarning)], \
        [str(w.message) for w in seen]


def _summary(folder):
    return json.loads((folder / "result.json").read_text())


def _write(folder, summary):
    (folder / "result.json").write_text(json.dumps(summary))


def test_missing_result_json(folder):
    (folder / "result.json").unlink()
    with pytest.raises(rigfit.DataError, match="result.json"):
        rigfit.load_result(folder)


@pytest.mark.parametrize("text,why", [(b"{not json", "malformed JSON"), (b"\xff\xfe{}", "UTF-8"),
                                      (b"[1, 2]", "expected a JSON object"),
                                      (b'{"experiments": 3}', "experiments"),
                                      (b'{"experiments": [{"name": "hx"}]}', "csv"),
                                      (b'{"experiments": [7]}', r"experiments\[0\]")])
def test_damaged_result_json(folder, text, why):
    (folder / "result.json").write_bytes(text)
    with pytest.raises(rigfit.DataError, match=why) as e:
        rigfit.load_result(folder)
    assert "result.json" in str(e.value)


def test_result_json_without_needed_keys(folder):
    s = _summary(folder)
    del s["parameters"]
    _write(folder, s)
    with pytest.raises(rigfit.DataError, match="result.json: not a rigfit result"):
        rigfit.load_result(folder)


def test_missing_csv_is_named(folder):
    csv = _summary(folder)["experiments"][0]["csv"]
    (folder / csv).unlink()
    with pytest.raises(rigfit.DataError, match=f"{csv}: missing"):
        rigfit.load_result(folder)


@pytest.mark.parametrize("content", [b"\xff\xff\n", b"", b"t,t_model\n1,x\n", b"a,b,c\n1,2,3\n"],
                         ids=["binary", "empty", "text", "columns"])
def test_damaged_csv_is_named(folder, content):
    csv = _summary(folder)["experiments"][0]["csv"]
    (folder / csv).write_bytes(content)
    with pytest.raises(rigfit.DataError, match=csv):
        rigfit.load_result(folder)


def test_names_outside_the_folder_are_refused(folder, tmp_path):
    s = _summary(folder)
    csv = s["experiments"][0]["csv"]
    outside = tmp_path / "outside.csv"
    shutil.copy(folder / csv, outside)
    for name in ("../outside.csv", str(outside)):
        s["experiments"][0]["csv"] = name
        _write(folder, s)
        with pytest.raises(rigfit.DataError, match="outside the result folder"):
            rigfit.load_result(folder)
    # A link inside the folder that leads out of it.
    s["experiments"][0]["csv"] = "link.csv"
    _write(folder, s)
    os.symlink(outside, folder / "link.csv")
    with pytest.raises(rigfit.DataError, match="outside the result folder"):
        rigfit.load_result(folder)
