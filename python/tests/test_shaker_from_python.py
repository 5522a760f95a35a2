"""The must-show of issue 60: a two-channel shaker campaign made and fitted
from Python alone. The rig is written inline as a dict: a table driven by a
measured acceleration (the record's drive column), a fixture on a force gauge
(the load cell, N), a specimen on a cubic-stiffening mount, and an
accelerometer on the specimen (absolute frame) whose sensitivity is a free
parameter (V per m/s²). The campaign is built with no file on disk, its
record made by ``rigfit.simulate`` at a known truth with noise on both
channels, set with ``set_data`` and fitted: every free parameter's 95 %
interval holds the truth and each channel's residual is at its noise."""

import time

import numpy as np
import pytest

import rigfit

RIG = {
    "id": "shaker_specimen",
    "doc": "A shaker table driven by a measured acceleration; a fixture on a force gauge, a "
           "specimen on a cubic-stiffening mount on the fixture, an accelerometer on the "
           "specimen.",
    "params": [
        {"name": "m_f", "unit": "kg", "doc": "fixture mass", "scale": "log"},
        {"name": "k_g", "unit": "N/m", "doc": "force gauge stiffness", "scale": "log"},
        {"name": "c_g", "unit": "N·s/m", "doc": "force gauge damping", "default": 0.0},
        {"name": "m_s", "unit": "kg", "doc": "specimen mass", "scale": "log"},
        {"name": "k", "unit": "N/m", "doc": "mount linear stiffness", "scale": "log"},
        {"name": "k3", "unit": "N/m^3", "doc": "mount cubic stiffness", "default": 0.0},
        {"name": "c", "unit": "N·s/m", "doc": "mount damping", "default": 0.0},
        {"name": "sens", "unit": "V/(m/s²)", "doc": "accelerometer sensitivity",
         "scale": "log"},
    ],
    "nodes": [{"name": "fixture", "mass": "m_f"}, {"name": "specimen", "mass": "m_s"}],
    "elements": [
        {"name": "gauge", "between": ["fixture", "ground"],
         "spring": {"law": "linear", "k": "k_g"}, "damper": {"law": "viscous", "c": "c_g"}},
        {"name": "mount", "between": ["specimen", "fixture"],
         "spring": {"law": "polynomial", "coeffs": [0.0, "k", 0.0, "k3"]},
         "damper": {"law": "viscous", "c": "c"}},
    ],
    "drives": [{"mode": "force", "law": {"type": "base_acceleration_table"}}],
    "outputs": [
        {"name": "F_gauge", "unit": "N", "sum": [{"force": "gauge"}]},
        {"name": "acc", "unit": "V",
         "sum": [{"acceleration": "specimen", "frame": "absolute", "gain": "sens"}]},
    ],
    "reach": {"elongation": 0.02, "rate": 5.0},
}

TRUTH = {"k": 2.0e4, "k3": 2.0e8, "c": 6.0, "sens": 0.01}
NOISE = {"F_gauge": 0.2, "acc": 0.004}


def campaign_dict():
    return {
        "name": "shaker-from-python",
        "rig": RIG,
        "params": {
            "m_f": 1.0, "k_g": 1.0e7, "c_g": 20.0, "m_s": 0.5,
            "k": {"min": 5.0e3, "max": 8.0e4, "scale": "log"},
            "k3": {"min": 0.0, "max": 1.0e9},
            "c": {"min": 0.5, "max": 50.0, "scale": "log"},
            "sens": {"min": 0.002, "max": 0.05, "scale": "log"},
        },
        "experiments": [{
            "name": "chirp",
            "data": {"file": "chirp.csv", "time_column": "t_s"},
            "drive": {"force": {"column": "a_table"}},
            "channels": [{"output": "F_gauge", "column": "F_N"},
                         {"output": "acc", "column": "acc_V"}],
        }],
        "search": {"population": 48, "generations": 30, "seed": 3},
    }


def table_acceleration(t):
    """The measured table acceleration (m/s²): a sweep from 5 to 80 Hz."""
    return 20.0 * np.sin(2 * np.pi * (5.0 * t + 75.0 * t ** 2))


def test_a_shaker_campaign_made_and_fitted_from_python_alone_recovers_its_truth(tmp_path):
    started = time.perf_counter()
    campaign = rigfit.Campaign.from_dict(campaign_dict(), base_dir=tmp_path, pending=True)
    assert list(tmp_path.iterdir()) == []
    assert campaign.pending == ["chirp"]
    with pytest.raises(rigfit.CampaignError, match="experiment 'chirp' has no record yet"):
        rigfit.fit(campaign, backend="cpu")

    assert sorted(campaign.genes) == sorted(TRUTH)
    t = np.arange(2500) * 2.0e-4
    record = rigfit.simulate(campaign, TRUTH, t=t, drive=table_acceleration(t), noise=NOISE,
                             seed=11)
    assert list(record.columns) == ["t_s", "F_N", "acc_V", "a_table"]
    campaign.set_data("chirp", record)
    assert campaign.pending == []
    assert list(tmp_path.iterdir()) == []

    result = rigfit.fit(campaign, backend="cpu")
    for name, value in TRUTH.items():
        lo, hi = result.params[name].interval95
        assert lo <= value <= hi, f"{name}: {value} outside [{lo}, {hi}]"
    for output, sigma in NOISE.items():
        rms = result.experiments[f"chirp.{output}"].residual_rms
        assert abs(rms / sigma - 1.0) < 0.2, f"{output}: residual RMS {rms} against σ {sigma}"
    assert list(tmp_path.iterdir()) == []
    assert time.perf_counter() - started < 120
