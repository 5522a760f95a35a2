"""Campaigns as objects: loaded and validated by the library (the same
checks and one-line errors as ``rigfit check``), with records set from numpy
or any DataFrame without a CSV on disk."""

import difflib
import json
import math
import os

import numpy as np

from . import _rigfit
from .errors import CampaignError, DataError
from .params import Parameter, Parameters


class Campaign:
    """A validated campaign: a rig, its parameters (fixed and free) and one
    or more experiments with their records.

    Build one with :meth:`from_json` (a campaign file) or :meth:`from_dict`
    (the same keys as a dict; a ``"rig"`` is a shipped rig's id, a rig file
    relative to ``base_dir`` or the rig itself inline).
    """

    def __init__(self, inner, base_dir, origin, records=None):
        self._inner = inner
        self._base_dir = os.fspath(base_dir)
        self._origin = origin
        # experiment name -> (lent path, CSV bytes)
        self._records = dict(records or {})
        self._info = json.loads(inner.info())

    # -- construction ---------------------------------------------------
    @classmethod
    def from_json(cls, path):
        """Reads and validates a campaign file (``rigfit check``'s checks);
        raises :class:`rigfit.CampaignError` or :class:`rigfit.DataError`
        naming the file and the JSON path."""
        path = os.fspath(path)
        inner = _rigfit.Campaign.load(path)
        return cls(inner, os.path.dirname(os.path.abspath(path)), path)

    @classmethod
    def from_dict(cls, campaign, base_dir=None, origin="<dict>"):
        """Validates a campaign given as a dict; relative paths (the rig
        file, the records) resolve against ``base_dir`` (default: the
        current folder); messages name ``origin`` as the file."""
        base_dir = os.path.abspath(os.fspath(base_dir) if base_dir is not None else os.getcwd())
        text = json.dumps(_plain_json(campaign, "", origin), allow_nan=False)
        inner = _rigfit.Campaign.from_text(text, base_dir, origin)
        return cls(inner, base_dir, origin)

    def to_dict(self):
        """The campaign's keys as validated (records set from memory show as
        ``"<memory:NAME>.csv"`` files)."""
        return json.loads(self._inner.raw_json)

    def copy(self):
        return Campaign(self._inner, self._base_dir, self._origin, self._records)

    # -- what it holds --------------------------------------------------
    @property
    def name(self):
        return self._info["name"]

    @property
    def rig(self):
        """The rig's id."""
        return self._info["rig"]

    @property
    def description(self):
        return self._info["description"]

    @property
    def path(self):
        """The campaign file (or the ``origin`` given to :meth:`from_dict`)."""
        return self._origin

    @property
    def experiments(self):
        """Experiment names, in the campaign's order."""
        return [x["name"] for x in self._info["experiments"]]

    @property
    def outputs(self):
        """The rig's outputs as (name, unit); output 0 is the measured one."""
        return [tuple(o) for o in self._info["outputs"]]

    @property
    def warnings(self):
        return list(self._info["warnings"])

    @property
    def substeps(self):
        """RK4 steps per sample interval the step rule chose."""
        return self._info["substeps"]

    @property
    def genes(self):
        """The free parameters' names in the search's order (the columns of
        ``theta`` and the rows of :attr:`bounds`)."""
        return [g["name"] for g in self._info["genes"]]

    @property
    def bounds(self):
        """The free parameters' bounds as a (P, 2) array, genes' order."""
        return np.array([[g["lower"], g["upper"]] for g in self._info["genes"]], dtype=float).reshape(-1, 2)

    @property
    def params(self):
        """Every parameter as lmfit-style :class:`Parameter` objects: the free
        ones (``vary=True``, with ``min``, ``max``, ``scale``, and ``value``
        their ``init`` or the middle of their range in their scale), then the
        fixed ones with the first experiment's value."""
        units = {p["name"]: p["unit"] for p in self._info["params"]}
        out = Parameters()
        for g in self._info["genes"]:
            lo, hi = g["lower"], g["upper"]
            if g["init"] is not None:
                value = g["init"]
            elif g["scale"] == "log" and lo > 0:
                value = float(np.sqrt(lo * hi))
            else:
                value = 0.5 * (lo + hi)
            out[g["name"]] = Parameter(g["name"], value=value, min=lo, max=hi, vary=True,
                                       scale=g["scale"], unit=g["unit"], experiment=g["experiment"],
                                       init=g["init"])
        names = [p["name"] for p in self._info["params"]]
        free_bare = {g["name"].split(".")[-1] for g in self._info["genes"]}
        for x in self._info["experiments"][:1]:
            for name, value in zip(names, x["values"]):
                if name not in out and name not in free_bare:
                    out[name] = Parameter(name, value=value, unit=units[name])
        return out

    def experiment_info(self, name):
        """Samples, sample interval (s), first time (s), fit window (sample
        indices), weight of experiment ``name``."""
        for x in self._info["experiments"]:
            if x["name"] == name:
                return {k: x[k] for k in ("samples", "dt", "t_first", "fit_window", "weight")}
        names = self.experiments
        close = difflib.get_close_matches(str(name), names, n=1)
        hint = f"; did you mean '{close[0]}'?" if close else ""
        raise CampaignError(
            f"{self._origin}: experiments: no experiment {str(name)!r}; the campaign has "
            f"{', '.join(repr(n) for n in names) or 'none'}{hint}")

    # -- records from memory ---------------------------------------------
    def set_data(self, name, frame, *, time_column=None, column=None):
        """Sets experiment ``name``'s record from ``frame``: a pandas (or
        polars, pyarrow, anything with the Arrow stream interface) DataFrame,
        or a dict of name → 1-D array. Its columns are read as the campaign's
        ``data`` object says (``time_column``, ``force_column``/``column``,
        the scales, a drive column), exactly as the same columns in a CSV
        file; ``time_column``/``column`` override the names. Nothing is
        written to disk. Raises :class:`rigfit.DataError` naming the
        experiment for a record rigfit refuses."""
        raw = self.to_dict()
        index = next((i for i, x in enumerate(raw["experiments"]) if x["name"] == name), None)
        if index is None:
            raise DataError(
                f"{self._origin}: experiments: no experiment '{name}'; the campaign has "
                f"{', '.join(self.experiments)}")
        names, columns = _columns_of(frame)
        data = raw["experiments"][index]["data"]
        fname = f"<memory:{name}>.csv"
        data["file"] = fname
        if time_column is not None:
            data["time_column"] = time_column
        if column is not None:
            data.pop("force_column", None)
            data["column"] = column
        records = dict(self._records)
        records[name] = (os.path.join(self._base_dir, fname), _rigfit.record_csv(names, columns))
        lent = [records[x["name"]] for x in raw["experiments"] if x["name"] in records]
        inner = _rigfit.Campaign.from_text(json.dumps(raw), self._base_dir, self._origin, lent)
        self._inner, self._records = inner, records
        self._info = json.loads(inner.info())

    # -- the ensemble as a function ---------------------------------------
    def objective(self, vectorized=True, *, backend="cpu", precision=None, adapter=None, threads=0):
        """The cost the search minimises (the weighted mean of 1 − R² over the
        experiments; 1e30 for a run that diverged) as a function of the free
        parameters in :attr:`genes` order.

        ``vectorized=True``: takes ``x`` of shape (P, S) and returns (S,)
        costs, as ``scipy.optimize.differential_evolution(...,
        vectorized=True)`` calls it (a (P,) vector gives a float); otherwise
        takes a (P,) vector and returns a float. All S sets run as one
        ensemble on the chosen backend.
        """
        from .ensemble import Objective
        return Objective(self, vectorized, backend=backend, precision=precision,
                         adapter=adapter, threads=threads)

    def simulate(self, theta, **kwargs):
        """:func:`rigfit.simulate` on this campaign."""
        from .ensemble import simulate
        return simulate(self, theta, **kwargs)

    # -- pickling ---------------------------------------------------------
    def __reduce__(self):
        return (_rebuild, (self._inner.raw_json, self._base_dir, self._origin, self._records))

    def __deepcopy__(self, memo):
        return self.copy()

    @property
    def search_method(self):
        """The campaign's search method, ``"ga"`` or ``"cmaes"`` (``search.method``;
        ``rigfit.fit(..., method=...)`` overrides it for one fit)."""
        return self._info["method"]

    def __repr__(self):
        # An experiment recorded on several channels shows in `experiments`
        # once per channel ("hx.x", "hx.y"); the campaign's experiments are
        # those of its JSON.
        try:
            raw = json.loads(self._inner.raw_json).get("experiments") or []
            count = len(raw) if isinstance(raw, list) else len(self.experiments)
        except (ValueError, AttributeError):
            count = len(self.experiments)
        channels = len(self.experiments)
        extra = f" ({channels} channels)" if channels != count else ""
        return (f"<rigfit.Campaign {self.name!r}: rig {self.rig}, {count} "
                f"experiment(s){extra}, {len(self.genes)} free parameter(s)>")


