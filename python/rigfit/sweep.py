"""``rigfit.sweep``: the job ``rigfit sweep`` runs (the calibrated rig over a
design's points, every run reduced to named metrics), from Python, as pandas
DataFrames."""

import json
import numbers
import os
import time
import warnings

from . import _rigfit
from ._progress import progress_bar
from .errors import CampaignError

_BACKENDS = ("cpu", "gpu")
_PRECISIONS = ("auto", "f32", "f64")
_INDEX_COLUMNS = ["metric", "variable", "first", "first_lo", "first_hi",
                  "total", "total_lo", "total_hi"]


def sweep(sweep, *, threads=0, backend="cpu", precision=None, adapter=None, progress=False):
    """Runs a design sweep, as ``rigfit sweep`` does, and returns its table
    as a pandas DataFrame: one row per design point, the columns of the CSV
    ``rigfit sweep --out`` writes (``point``, each variable, each metric and,
    with the calibration's uncertainty, each metric's ``.median``, ``.lo``
    and ``.hi``), the same numbers (a test holds them to the CLI's CSV).
    ``point`` is an int column; a metric not defined at a point is NaN.

    ``sweep``: the path (``str`` or ``os.PathLike``) of a sweep file (see
    ``docs/guide/design.md``), or a dict holding the same JSON object, whose
    relative paths (``"campaign"``, ``"params"``) are relative to the
    current working directory. A sweep that rigfit refuses raises
    :class:`rigfit.CampaignError` (a ``ValueError``; a refused record:
    :class:`rigfit.DataError`) with the CLI's message: the file (for a
    dict, ``<cwd>/<sweep dict>``), the JSON path, what was expected and
    what was found.

    ``threads``: CPU threads (0: every core). ``backend``: ``"cpu"`` (the
    f64 lanes, the reference) or ``"gpu"`` (the GPU's history kernel, no
    adapter is a :class:`rigfit.DeviceError`); ``precision`` (``"auto"``,
    ``"f32"``, ``"f64"``) and ``adapter`` choose the GPU's and go only with
    ``backend="gpu"``. ``progress``: ``True`` for a ``tqdm.auto`` bar over
    the design points, or a callable given a dict per chunk of points
    (``done``, ``total``, ``elapsed_s``).

    The GIL is released while the sweep runs; Ctrl-C raises
    ``KeyboardInterrupt`` at once (the sweep's threads stop at the end of
    the chunk of points in flight).

    ``df.attrs``: ``wall_s``, ``runs_per_s``, ``runs``, ``device`` and
    ``substeps`` (the RK4 steps per sample the points took), as ``rigfit
    sweep --json`` reports them; for points drawn as Saltelli's design
    (``"sampling": {..., "indices": true}``), ``attrs["indices"]``: a
    DataFrame of the Sobol indices with columns ``metric``, ``variable``,
    ``first``, ``first_lo``, ``first_hi``, ``total``, ``total_lo``,
    ``total_hi`` (the CSV ``rigfit sweep --indices`` writes; NaN where a
    metric's indices are not defined).

    Example::

        import rigfit
        df = rigfit.sweep({
            "campaign": "campaigns/aa2024_t3_synthetic.json",
            "substeps": 2,
            "variables": {"c4": {"log": [1e3, 1e5, 9]}, "m1": {"values": [4.0, 6.0, 7.9]}},
            "metrics": [
                {"name": "ringing", "metric": "ringing", "output": "load_cell_force",
                 "against": "specimen_force"},
                {"name": "peak_N", "metric": "peak", "output": "load_cell_force"},
            ],
        })
        df.pivot(index="c4", columns="m1", values="ringing")
    """
    try:
        import pandas as pd
    except ImportError as e:  # pragma: no cover - pandas is in the test extras
        raise ImportError("rigfit.sweep returns pandas DataFrames: pip install pandas") from e
    path, text = _source(sweep)
    threads = _threads(threads)
    backend, precision, adapter = _device(backend, precision, adapter)
    callback, close = _progress(progress)
    try:
        out = _rigfit.sweep(path, text, threads=threads, backend=backend, precision=precision,
                            adapter=adapter, progress=callback)
    finally:
        close()
    for w in out["warnings"]:
        warnings.warn(f"rigfit: {w}", UserWarning, stacklevel=2)
    header = list(out["header"])
    df = pd.DataFrame(out["cells"], columns=header)
    df["point"] = df["point"].astype("int64")
    df.attrs["wall_s"] = out["wall_s"]
    df.attrs["runs_per_s"] = out["runs_per_s"]
    df.attrs["runs"] = out["runs"]
    df.attrs["device"] = out["device"]
    df.attrs["substeps"] = list(out["substeps"])
    if out["indices"] is not None:
        df.attrs["indices"] = _indices(pd, out["indices"])
    return df


