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

    def __init__(self, inner, base_dir, origin, records=None, kept=None):
        self._inner = inner
        self._base_dir = os.fspath(base_dir)
        self._origin = origin
        # experiment name -> (lent path, its columns: a _rigfit.Record)
        self._records = dict(records or {})
        # (path, bytes or Record) of every record the campaign was built
        # from, those read from disk too: a rebuild (an edit, a pickle)
        # reads these.
        self._kept = list(kept or [])
        self._info = json.loads(inner.info())

    # -- construction ---------------------------------------------------
    @classmethod
    def from_json(cls, path):
        """Reads and validates a campaign file (``rigfit check``'s checks);
        raises :class:`rigfit.CampaignError` or :class:`rigfit.DataError`
        naming the file and the JSON path."""
        path = os.fspath(path)
        base_dir = os.path.dirname(os.path.abspath(path))
        inner, kept = _rigfit.Campaign.load_kept(path, base_dir)
        return cls(inner, base_dir, path, kept=kept)

    @classmethod
    def from_dict(cls, campaign, base_dir=None, origin="<dict>", *, pending=False):
        """Validates a campaign given as a dict; relative paths (the rig
        file, the records) resolve against ``base_dir`` (default: the
        current folder); messages name ``origin`` as the file.

        ``pending=True``: an experiment whose data file does not exist is
        built without its record, to be given by :meth:`set_data` (one made
        by ``rigfit.simulate(campaign, params, t=...)``, say): until every
        experiment has one, the campaign shows its parameters, genes and
        outputs and simulates on a time grid, and anything that scores a
        record (``rigfit.fit``, :meth:`objective`, :meth:`residuals`, a
        simulation on the records' grids) raises
        :class:`rigfit.CampaignError` naming the experiments still without
        one (:attr:`pending`). The records that do exist are checked as each
        missing one is set, and in full once none is missing."""
        from . import _arguments as check
        pending = check.flag("pending", pending)
        base_dir = os.path.abspath(os.fspath(base_dir) if base_dir is not None else os.getcwd())
        text = json.dumps(_plain_json(campaign, "", origin), allow_nan=False)
        missing = _missing_records(json.loads(text), base_dir) if pending else []
        if missing:
            from ._pending import pending_campaign
            return pending_campaign(cls, text, base_dir, origin, missing)
        inner, kept = _rigfit.Campaign.build(text, base_dir, origin)
        return cls(inner, base_dir, origin, kept=kept)

    def to_dict(self):
        """The campaign's keys as validated (records set from memory show as
        ``"<memory:NAME>.csv"`` files)."""
        return json.loads(self._built.raw_json)

    def copy(self):
        """An independent copy (the validated campaign itself is shared: it
        never changes; an edit of either rebuilds that one)."""
        c = Campaign(self._built, self._base_dir, self._origin, self._records, self._kept)
        c._pending = list(self.__dict__.get("_pending") or [])
        return c

    # -- records still to come (from_dict(..., pending=True)) --------------
    @property
    def _inner(self):
        # The validated campaign, for everything that computes on it; refused
        # while an experiment has no record (its grid a placeholder).
        pending = self.__dict__.get("_pending")
        if pending:
            from ._pending import no_record
            raise CampaignError(no_record(self._origin, pending))
        return self._built

    @_inner.setter
    def _inner(self, inner):
        self._built = inner

    def _values(self):
        """The validated campaign even while records are pending: its rig,
        parameters and genes are the campaign's, a pending experiment's grid
        a placeholder."""
        return self._built

    @property
    def pending(self):
        """The experiments still without a record (``from_dict(...,
        pending=True)``): :meth:`set_data` gives one."""
        return list(self.__dict__.get("_pending") or [])

    def _lent(self):
        """(path, bytes or Record) of every record the campaign was built
        from: those set from memory, then those read from disk when it was
        built."""
        lent = list(self._records.values())
        paths = {os.fspath(p) for p, _ in lent}
        return lent + [(p, b) for p, b in getattr(self, "_kept", ()) if os.fspath(p) not in paths]

    def _rebuilt_from(self, raw):
        """Rebuilds the campaign from its edited JSON ``raw`` with the very
        records it holds (none read again from disk); on an error nothing
        changes."""
        text = json.dumps(raw, allow_nan=False)
        if self.__dict__.get("_pending"):
            from ._pending import rebuild_pending
            return rebuild_pending(self, text, self._records, self._pending)
        inner, kept = _rigfit.Campaign.build(text, self._base_dir, self._origin, self._lent())
        self._inner, self._kept = inner, kept
        self._info = json.loads(inner.info())

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
        """Every parameter as lmfit-style :class:`Parameter` objects, named as
        ``result.json`` names them: the free ones first, in :attr:`genes`
        order (``vary=True``, with ``min``, ``max``, ``scale``, and ``value``
        their ``init`` or the middle of their range in their scale), then the
        fixed ones: by their bare name where every experiment has one value,
        else once per experiment (``"v2.velocity"``), and each experiment's
        clock offset (``"v2.offset"``).

        Bound to the campaign: setting ``value``, ``min``, ``max``, ``vary``
        or ``scale`` of one of them (or ``.set(...)``, ``params[name] =
        Parameter(...)``, ``params.add(...)``) is :meth:`set_params`: the
        campaign is rebuilt with it, or nothing changes and
        :class:`rigfit.CampaignError` says why. ``params.copy()`` is a
        detached copy."""
        view = getattr(self, "_params_view", None)
        if view is None:
            view = self._params_view = Parameters()
            view._campaign = self
        view._refresh(self._listing())
        return view

    def _listing(self):
        from ._param_edits import listing
        return listing(self._info, json.loads(self._built.raw_json))

    def set_params(self, params=None, /, **changes):
        """Edits parameters, lmfit-style, and rebuilds the campaign (the
        library validating it; its records, those set from memory too, kept
        as they are). ``params``: a :class:`Parameters` (a fit result's, to
        start the next search at its values) or a dict; ``changes``: name =
        edit. An edit is a number (fixed at that value), a dict of
        ``value``, ``min``, ``max``, ``vary``, ``scale`` (the rest as it
        is), or a :class:`Parameter`. ``vary=False`` fixes a parameter at
        ``value`` (default: its current value) and takes it out of
        :attr:`genes`; ``vary=True`` frees one in [``min``, ``max``] (both
        needed for one fixed now), ``value`` then the search's start
        (``init``; an ``init`` outside new bounds is dropped). A bare name
        (``"m1"``) edits every experiment's value, ``"v2.velocity"``
        experiment ``v2``'s alone. All or nothing: an unknown name (with a
        did-you-mean) or a value the library refuses raises
        :class:`rigfit.CampaignError` naming it, and nothing changes."""
        from ._param_edits import edited
        merged = {}
        if params is not None:
            if not hasattr(params, "items"):
                from .errors import ArgumentTypeError
                raise ArgumentTypeError(
                    f"params: expected rigfit.Parameters or a dict of name -> edit, found "
                    f"{type(params).__name__}")
            merged.update(params.items())
        merged.update(changes)
        if not merged:
            return
        current = {p.name: p for p in self._listing()}
        raw = edited(self.to_dict(), self._info, current, merged)
        self._rebuilt_from(raw)
        view = getattr(self, "_params_view", None)
        if view is not None:
            view._refresh(self._listing())

    def experiment_info(self, name):
        """Samples, sample interval (s), first time (s), fit window (sample
        indices), weight of experiment ``name``."""
        pending = self.__dict__.get("_pending") or []
        if str(name).split(".")[0] in pending:
            from ._pending import no_record
            raise CampaignError(no_record(self._origin, [str(name).split(".")[0]]))
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
    def set_data(self, name, frame, *, time_column=None, column=None, time_scale=None,
                 scale=None):
        """Sets experiment ``name``'s record from ``frame``: a pandas (or
        polars, pyarrow, anything with the Arrow stream interface) DataFrame,
        or a dict of name → 1-D array. Its columns are read as the campaign's
        ``data`` object says (``time_column``, ``force_column``/``column``,
        the scales, a drive column), exactly as the same columns in a CSV
        file; ``time_column``/``column`` override the names. Nothing is
        written to disk.

        ``time_scale``: the multiplier of the time column to seconds (1e-3
        for milliseconds; the data object's ``"time_scale"``). ``scale``: the
        multiplier of the measured column to the rig output's unit (1e3 for
        kN into N; the data object's ``"scale"``, or every channel's), or a
        dict measured column → multiplier. Either replaces the campaign's.

        A pandas index: a named index is a column of that name, read as
        ``frame.reset_index()`` would be (so ``df.set_index("t_s")`` works
        as it stands, and an index named as a column is refused as
        ambiguous); an unnamed index of floats is the time when the time
        column is named and the frame has no column of that name (refused as
        ambiguous when it has one); an unnamed integer index (0, 1, 2, …, or
        the rows a filter kept) is row labels, not read.

        The record is checked against the rig before anything runs: a fit
        window that keeps almost none of it (a time column in milliseconds
        read as seconds) or a magnitude off by a power of 10³ (within 3×)
        from everything the rig produces at the centre and corners of its
        bounds (a force in kN against a rig in N) is refused with the
        ``time_scale``/``scale`` that fixes it; a magnitude 100× or more off
        otherwise, a record sampled far slower than the rig moves, or one
        starting long after ``t = 0`` is warned of (:attr:`warnings`, and a
        Python ``RuntimeWarning``). Raises
        :class:`rigfit.DataError` or :class:`rigfit.CampaignError` naming the
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
        names, columns, time_column = _time_index(frame, names, columns,
                                                  time_column, data.get("time_column"))
        if time_column is not None:
            data["time_column"] = time_column
        _set_scales(raw["experiments"][index], names, column, time_scale, scale)
        heard = set(self.warnings)
        if column is not None:
            data.pop("force_column", None)
            data["column"] = column
        # The file's format and text encoding are not the arrays'.
        for key in ("format", "encoding", "decimal"):
            data.pop(key, None)
        records = dict(self._records)
        records[name] = (os.path.join(self._base_dir, fname), _rigfit.record_of(names, columns))
        lent = [records[x["name"]] for x in raw["experiments"] if x["name"] in records]
        if self.__dict__.get("_pending"):
            from ._pending import rebuild_pending
            left = [n for n in self._pending if n != name]
            return rebuild_pending(self, json.dumps(raw), records, left)
        # The other experiments' records as the campaign holds them, never
        # read again from disk (which may have changed since).
        inner, kept = _rigfit.Campaign.build(json.dumps(raw), self._base_dir, self._origin,
                                             lent + list(self._kept))
        self._inner, self._records, self._kept = inner, records, kept
        self._info = json.loads(inner.info())
        _warn_new(self.warnings, heard)

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

    def residuals(self, theta, *, backend="cpu", precision=None, adapter=None, threads=0):
        """The residual vector of one parameter set ``theta`` (P,) in
        :attr:`genes` order, a (N,) array, or of each row of an (S, P)
        array, an (S, N) array, for ``scipy.optimize.least_squares`` (and
        lmfit's ``Minimizer``: ``theta`` may be lmfit ``Parameters`` or a
        dict, read by name). Every experiment's fit window in turn, each
        sample's ``model − measured`` scaled by ``sqrt(w_e / (W · SS_tot,e))``,
        so ``sum(r**2)`` is :meth:`objective`'s cost. A run that blew up
        gives ``sqrt(1e30 / N)`` in every entry (finite, as
        ``least_squares`` requires; its sum of squares is the objective's
        1e30). The evaluator is opened once and kept for the next call."""
        from .residuals import residuals
        return residuals(self, theta, backend=backend, precision=precision, adapter=adapter,
                         threads=threads)

    # -- pickling ---------------------------------------------------------
    def __reduce__(self):
        # The records travel with the campaign (those read from disk too): an
        # unpickled copy fits the data this one holds, whatever the disk
        # holds by then.
        return (_rebuild, (self._inner.raw_json, self._base_dir, self._origin, self._records,
                           self._lent()))

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
            raw = json.loads(self._built.raw_json).get("experiments") or []
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


def _missing_records(raw, base_dir):
    """The experiments of ``raw`` whose data file does not exist (left to
    the library to refuse when ``raw`` is malformed)."""
    missing = []
    for x in raw.get("experiments") or [] if isinstance(raw, dict) else []:
        try:
            name, file = x["name"], x["data"]["file"]
        except (KeyError, TypeError):
            continue
        if isinstance(name, str) and isinstance(file, str) \
                and not os.path.exists(os.path.join(base_dir, file)):
            missing.append(name)
    return missing


def _rebuild(raw_json, base_dir, origin, records, lent=None):
    lent = list(records.values()) if lent is None else list(lent)
    inner, kept = _rigfit.Campaign.build(raw_json, base_dir, origin, lent)
    return Campaign(inner, base_dir, origin, records, kept)


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


def _time_index(frame, names, columns, time_column, data_time):
    """``names``/``columns`` with ``frame``'s pandas index where it is a
    column (see :meth:`Campaign.set_data`), and the time column to read
    (``None``: the data object's)."""
    index = getattr(frame, "index", None) if not isinstance(frame, dict) else None
    if index is None or not type(frame).__module__.startswith("pandas") \
            or getattr(index, "nlevels", 1) != 1:
        return names, columns, time_column
    values = np.asarray(index)
    if values.dtype.kind not in "iuf":
        return names, columns, time_column
    wanted = time_column if time_column is not None else data_time
    label = index.name
    if label is not None:
        label = str(label)
        if label in names:
            raise DataError(
                f"set_data: the frame's index and one of its columns are both named {label!r}: "
                f"which is the record's? rename one (or frame.reset_index(drop=True))")
        values = np.ascontiguousarray(values, dtype=np.float64)
        return [label] + names, [values] + columns, time_column
    if values.dtype.kind != "f":
        return names, columns, time_column  # row labels
    if not isinstance(wanted, str):
        raise DataError(
            "set_data: the frame has an unnamed index of floats and its time column is given by "
            "position: is the index the time? name it (frame.index.name = 't') or pass "
            "time_column=")
    if wanted in names:
        raise DataError(
            f"set_data: the frame has an unnamed index of floats and a column {wanted!r} (the "
            f"time column): which is the time? drop the index (frame.reset_index(drop=True)) "
            f"or name it and pass time_column=")
    values = np.ascontiguousarray(values, dtype=np.float64)
    return [wanted] + names, [values] + columns, time_column


def _set_scales(experiment, names, column, time_scale, scale):
    """Writes ``time_scale`` and ``scale`` (a number, or a dict measured
    column → number) into ``experiment``'s data object or channels, as a
    campaign file would hold them."""
    from . import _arguments as check
    data = experiment["data"]
    time_scale = check.real("time_scale", time_scale, positive=True)
    if time_scale is not None:
        data["time_scale"] = time_scale
    if scale is None:
        return
    channels = experiment.get("channels") or []
    if isinstance(scale, dict):
        if channels:
            targets = {str(ch.get("column")): ch for ch in channels}
        else:
            key = column if column is not None else data.get("column", data.get("force_column", 1))
            if isinstance(key, int) and not isinstance(key, bool) and 0 <= key < len(names):
                key = names[key]
            targets = {str(key): data}
        for col, factor in scale.items():
            if str(col) not in targets:
                raise CampaignError(
                    f"scale: no measured column {col!r} in experiment "
                    f"{experiment.get('name')!r}; its measured column(s): "
                    f"{', '.join(repr(k) for k in targets)}")
            _set_scale(targets[str(col)], check.real(f"scale[{col!r}]", factor, optional=False),
                       f"scale[{col!r}]")
        return
    factor = check.real("scale", scale)
    for target in channels or [data]:
        _set_scale(target, factor, "scale")


def _set_scale(target, factor, name):
    if factor == 0:
        raise CampaignError(f"{name}=0.0: expected a non-zero multiplier")
    target.pop("force_scale", None)
    target["scale"] = factor


def _warn_new(warnings_now, heard):
    """Each campaign warning not in ``heard`` as a Python warning, so that a
    notebook shows it when the record is given."""
    import warnings
    for w in warnings_now:
        if w not in heard:
            warnings.warn(w, RuntimeWarning, stacklevel=3)
