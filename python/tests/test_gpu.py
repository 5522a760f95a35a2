"""The GPU path (lavapipe in CI, where RIGFIT_REQUIRE_GPU=1 makes a missing
adapter a failure): the ensemble on the GPU agrees with the CPU lanes, and a
selector that names no adapter is a DeviceError."""

import numpy as np
import pytest

import rigfit
from conftest import CAMPAIGNS


def test_gpu_ensemble_agrees_with_the_cpu_lanes():
    c = rigfit.Campaign.from_json(CAMPAIGNS / "bearing_2dof_synthetic.json")
    lo, hi = c.bounds[:, 0], c.bounds[:, 1]
    theta = lo + (hi - lo) * np.random.default_rng(0).random((64, len(c.genes)))
    gpu = rigfit.simulate(c, theta, backend="gpu")
    cpu = rigfit.simulate(c, theta, backend="cpu")
    assert gpu.shape == cpu.shape
    # f64 kernels where the adapter has them (lavapipe does), else f32.
    np.testing.assert_allclose(gpu, cpu, rtol=0, atol=1e-4 * np.abs(cpu).max())
    costs_gpu = c.objective(backend="gpu")(theta.T)
    costs_cpu = c.objective(backend="cpu")(theta.T)
    np.testing.assert_allclose(costs_gpu, costs_cpu, rtol=1e-3)


def test_an_adapter_that_is_not_there_is_a_device_error():
    c = rigfit.Campaign.from_json(CAMPAIGNS / "bearing_2dof_synthetic.json")
    with pytest.raises(rigfit.DeviceError, match='adapter="no such adapter"'):
        rigfit.simulate(c, c.bounds.mean(axis=1)[None, :], backend="gpu", adapter="no such adapter")
    assert issubclass(rigfit.DeviceError, RuntimeError)


def test_auto_with_a_named_adapter_runs_on_it_without_a_race(bearing, cli, tmp_path, monkeypatch):
    # As `rigfit run --backend auto --adapter 0`: asking for a device is
    # asking for the GPU, so nothing is measured or cached.
    monkeypatch.setenv("RIGFIT_CACHE_DIR", str(tmp_path / "cache"))
    cli("run", bearing, "--backend", "auto", "--adapter", "0", "--seed", "4",
        "--out", tmp_path / "cli")
    import json
    cli_json = json.loads((tmp_path / "cli" / "result.json").read_text())
    r = rigfit.fit(rigfit.Campaign.from_json(bearing), seed=4, backend="auto", adapter="0")
    assert r.backend == cli_json["backend"] == "gpu"
    assert "backend_trial" not in r.summary and "backend_trial" not in cli_json
    assert r.summary["params"] == cli_json["params"]
    assert not (tmp_path / "cache").exists()
