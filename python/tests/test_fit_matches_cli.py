"""rigfit.fit runs the job `rigfit run` runs: for the same campaign, seed and
backend, every parameter in result.json is the same, bit for bit."""

import json
import pickle

import numpy as np

import rigfit


def _parameters(summary):
    keep = ("name", "value", "bounds", "std_error", "interval_95", "determined", "at_bound",
            "elite_range")
    return [{k: p.get(k) for k in keep} for p in summary["parameters"]]


def test_python_and_cli_give_the_same_result_json_bit_for_bit(bearing, cli, tmp_path):
    cli("run", bearing, "--backend", "cpu", "--seed", "11", "--out", tmp_path / "cli")
    cli_json = json.loads((tmp_path / "cli" / "result.json").read_text())

    c = rigfit.Campaign.from_json(bearing)
    r = rigfit.fit(c, seed=11, backend="cpu")
    py_json = json.loads(r.files["result.json"])

    assert py_json["params"] == cli_json["params"]          # floats parsed exactly
    assert _parameters(py_json) == _parameters(cli_json)
    assert py_json["fitness"] == cli_json["fitness"]
    assert py_json["polish"]["correlation"] == cli_json["polish"]["correlation"]
    assert [x["r2"] for x in py_json["experiments"]] == [x["r2"] for x in cli_json["experiments"]]
    # The experiment CSVs hold the same numbers.
    for x in cli_json["experiments"]:
        assert r.files[x["csv"]] == (tmp_path / "cli" / x["csv"]).read_bytes()

    # The result object reads them.
    for p in cli_json["parameters"]:
        assert r.params[p["name"]].value == p["value"]
        if p.get("std_error") is not None:
            assert r.params[p["name"]].stderr == p["std_error"]
            assert r.params[p["name"]].interval95 == tuple(p["interval_95"])
    assert r.correlation.shape == (len(c.genes), len(c.genes))
    assert np.allclose(np.diag(r.correlation), 1.0)
    hx = r.experiments["hx"]
    assert hx.model.shape == (len(hx.t), len(c.outputs))
    scale = np.abs(hx.measured).max()
    assert np.allclose(hx.residual, hx.model[:, 0] - hx.measured, atol=1e-6 * scale, rtol=0)
    assert 0.0 < r.r2["hx"] <= 1.0


def test_result_saves_what_run_writes_loads_and_pickles(bearing, tmp_path):
    c = rigfit.Campaign.from_json(bearing)
    r = rigfit.fit(c, seed=2, backend="cpu")
    folder = r.save(tmp_path / "saved")
    names = sorted(p.name for p in (tmp_path / "saved").iterdir())
    manifest = json.loads((tmp_path / "saved" / "rigfit-files.json").read_text())
    listed = manifest["files"] if isinstance(manifest, dict) else manifest
    checkpoints = {"checkpoint.json", "profiles.checkpoint.json"}
    assert set(names) == (set(listed) - checkpoints) | {"rigfit-files.json"}
    import pytest
    with pytest.raises(FileExistsError):
        r.save(folder)
    r.save(folder, overwrite=True)
    assert "result.json" in names and "hx.csv" in names and "fit_hx.svg" in names
    again = rigfit.load_result(folder)
    assert again == r and again.params["k_x"].value == r.params["k_x"].value
    back = pickle.loads(pickle.dumps(r))
    assert back == r
    assert back.fit_report() == r.fit_report()
    assert "[[Variables]]" in r.fit_report() and "k_x" in r.fit_report()
    assert "<table>" in r._repr_html_()
    df = r.to_dataframe()
    assert set(df["experiment"]) == {"hx", "hy"}
    assert len(r.params_dataframe()) == len(r.params)


def test_progress_callback_sees_every_generation_and_the_polish(bearing):
    seen = []
    rigfit.fit(rigfit.Campaign.from_json(bearing), backend="cpu", progress=seen.append)
    gens = [p["generation"] for p in seen if p["stage"] == "ga"]
    assert gens == list(range(6))
    assert any(p["stage"] == "polish" for p in seen)


def test_tqdm_progress_bar_runs(bearing, capsys):
    r = rigfit.fit(rigfit.Campaign.from_json(bearing), backend="cpu", progress=True)
    assert r.summary["generations"] == 6


def test_a_search_setting_out_of_range_is_a_campaign_error(bearing):
    import pytest
    with pytest.raises(rigfit.CampaignError, match="population"):
        rigfit.fit(rigfit.Campaign.from_json(bearing), population=1, backend="cpu")
    with pytest.raises(rigfit.CampaignError, match="backend"):
        rigfit.fit(rigfit.Campaign.from_json(bearing), backend="tpu")


def test_the_gil_is_released_while_a_fit_runs(bearing):
    import threading
    import time
    c = rigfit.Campaign.from_json(bearing)
    done = threading.Event()
    ticks = 0

    def job():
        rigfit.fit(c, backend="cpu", population=128, generations=12)
        done.set()

    th = threading.Thread(target=job)
    th.start()
    while not done.is_set():
        ticks += 1          # Python bytecode running beside the fit
        time.sleep(0.001)
    th.join()
    assert ticks > 50, ticks


def test_backend_auto_takes_the_clis_measured_choice(bearing, cli, tmp_path, monkeypatch):
    # `auto` races the two paths once and caches the choice per machine and
    # job; both sides read the same cache, so they run on the same path.
    monkeypatch.setenv("RIGFIT_CACHE_DIR", str(tmp_path / "cache"))
    # A job this short would run on the CPU unmeasured: measure it anyway.
    monkeypatch.setenv("RIGFIT_AUTO_TRIAL", "always")
    cli("run", bearing, "--backend", "auto", "--seed", "4", "--out", tmp_path / "cli")
    cli_json = json.loads((tmp_path / "cli" / "result.json").read_text())
    r = rigfit.fit(rigfit.Campaign.from_json(bearing), seed=4, backend="auto")
    py_json = json.loads(r.files["result.json"])
    assert py_json["backend"] == cli_json["backend"]
    assert py_json["params"] == cli_json["params"]
    assert py_json.get("backend_trial", {}).get("chosen") == cli_json.get("backend_trial", {}).get("chosen")


def test_cmaes_from_python_is_the_cli_s_cmaes_and_reports_its_covariance(bearing, cli, tmp_path):
    cli("run", bearing, "--backend", "cpu", "--seed", "5", "--method", "cmaes",
        "--generations", "12", "--out", tmp_path / "cli")
    cli_json = json.loads((tmp_path / "cli" / "result.json").read_text())
    c = rigfit.Campaign.from_json(bearing)
    assert c.search_method == "ga"
    r = rigfit.fit(c, seed=5, backend="cpu", method="cmaes", generations=12)
    py_json = json.loads(r.files["result.json"])
    assert py_json["search_method"] == cli_json["search_method"] == "cmaes"
    assert py_json["params"] == cli_json["params"]
    assert py_json["search_summary"] == cli_json["search_summary"]
    corr = np.array(py_json["search_summary"]["correlation"])
    assert corr.shape == (len(c.genes), len(c.genes))
    assert np.allclose(np.diag(corr), 1.0)
    assert "search method      = cmaes" in r.fit_report()
    import pytest
    with pytest.raises(rigfit.CampaignError, match="unknown search method `de`"):
        rigfit.fit(c, seed=5, backend="cpu", method="de")
