"""A campaign's parameters as :class:`Parameter` objects, and edits to them
written back into the campaign's JSON (the library validates the result).

Names are those of ``result.json``: a free parameter by its gene's name
(``"k1"``, ``"hx.tau"``, ``"v2.offset"``); a fixed one by its bare name where
every experiment has one value and no experiment searches it, else once per
experiment (``"v2.velocity"``), and each experiment's clock offset
(``"v2.offset"``).
"""

import difflib
import math
import numbers

import numpy as np

from . import _arguments as check
from .errors import ArgumentTypeError, CampaignError
from .params import Parameter

#: What an edit may change.
EDITABLE = ("value", "min", "max", "vary", "scale")


def listing(info, raw):
    """Every parameter of a campaign (its ``info()`` and its JSON ``raw``):
    the genes in the search's order, then the fixed ones."""
    out = []
    genes = {}
    for g in info["genes"]:
        lo, hi = g["lower"], g["upper"]
        if g["init"] is not None:
            value = g["init"]
        elif g["scale"] == "log" and lo > 0:
            value = float(np.sqrt(lo * hi))
        else:
            value = 0.5 * (lo + hi)
        genes[g["name"]] = g
        out.append(Parameter(g["name"], value=value, min=lo, max=hi, vary=True, scale=g["scale"],
                             unit=g["unit"], experiment=g["experiment"], init=g["init"]))
    names = _experiments(raw)
    runs = {}
    for x in info["experiments"]:
        runs.setdefault(x["name"].split(".")[0], x)
    firsts = [runs.get(n) for n in names]
    if any(x is None for x in firsts):
        return out
    for i, p in enumerate(info["params"]):
        n = p["name"]
        values = [_value(x["values"][i]) for x in firsts]
        own = [_own(raw, e, n) for e in range(len(names))]
        if n in genes:
            # A shared gene; experiments that fix their own value show it.
            rows = [(f"{x}.{n}", e) for e, x in enumerate(names)
                    if own[e] and f"{x}.{n}" not in genes]
        elif not any(f"{x}.{n}" in genes for x in names) and all(
                _same(v, values[0]) for v in values):
            rows = [(n, None)] if names else []
        else:
            rows = [(f"{x}.{n}", e) for e, x in enumerate(names) if f"{x}.{n}" not in genes]
        for name, e in rows:
            out.append(Parameter(name, value=values[0 if e is None else e], unit=p["unit"],
                                 experiment=None if e is None else names[e]))
    for e, x in enumerate(names):
        name = f"{x}.offset"
        if name not in genes:
            out.append(Parameter(name, value=firsts[e]["offset"], unit="s", experiment=x))
    return out


def edited(raw, info, current, changes):
    """``raw`` (a copy is edited) with ``changes`` (name → a dict of
    :data:`EDITABLE` keys, a number or a :class:`Parameter`) applied;
    ``current`` is the campaign's listing by name. Raises
    :class:`CampaignError` naming the parameter for what cannot be written."""
    import copy
    raw = copy.deepcopy(raw)
    known = [p["name"] for p in info["params"]]
    unknown = [n for n in changes if _locations(raw, info, known, n) is None]
    if unknown:
        raise CampaignError(_unknown(unknown, list(current) + known))
    for name, change in changes.items():
        fields = _fields(name, change)
        spec = _spec(name, current.get(name), fields)
        locations = _locations(raw, info, known, name)
        if spec is not None and isinstance(spec, dict) and len(locations) > 1:
            where = ", ".join(repr(_name_of(raw, loc, name)) for loc in locations)
            raise CampaignError(
                f"params[{name!r}]: vary=True: '{name}' is set in several places ({where}); "
                f"free one of them by that name")
        for loc in locations:
            _put(raw, loc, spec)
    return raw


def _fields(name, change):
    """``change`` as a dict of :data:`EDITABLE` keys, checked."""
    if isinstance(change, Parameter):
        fields = {"value": change.value, "vary": change.vary}
        if change.vary:
            fields.update(min=change.min, max=change.max)
            # A Parameter's "linear" is its default (a fit result's says
            # nothing of the scale): the campaign's scale stays.
            if change.scale != "linear":
                fields["scale"] = change.scale
        return _checked(name, fields)
    if isinstance(change, dict):
        bad = [k for k in change if k not in EDITABLE]
        if bad:
            raise CampaignError(
                f"params[{name!r}]: expected the keys {', '.join(EDITABLE)}; found {bad[0]!r}")
        return _checked(name, dict(change))
    if change is None or isinstance(change, (numbers.Real, np.integer, np.floating)) \
            and not isinstance(change, (bool, np.bool_)):
        return _checked(name, {"value": change, "vary": False})
    raise ArgumentTypeError(
        f"params[{name!r}]: expected a number (fixed), a dict of value/min/max/vary/scale or "
        f"a rigfit.Parameter, found {type(change).__name__} {change!r:.60}")


