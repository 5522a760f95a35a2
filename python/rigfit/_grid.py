"""``rigfit.simulate`` on a time grid of the caller's own: one experiment
run at the given times (its record need not exist yet), returned as the
record the campaign reads (its ``data`` object's columns, each measured
channel with Gaussian noise if asked), which :meth:`Campaign.set_data` takes
as it stands."""

import difflib
import json
import os

import numpy as np

from . import _arguments as check
from . import _rigfit
from .errors import ArgumentTypeError, CampaignError, Error

#: Relative jitter of the sample interval above which the library resamples
#: a record (``rigfit::base::data::JITTER_TOLERANCE``): a grid must stay
#: within it, or the samples would not be at the times given.
JITTER_TOLERANCE = 1.0e-3


def time_grid(t, dt, samples):
    """The sample times (s) from ``t=`` or ``dt=`` and ``samples=``."""
    if t is not None and (dt is not None or samples is not None):
        raise CampaignError("t: expected t= alone, or dt= with samples=, not both")
    if t is None:
        dt = check.real("dt", dt, positive=True)
        samples = check.integer("samples", samples, minimum=2, optional=False)
        return np.arange(samples, dtype=np.float64) * dt
    try:
        a = np.asarray(t, dtype=np.float64)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"t: expected an array of times (s), found "
                                f"{type(t).__name__}") from None
    if a.ndim != 1 or a.size < 2:
        raise CampaignError(f"t: expected a 1-D array of at least 2 times (s), found shape "
                            f"{a.shape}")
    if not np.all(np.isfinite(a)):
        raise CampaignError("t: expected finite times, found NaN or infinity")
    d = np.diff(a)
    if not np.all(d > 0):
        k = int(np.argmin(d > 0))
        raise CampaignError(f"t: expected strictly increasing times, found t[{k + 1}] = "
                            f"{a[k + 1]!r} after t[{k}] = {a[k]!r}")
    median = float(np.median(d))
    jitter = float(np.max(np.abs(d - median)) / median)
    if jitter > JITTER_TOLERANCE:
        raise CampaignError(
            f"t: expected uniformly spaced times (interval jitter at most "
            f"{100 * JITTER_TOLERANCE:g} % of the median interval), found a jitter of "
            f"{100 * jitter:.3g} %; the samples of a record are taken at a fixed interval")
    return np.ascontiguousarray(a)


def _experiment(raw, name, origin):
    names = [x.get("name") for x in raw["experiments"]]
    if name is None:
        return 0
    name = check.text("experiment", name)
    if name in names:
        return names.index(name)
    close = difflib.get_close_matches(name, [str(n) for n in names], n=1)
    hint = f"; did you mean '{close[0]}'?" if close else ""
    raise CampaignError(f"experiment={name!r}: {origin} has experiments "
                        f"{', '.join(repr(n) for n in names)}{hint}")


def _column(value, default):
    return default if value is None else value


def layout(x, outputs):
    """The record's columns of experiment ``x`` (its raw dict) in order, as
    (header, role): ``"time"``, ``("measured", j)``, ``"drive"`` or
    ``"unused"``, each placed where the campaign's ``data`` reads it (by name,
    or at a 0-based position), as ``rigfit simulate`` lays out its records;
    and the measured channels as (output name, scale)."""
    data = x.get("data") or {}
    units = dict(outputs)
    if x.get("channels"):
        channels = [(ch["output"], float(ch.get("scale", 1.0))) for ch in x["channels"]]
        columns = [ch["column"] for ch in x["channels"]]
    else:
        channels = [(outputs[0][0], float(data.get("force_scale", data.get("scale", 1.0))))]
        columns = [_column(data.get("force_column", data.get("column")), 1)]
    wanted = [(_column(data.get("time_column"), 0), "t_s", "time")]
    for j, ((out, _), col) in enumerate(zip(channels, columns)):
        wanted.append((col, f"{out}_{units.get(out, '')}".rstrip("_"), ("measured", j)))
    drive = x.get("drive")
    if isinstance(drive, dict) and isinstance(drive.get("force"), dict) \
            and drive["force"].get("column") is not None:
        wanted.append((drive["force"]["column"], "drive", "drive"))
    width = max([c + 1 for c, _, _ in wanted if isinstance(c, int)] + [len(wanted)])
    slots = [None] * width
    for c, header, role in wanted:
        if isinstance(c, int):
            if slots[c] is not None:
                raise CampaignError(f"experiment '{x['name']}': its data object reads two "
                                    f"columns at position {c}")
            slots[c] = (header, role)
    taken = {s[0] for s in slots if s}
    for c, header, role in wanted:
        if isinstance(c, str):
            free = slots.index(None)
            slots[free] = (c, role)
            taken.add(c)
    out = []
    for i, s in enumerate(slots):
        if s is None:
            name = f"unused_{i}"
            while name in taken:
                name += "_"
            s = (name, "unused")
        out.append(s)
    return out, channels


