from collections.abc import Sequence
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

class Report(dict[str, Any]):
    fragment: dict[str, Any] | None
    spectra: dict[str, NDArray[Any]] | None

_Triple = Sequence[ArrayLike]

def ringdown(
    t: ArrayLike,
    f: ArrayLike,
    *,
    m1: float | None = None,
    k1: float | None = None,
    start: float | None = None,
) -> Report: ...
def fit_specimen(e: ArrayLike, f: ArrayLike, *, degree: int = 3) -> Report: ...
def frf(
    t: ArrayLike,
    u: ArrayLike,
    y: ArrayLike,
    *,
    response: Literal["displacement", "velocity", "acceleration"] = "displacement",
    segment: int | None = None,
    modes: int = 1,
    f_min: float | None = None,
    f_max: float | None = None,
    min_coherence: float = 0.8,
    names: Sequence[str] = ("m", "k", "c"),
    fixed: bool = False,
) -> Report: ...
def rfs(
    t: ArrayLike,
    x: ArrayLike,
    accel: ArrayLike,
    *,
    mass: float,
    terms: str | Sequence[str] = ("linear", "viscous"),
    alpha: float | None = None,
    beta: float | None = None,
    cutoff: float | None = None,
    filter_order: int = 4,
    fixed: bool = False,
) -> Report: ...
def idim(
    q: ArrayLike,
    force: ArrayLike,
    *,
    sample_rate: float | None = None,
    t: ArrayLike | None = None,
    gain: float = 1.0,
    cutoff: float = 100.0,
    filter_order: int = 4,
    decimation: int = 10,
    fixed: bool = False,
) -> Report: ...
def nimiso(
    t: ArrayLike,
    x: ArrayLike,
    f: ArrayLike,
    *,
    f_min: float,
    f_max: float,
    nonlinear: str = "cubic",
    segment: int | None = None,
    fixed: bool = False,
) -> Report: ...
def arx(
    t: ArrayLike,
    u: ArrayLike,
    ys: ArrayLike,
    *,
    mass: float | Sequence[float],
    f_min: float,
    f_max: float,
    names: Sequence[str] = ("k2", "c2"),
    form: str = "linear",
    segment: int | None = None,
    min_coherence: float = 0.9,
    fixed: bool = False,
) -> Report: ...
def impedance(
    t: ArrayLike,
    x_impact: _Triple,
    y_impact: _Triple,
    *,
    f_min: float,
    f_max: float,
    mass: float | None = None,
    fixed: bool = False,
) -> Report: ...
def sensitivity(
    t: ArrayLike,
    base: _Triple,
    changed: _Triple,
    *,
    k1: float,
    f_min: float,
    f_max: float,
    c1: float = 0.0,
    segment: int | None = None,
    name: str = "k2",
    base_value: float | None = None,
    fixed: bool = False,
) -> Report: ...
