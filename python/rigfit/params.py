"""lmfit-style parameters: ``value``, ``min``, ``max``, ``vary``, ``scale``,
``unit``, and for a fitted one ``stderr``, ``interval95`` and flags."""

import math


class Parameter:
    """One parameter of a campaign or a fit.

    ``vary`` is True for a free parameter (a gene of the search, bounded by
    ``min`` and ``max``, sampled uniformly in ``scale``: ``"linear"`` or
    ``"log"``); a fixed one has ``min``/``max`` of ``None``.
    """

    __slots__ = (
        "name", "value", "min", "max", "vary", "scale", "unit", "experiment",
        "init", "stderr", "interval95", "determined", "at_bound", "correlated_with",
        "elite_range", "uncertainty_note", "_bound",
    )

    def __init__(self, name, value=None, min=None, max=None, vary=False, scale="linear",
                 unit="", experiment=None, init=None, stderr=None, interval95=None,
                 determined=None, at_bound=None, correlated_with=(), elite_range=None,
                 uncertainty_note=None):
        self.name = name
        self.value = value
        self.min = min
        self.max = max
        self.vary = vary
        self.scale = scale
        self.unit = unit
        self.experiment = experiment
        self.init = init
        self.stderr = stderr
        self.interval95 = interval95
        self.determined = determined
        self.at_bound = at_bound
        self.correlated_with = list(correlated_with)
        self.elite_range = elite_range
        self.uncertainty_note = uncertainty_note

    def __setattr__(self, key, value):
        bound = getattr(self, "_bound", None)
        if bound is not None and key != "_bound":
            bound._edit(self, key, value)
            return
        object.__setattr__(self, key, value)

    def set(self, value=None, vary=None, min=None, max=None, scale=None):
        """lmfit's ``set``: changes the given attributes (``None`` leaves
        one as it is) at once. On a campaign's parameter (from
        ``campaign.params``) the campaign is rebuilt with them, or nothing
        changes and :class:`rigfit.CampaignError` says why."""
        changes = {k: v for k, v in (("value", value), ("vary", vary), ("min", min),
                                     ("max", max), ("scale", scale)) if v is not None}
        bound = getattr(self, "_bound", None)
        if bound is not None:
            bound._edit_many(self, changes)
            return
        for k, v in changes.items():
            object.__setattr__(self, k, v)

    def __repr__(self):
        parts = [f"value={_num(self.value)}"]
        if self.stderr is not None:
            parts.append(f"+/- {_num(self.stderr)}")
        if self.vary:
            parts.append(f"bounds=[{_num(self.min)}:{_num(self.max)}]")
            if self.scale != "linear":
                parts.append(f"scale={self.scale}")
        else:
            parts.append("(fixed)")
        if self.unit:
            parts.append(f"unit={self.unit!r}")
        return f"<Parameter '{self.name}', {', '.join(parts)}>"

    def __getstate__(self):
        return {k: getattr(self, k) for k in self.__slots__ if k != "_bound"}

    def __setstate__(self, state):
        for k in self.__slots__:
            object.__setattr__(self, k, state.get(k))

    def __copy__(self):
        # A copy is detached: editing it edits no campaign.
        p = Parameter.__new__(Parameter)
        p.__setstate__(self.__getstate__())
        return p

    def __deepcopy__(self, memo):
        import copy
        p = Parameter.__new__(Parameter)
        p.__setstate__(copy.deepcopy(self.__getstate__(), memo))
        return p

    def __reduce__(self):
        return (_parameter, (self.__getstate__(),))

    def __eq__(self, other):
        return isinstance(other, Parameter) and self.__getstate__() == other.__getstate__()


