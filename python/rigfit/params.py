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
        "elite_range", "uncertainty_note",
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
        return {k: getattr(self, k) for k in self.__slots__}

    def __setstate__(self, state):
        for k in self.__slots__:
            setattr(self, k, state.get(k))

    def __eq__(self, other):
        return isinstance(other, Parameter) and self.__getstate__() == other.__getstate__()


class Parameters(dict):
    """An ordered name → :class:`Parameter` mapping (lmfit's ``Parameters``):
    ``params["k1"].value``; ``valuesdict()`` gives name → value."""

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