def _sigmas(noise, channels, units, name):
    """One standard deviation per channel from ``noise=``: a number (one
    channel) or a dict of output name → σ (a channel left out: none)."""
    listed = ", ".join(f"'{o}' ({units.get(o, '')})" for o, _ in channels)
    if noise is None:
        return [0.0] * len(channels)
    if isinstance(noise, dict):
        known = [o for o, _ in channels]
        for k in noise:
            if k not in known:
                close = difflib.get_close_matches(str(k), known, n=1)
                hint = f"; did you mean '{close[0]}'?" if close else ""
                raise CampaignError(f"noise: {k!r} is no channel of experiment '{name}' "
                                    f"(its channels: {listed}){hint}")
        values = [noise.get(o, 0.0) for o in known]
        where = [f"noise[{o!r}]" for o in known]
    else:
        if len(channels) != 1:
            raise CampaignError(
                f"noise={noise!r}: experiment '{name}' has {len(channels)} channels in their own "
                f"units ({listed}); give a dict of output name → standard deviation")
        values, where = [noise], ["noise"]
    out = []
    for w, v in zip(where, values):
        v = check.real(w, v, optional=False)
        if v < 0:
            raise CampaignError(f"{w}={v!r}: expected a standard deviation >= 0 in the "
                                f"output's unit")
        out.append(v)
    return out


def _drive(drive, n, x, column):
    if column is None:
        if drive is not None:
            raise CampaignError(f"drive: experiment '{x['name']}' reads no drive column; "
                                f"leave drive out")
        return None
    if drive is None:
        raise CampaignError(
            f"drive: experiment '{x['name']}' reads its drive from column {column!r} of its "
            f"record: give drive= ({n} values of that column, one per time of the grid, in the "
            f"unit its record holds)")
    try:
        a = np.asarray(drive, dtype=np.float64)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"drive: expected an array of {n} numbers, found "
                                f"{type(drive).__name__}") from None
    if a.shape != (n,):
        raise CampaignError(f"drive: expected {n} values, one per time of the grid, found "
                            f"shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise CampaignError("drive: expected finite values, found NaN or infinity")
    return np.ascontiguousarray(a)


def simulate_grid(campaign, inner, a, *, t, experiment, noise, seed, drive, substeps, threads,
                  max_memory, single):
    """The records of the parameter sets ``a`` (S, P) on the grid ``t`` (s),
    a DataFrame each (a dict of columns without pandas); one when
    ``single``."""
    raw = campaign.to_dict()
    origin = campaign.path
    e = _experiment(raw, experiment, origin)
    x = raw["experiments"][e]
    name = x["name"]
    for state, v in (x.get("initial") or {}).items():
        if isinstance(v, dict) and "column" in v:
            raise CampaignError(
                f"experiment '{name}': initial.{state} is read from column {v['column']!r} of "
                f"its record, which a simulation on a grid does not have; give the initial "
                f"value as a number")
    outputs = campaign.outputs
    units = dict(outputs)
    cols, channels = layout(x, outputs)
    sigmas = _sigmas(noise, channels, units, name)
    drive_col = next((h for h, role in cols if role == "drive"), None)
    n = len(t)
    drive = _drive(drive, n, x, drive_col)
    seed = check.integer("seed", seed, maximum=check.MAX_SEED)
    substeps = check.integer("substeps", substeps, minimum=1)
    time_scale = float((x.get("data") or {}).get("time_scale", 1.0))
    t_rec = np.ascontiguousarray(t / time_scale)
    zeros = np.zeros(n)

    def column(role, values_of):
        if role == "time":
            return t_rec
        if role == "drive":
            return drive
        if role == "unused":
            return zeros
        return values_of(role[1])

    names = [h for h, _ in cols]
    record = _rigfit.record_of(names, [column(r, lambda j: zeros) for _, r in cols])
    fname = f"<grid:{name}>.csv"
    x = json.loads(json.dumps(x))
    x["data"]["file"] = fname
    x.pop("fit_window", None)
    for ch in x.get("channels") or []:
        ch.pop("fit_window", None)
    raw.pop("validation", None)
    raw["experiments"] = [x]
    base_dir = campaign._base_dir
    try:
        out, used, notes = _rigfit.simulate_grid(
            inner, json.dumps(raw), base_dir, origin, (os.path.join(base_dir, fname), record),
            e, a, samples=n, sigmas=sigmas, substeps=substeps, threads=threads, max_memory=max_memory)
    except Error as err:
        raise check.reword(err)
    output_index = {o: i for i, (o, _) in enumerate(outputs)}
    rng = np.random.default_rng(seed)
    frames = []
    for s in range(out.shape[0]):
        z = rng.standard_normal((n, len(channels)))

        def measured(j, s=s, z=z):
            o, scale = channels[j]
            return (out[s, :, output_index[o]] + sigmas[j] * z[:, j]) / scale

        frames.append(_frame(names, [column(r, measured) for _, r in cols],
                             {"experiment": name, "substeps": used, "seed": seed,
                              "noise": dict(zip([o for o, _ in channels], sigmas))}))
    return frames[0] if single else frames, notes


def _frame(names, columns, attrs):
    try:
        import pandas as pd
    except ImportError:
        return dict(zip(names, columns))
    df = pd.DataFrame(dict(zip(names, columns)), columns=names)
    df.attrs.update(attrs)
    return df