def _source(sweep):
    """The path the library reads, and the JSON text of a dict (else None)."""
    if isinstance(sweep, dict):
        try:
            text = json.dumps(sweep, allow_nan=False)
        except (TypeError, ValueError) as e:
            raise TypeError(f"sweep: the dict is not JSON: {e}") from None
        return os.path.join(os.getcwd(), "<sweep dict>"), text
    if isinstance(sweep, (str, os.PathLike)):
        path = os.fspath(sweep)
        if isinstance(path, bytes):
            path = os.fsdecode(path)
        return path, None
    raise TypeError("sweep: expected the path of a sweep file (str or os.PathLike) or a dict "
                    f"of its JSON, found {type(sweep).__name__}")


def _threads(threads):
    if isinstance(threads, bool) or not isinstance(threads, numbers.Integral):
        raise TypeError(f"threads: expected an int (0: every core), found "
                        f"{type(threads).__name__}")
    if threads < 0:
        raise CampaignError(f"threads={int(threads)}: expected 0 (every core) or more")
    return int(threads)


def _device(backend, precision, adapter):
    if not isinstance(backend, str):
        raise TypeError(f"backend: expected one of {', '.join(map(repr, _BACKENDS))}, found "
                        f"{type(backend).__name__}")
    if backend not in _BACKENDS:
        raise CampaignError(f"backend={backend!r}: expected one of "
                            f"{', '.join(map(repr, _BACKENDS))}")
    if precision is not None:
        if not isinstance(precision, str):
            raise TypeError(f"precision: expected None or one of "
                            f"{', '.join(map(repr, _PRECISIONS))}, found {type(precision).__name__}")
        if precision not in _PRECISIONS:
            raise CampaignError(f"precision={precision!r}: expected None or one of "
                                f"{', '.join(map(repr, _PRECISIONS))}")
    if adapter is not None and not isinstance(adapter, (str, int)):
        raise TypeError(f"adapter: expected a str (a name's part or an index), found "
                        f"{type(adapter).__name__}")
    if adapter is not None:
        adapter = str(adapter)
    if backend != "gpu" and (precision is not None or adapter is not None):
        raise CampaignError("precision= and adapter= choose the GPU's; pass backend=\"gpu\" "
                            "with them")
    return backend, precision, adapter


def _indices(pd, ix):
    rows = []
    nan = float("nan")
    for metric, per_variable in ix["metrics"]:
        for i, variable in enumerate(ix["variables"]):
            if isinstance(per_variable, str):  # why the metric's indices are not defined
                rows.append([metric, variable] + [nan] * 6)
            else:
                rows.append([metric, variable] + list(per_variable[i]))
    return pd.DataFrame(rows, columns=_INDEX_COLUMNS)


def _progress(progress):
    """The callback the sweep calls with (done, total), and what closes it."""
    if not progress:
        return None, lambda: None
    start = time.monotonic()
    if callable(progress):
        def call(done, total):
            progress({"done": done, "total": total, "elapsed_s": time.monotonic() - start})
        return call, lambda: None
    tqdm = progress_bar()
    bars = []

    def update(done, total):
        if not bars:
            bars.append(tqdm(total=total, desc="sweep", unit="point"))
        bars[0].n = done
        bars[0].refresh()

    def close():
        for bar in bars:
            bar.close()
    return update, close
