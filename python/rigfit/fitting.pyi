import os
from collections.abc import Callable
from typing import Any, Literal

from .campaign import Campaign
from .result import FitResult

def fit(
    campaign: Campaign,
    *,
    seed: int | None = None,
    backend: Literal["auto", "gpu", "cpu"] | None = None,
    precision: Literal["auto", "f32", "f64"] | None = None,
    adapter: int | str | None = None,
    out: str | os.PathLike[str] | None = None,
    resume: bool = False,
    overwrite: bool = False,
    population: int | None = None,
    generations: int | None = None,
    target_fitness: float | None = None,
    method: Literal["ga", "cmaes"] | None = None,
    threads: int = 0,
    max_memory: float | str | None = None,
    progress: bool | Callable[[dict[str, Any]], object] = False,
) -> FitResult: ...
