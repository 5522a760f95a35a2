"""The public API as a user calls it, for ``mypy --strict`` (test_typing.py):
every call here must type-check against the package's stubs. Nothing here
runs at import."""

from __future__ import annotations

import pathlib
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares  # type: ignore[import-untyped]

import rigfit
from rigfit import identify


def campaign_from_files(root: pathlib.Path) -> rigfit.Campaign:
    c = rigfit.Campaign.from_json(root / "campaigns" / "bearing_2dof_synthetic.json")
    same = rigfit.Campaign.from_dict(c.to_dict(), base_dir=root / "campaigns", origin="copy")
    names: list[str] = same.genes + c.experiments
    bounds: NDArray[np.float64] = c.bounds
    lo: float = float(bounds[0, 0])
    info: dict[str, Any] = c.experiment_info(c.experiments[0])
    outputs: list[tuple[str, str]] = c.outputs
    k = c.params["k_x"]
    low: float | None = k.min
    value: float = k.value * 2.0
    free: dict[str, float] = c.params.valuesdict()
    rigs: dict[str, dict[str, Any]] = rigfit.shipped_rigs()
    print(names, lo, info, outputs, low, value, free, len(rigs), c.substeps, c.search_method)
    return c


def records_from_memory(c: rigfit.Campaign) -> None:
    t = np.linspace(0.0, 0.1, 501)
    c.set_data(c.experiments[0], {"t_s": t, "x_m": np.sin(t)}, time_column="t_s", column="x_m")
    c.set_data(c.experiments[0], {"t_ms": t * 1e3, "x_mm": np.sin(t)}, time_column="t_ms",
               column="x_mm", time_scale=1e-3, scale=1e-3)


def edits_and_synthetic_records(c: rigfit.Campaign) -> None:
    p = c.params
    p["k_x"].min = 1e6
    p["k_x"].set(value=1.5e6, vary=True)
    c.set_params(k_y={"min": 1e6, "max": 5e6}, c_y=20.0)
    c.set_params(p)
    pending = rigfit.Campaign.from_dict(c.to_dict(), base_dir=".", pending=True)
    waiting: list[str] = pending.pending
    frame = rigfit.simulate(pending, dict(zip(c.genes, c.bounds.mean(axis=1).tolist())),
                            dt=1e-4, samples=500, noise=0.01, seed=1)
    print(waiting, frame)


def fit_and_read(c: rigfit.Campaign, folder: pathlib.Path) -> float:
    def on_generation(p: dict[str, Any]) -> None:
        print(p["stage"])

    result: rigfit.FitResult = rigfit.fit(
        c, seed=3, backend="cpu", population=48, generations=6, threads=2, out=folder,
        overwrite=True, max_memory="2G", progress=on_generation)
    x: NDArray[np.float64] = result.x
    cov = result.covariance
    if cov is not None:
        print(np.sqrt(np.diag(cov)))
    stats: tuple[float, float, float, float] = (result.chisqr, result.redchi, result.aic,
                                                result.bic)
    counts: tuple[int, int, int] = (result.nfev, result.ndata, result.nvarys)
    ok: bool = result.success
    why: str = result.message
    for name, p in result.params.items():
        if p.stderr is not None and p.interval95 is not None:
            print(name, p.value, p.stderr, p.interval95[0])
    for name, e in result.experiments.items():
        r2: float = e.r2
        window: NDArray[np.float64] = e.residual[e.in_fit_window]
        print(name, r2, window.size)
    report: str = result.fit_report()
    saved: str = result.save(folder / "copy", overwrite=False)
    back = rigfit.load_result(saved)
    print(x, stats, counts, ok, why, report, back == result)
    return result.fitness


def ensemble(c: rigfit.Campaign) -> NDArray[np.float64]:
    theta = c.bounds.mean(axis=1)
    histories: NDArray[np.float64] = rigfit.simulate(c, theta[None, :], backend="cpu")
    also = c.simulate(theta[None, :], threads=1)
    cost = c.objective(vectorized=False)(theta)
    r: NDArray[np.float64] = c.residuals(theta)
    rows = c.residuals(np.vstack([theta, theta]), backend="cpu", threads=1)
    by_name = c.residuals(dict(zip(c.genes, theta.tolist())))
    sol = least_squares(c.residuals, theta, bounds=tuple(c.bounds.T))
    print(histories.shape, also.shape, cost, rows.shape, by_name.shape, sol)
    return r


def sweeps_and_identification(t: NDArray[np.float64], f: NDArray[np.float64]) -> None:
    table = rigfit.sweep({"campaign": "c.json", "design": {}}, threads=1)
    ring: identify.Report = rigfit.ringdown(t, f, m1=1.2)
    fragment = ring.fragment
    spectra = rigfit.frf(t, f, f, response="acceleration", modes=1).spectra
    print(table, fragment, spectra)
    try:
        rigfit.Campaign.from_json("missing.json")
    except rigfit.CampaignError as e:
        print(e)
    except rigfit.Interrupted as stop:
        checkpoint: str | None = stop.checkpoint
        print(checkpoint)