def shipped_rigs():
    """The shipped rigs, id → the rig description (a dict; ``"rig": id`` in a
    campaign uses one, ``"rig": {...}`` takes one inline, edited or not)."""
    return {rid: json.loads(text) for rid, text in _rigfit.shipped_rigs()}


def _plain_json(value, where, origin):
    """``value`` as plain JSON values: numpy scalars and arrays become
    numbers, booleans and lists, paths become strings. Anything else that is
    not JSON (a set, bytes, a Decimal, ...) and any NaN or infinity raise
    :class:`CampaignError` naming its JSON path."""
    def fail(what):
        raise CampaignError(f"{origin}: {where or '(top level)'}: {what}")

    if value is None or isinstance(value, (bool, np.bool_)):
        return None if value is None else bool(value)
    if isinstance(value, str):
        return str(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        v = float(value)
        if not math.isfinite(v):
            fail(f"expected a finite number, found {v!r} (not a finite number)")
        return v
    if isinstance(value, np.ndarray):
        if value.dtype.kind not in "biuf":
            fail(f"expected numbers, found a numpy array of dtype {value.dtype}")
        return _plain_json(value.tolist(), where, origin)
    if isinstance(value, os.PathLike):
        path = os.fspath(value)
        if not isinstance(path, str):
            fail(f"expected a JSON value, found a bytes path {path!r}")
        return path
    if isinstance(value, dict):
        out = {}
        for k, v in value.items():
            if not isinstance(k, str):
                fail(f"expected string keys, found the key {k!r} ({type(k).__name__})")
            out[str(k)] = _plain_json(v, f"{where}.{k}" if where else str(k), origin)
        return out
    if isinstance(value, (list, tuple)):
        return [_plain_json(v, f"{where}[{i}]", origin) for i, v in enumerate(value)]
    fail(f"expected a JSON value (number, string, boolean, null, list or dict), "
         f"found {type(value).__name__} {value!r:.60}")


def _rebuild(raw_json, base_dir, origin, records):
    lent = list(records.values())
    inner = _rigfit.Campaign.from_text(raw_json, base_dir, origin, lent)
    return Campaign(inner, base_dir, origin, records)


def _columns_of(frame):
    """Column names and float64 arrays of a dict, a pandas DataFrame, or any
    frame with ``to_pandas`` or the Arrow stream interface."""
    if isinstance(frame, dict):
        items = list(frame.items())
    else:
        is_pandas = type(frame).__module__.startswith("pandas")
        if not is_pandas and hasattr(frame, "to_pandas"):
            frame = frame.to_pandas()  # polars, pyarrow
        elif not hasattr(frame, "columns") and hasattr(frame, "__arrow_c_stream__"):
            import pyarrow
            frame = pyarrow.table(frame).to_pandas()
        if not hasattr(frame, "columns"):
            raise DataError(
                f"set_data: expected a DataFrame or a dict of columns, found {type(frame).__name__}")
        items = [(c, frame[c]) for c in frame.columns]
    names, columns = [], []
    for k, v in items:
        try:
            a = np.ascontiguousarray(np.asarray(v, dtype=np.float64))
        except (TypeError, ValueError) as e:
            raise DataError(f"set_data: column {k!r}: expected numbers, found {e}") from None
        if a.ndim != 1:
            raise DataError(f"set_data: column {k!r}: expected a 1-D column, found shape {a.shape}")
        names.append(str(k))
        columns.append(a)
    if not columns:
        raise DataError("set_data: expected at least a time and a measured column, found none")
    return names, columns