def _checked(name, fields):
    out = {}
    for k, v in fields.items():
        where = f"params[{name!r}].{k}"
        if v is None:
            continue
        if k == "vary":
            out[k] = check.flag(where, v)
        elif k == "scale":
            out[k] = check.choice(where, v, ("linear", "log"))
        else:
            if isinstance(v, (bool, np.bool_)) or not isinstance(
                    v, (numbers.Real, np.integer, np.floating)):
                raise ArgumentTypeError(f"{where}: expected a number, found "
                                        f"{type(v).__name__} {v!r:.60}")
            x = float(v)
            if math.isnan(x) or (math.isinf(x) and not (k == "value" and x > 0)):
                raise CampaignError(f"{where}={x!r}: expected a finite number")
            out[k] = x
    if "value" in fields and fields["value"] is None and fields.get("vary") is False:
        out["value"] = math.inf
    return out


def _spec(name, cur, fields):
    """The JSON value of parameter ``name`` (a number, ``None`` for +inf, or
    ``{"min", "max", "scale"?, "init"?}``) after ``fields`` on ``cur``."""
    free = fields.get("vary", cur.vary if cur is not None else False)
    value = fields.get("value", cur.value if cur is not None else None)
    if not free:
        bounds = [k for k in ("min", "max", "scale") if k in fields]
        if bounds:
            raise CampaignError(
                f"params[{name!r}].{bounds[0]}: a fixed parameter has no "
                f"{'scale' if bounds == ['scale'] else 'bounds'}; give vary=True with min and max "
                f"to search '{name}'")
        if value is None:
            raise CampaignError(f"params[{name!r}]: vary=False: expected a value to fix it at")
        return None if math.isinf(value) else value
    was_free = cur is not None and cur.vary
    lo = fields.get("min", cur.min if was_free else None)
    hi = fields.get("max", cur.max if was_free else None)
    if lo is None or hi is None:
        raise CampaignError(
            f"params[{name!r}]: vary=True: expected min and max (the range the search samples) "
            f"for a parameter that is fixed now")
    spec = {"min": lo, "max": hi}
    scale = fields.get("scale", cur.scale if was_free else None)
    if scale is not None:
        spec["scale"] = scale
    init = fields.get("value")
    if init is None and cur is not None and (cur.init is not None or not was_free):
        # The value it had seeds the search where it is still inside the range.
        seed = cur.init if was_free else cur.value
        init = seed if seed is not None and lo <= seed <= hi else None
    if init is not None:
        spec["init"] = init
    return spec


def _experiments(raw):
    xs = raw.get("experiments")
    return [x.get("name") for x in xs] if isinstance(xs, list) else []


def _own(raw, e, n):
    x = raw["experiments"][e]
    if n.startswith("initial_"):
        return n[len("initial_"):] in (x.get("initial") or {})
    return n in (x.get("params") or {})


def _locations(raw, info, known, name):
    """Where ``name`` is written in the JSON; ``None`` for a name the
    campaign does not have."""
    names = _experiments(raw)
    genes = {g["name"] for g in info["genes"]}
    head, dot, n = name.partition(".")
    if dot:
        if head not in names:
            return None
        e = names.index(head)
        if n == "offset":
            return [("offset", e)]
        if n not in known:
            return None
        if n.startswith("initial_"):
            return [("initial", e, n[len("initial_"):])]
        return [("own", e, n)]
    if name not in known:
        return None
    if name in genes:
        return [("shared", name)]
    per = [f"{x}.{name}" for x in names if f"{x}.{name}" in genes]
    if per:
        raise CampaignError(
            f"params[{name!r}]: '{name}' is searched per experiment "
            f"({', '.join(repr(p) for p in per)}); name the experiment's parameter")
    if name.startswith("initial_"):
        return [("initial", e, name[len("initial_"):]) for e in range(len(names))]
    locs = [("own", e, name) for e in range(len(names)) if _own(raw, e, name)]
    if len(locs) < len(names) or not locs:
        locs.insert(0, ("shared", name))
    return locs


def _name_of(raw, loc, name):
    if loc[0] == "shared":
        return name
    x = raw["experiments"][loc[1]]["name"]
    return f"{x}.offset" if loc[0] == "offset" else f"{x}.{name.split('.')[-1]}"


def _put(raw, loc, spec):
    if loc[0] == "shared":
        raw.setdefault("params", {})[loc[1]] = spec
        return
    x = raw["experiments"][loc[1]]
    if loc[0] == "offset":
        x["offset"] = spec
    elif loc[0] == "own":
        x.setdefault("params", {})[loc[2]] = spec
    else:
        x.setdefault("initial", {})[loc[2]] = spec


def _value(v):
    return math.inf if v is None else v


def _same(a, b):
    return a == b or (a != a and b != b)


def _unknown(names, choices):
    parts = []
    for n in names:
        close = difflib.get_close_matches(str(n), choices, n=1)
        parts.append(repr(n) + (f" (did you mean '{close[0]}'?)" if close else ""))
    return (f"params: the campaign has no parameter {', '.join(parts)}; it has "
            f"{', '.join(dict.fromkeys(choices))}")