class Parameters(dict):
    """An ordered name → :class:`Parameter` mapping (lmfit's ``Parameters``):
    ``params["k1"].value``; ``valuesdict()`` gives name → value.

    ``campaign.params`` is bound to its campaign (:attr:`campaign`): setting
    ``value``, ``min``, ``max``, ``vary`` or ``scale`` of one of its
    parameters, ``set(...)``, ``params[name] = Parameter(...)``, ``add`` and
    ``update`` rebuild the campaign with the change, or change nothing and
    raise :class:`rigfit.CampaignError`. Any other ``Parameters`` (a
    :meth:`copy`, a fit result's) is detached: editing it edits no campaign.
    """

    _campaign = None

    @property
    def campaign(self):
        """The campaign these parameters edit, or ``None`` (detached)."""
        return self._campaign

    # -- edits ------------------------------------------------------------
    def _edit(self, param, key, value):
        from .errors import CampaignError
        if key not in ("value", "min", "max", "vary", "scale"):
            raise CampaignError(
                f"params[{param.name!r}].{key}: a campaign's parameter takes value, min, max, "
                f"vary and scale; params.copy() gives a detached copy to annotate")
        if value is None:
            raise CampaignError(f"params[{param.name!r}].{key}=None: expected a "
                                f"{'True or False' if key == 'vary' else 'value'}")
        self._edit_many(param, {key: value})

    def _edit_many(self, param, changes):
        if changes:
            self._campaign.set_params({param.name: changes})

    def __setitem__(self, name, param):
        if self._campaign is None:
            dict.__setitem__(self, name, param)
            return
        from .errors import ArgumentTypeError
        if not isinstance(param, Parameter):
            raise ArgumentTypeError(
                f"params[{name!r}]: expected a rigfit.Parameter, found {type(param).__name__}")
        self._campaign.set_params({name: param})

    def add(self, name, value=None, vary=True, min=None, max=None, scale=None):
        """lmfit's ``add``: on a campaign's parameters, sets parameter
        ``name`` (one the campaign has) free in [``min``, ``max``] starting
        at ``value``, or fixed at ``value`` (``vary=False``); on detached
        ones, adds a :class:`Parameter`."""
        if self._campaign is None:
            dict.__setitem__(self, name, Parameter(name, value=value, vary=vary, min=min,
                                                   max=max, scale=scale or "linear"))
            return
        changes = {k: v for k, v in (("value", value), ("vary", vary), ("min", min),
                                     ("max", max), ("scale", scale)) if v is not None}
        self._campaign.set_params({name: changes})

    def update(self, *args, **kwargs):
        if self._campaign is None:
            dict.update(self, *args, **kwargs)
            return
        self._campaign.set_params(dict(*args, **kwargs))

    def _refuse(self):
        from .errors import CampaignError
        raise CampaignError("params: a campaign's parameters cannot be removed; fix one with "
                            "params[name].set(vary=False, value=...), or edit params.copy()")

    def __delitem__(self, name):
        if self._campaign is not None:
            self._refuse()
        dict.__delitem__(self, name)

    def pop(self, *args):
        if self._campaign is not None:
            self._refuse()
        return dict.pop(self, *args)

    def popitem(self):
        if self._campaign is not None:
            self._refuse()
        return dict.popitem(self)

    def clear(self):
        if self._campaign is not None:
            self._refuse()
        dict.clear(self)

    def setdefault(self, name, default=None):
        if self._campaign is not None and name not in self:
            self._refuse()
        return dict.setdefault(self, name, default)

    def _refresh(self, fresh):
        """Takes the campaign's parameters ``fresh`` (a list), keeping the
        objects a caller holds (by name) up to date."""
        held = dict(self)
        dict.clear(self)
        for p in fresh:
            q = held.get(p.name)
            if q is None:
                q = p
            else:
                q.__setstate__(p.__getstate__())
            object.__setattr__(q, "_bound", self)
            dict.__setitem__(self, p.name, q)
        for name, q in held.items():
            if name not in self:
                object.__setattr__(q, "_bound", None)

    # -- copies -----------------------------------------------------------
    def copy(self):
        """A detached copy (editing it edits no campaign)."""
        import copy
        return Parameters((k, copy.copy(p)) for k, p in self.items())

    __copy__ = copy

    def __deepcopy__(self, memo):
        return self.copy()

    def __reduce__(self):
        return (Parameters, (list(self.copy().items()),))

    def valuesdict(self):
        return {k: p.value for k, p in self.items()}

    def free(self):
        """The free parameters, in the genes' (the search's) order."""
        return Parameters((k, p) for k, p in self.items() if p.vary)

    def pretty_print(self):
        print(self.pretty())

    def pretty(self):
        rows = [f"{'name':<22} {'value':>13} {'stderr':>11} {'min':>11} {'max':>11} vary  unit"]
        for p in self.values():
            rows.append(
                f"{p.name:<22} {_num(p.value):>13} {_num(p.stderr):>11} {_num(p.min):>11} "
                f"{_num(p.max):>11} {str(p.vary):<5} {p.unit}"
            )
        return "\n".join(rows)

    def __repr__(self):
        return "Parameters([" + ", ".join(repr(p) for p in self.values()) + "])"


def _num(x):
    if x is None:
        return "-"
    if isinstance(x, float) and (math.isnan(x) or math.isinf(x)):
        return str(x)
    return f"{x:.6g}"


def _parameter(state):
    p = Parameter.__new__(Parameter)
    p.__setstate__(state)
    return p
