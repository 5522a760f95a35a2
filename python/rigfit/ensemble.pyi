from typing import Any, Literal, Mapping, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .campaign import Campaign

@overload
def simulate(
    campaign: Campaign,
    theta: ArrayLike | Mapping[str, Any],
    *,
    t: None = None,
    dt: None = None,
    samples: None = None,
    backend: Literal["auto", "gpu", "cpu"] | None = "cpu",
    precision: Literal["auto", "f32", "f64"] | None = None,
    adapter: int | str | None = None,
    threads: int = 0,
    max_memory: float | str | None = None,
) -> NDArray[np.float64]: ...
@overload
def simulate(
    campaign: Campaign,
    theta: ArrayLike | Mapping[str, Any],
    *,
    t: ArrayLike | None = None,
    dt: float | None = None,
    samples: int | None = None,
    experiment: str | None = None,
    noise: float | Mapping[str, float] | None = None,
    seed: int | None = None,
    drive: ArrayLike | None = None,
    substeps: int | None = None,
    backend: Literal["cpu"] | None = "cpu",
    precision: Literal["auto", "f64"] | None = None,
    threads: int = 0,
    max_memory: float | str | None = None,
) -> Any: ...

class Objective:
    campaign: Campaign
    vectorized: bool
    evaluations: int
    def __init__(
        self,
        campaign: Campaign,
        vectorized: bool = True,
        *,
        backend: Literal["auto", "gpu", "cpu"] | None = None,
        precision: Literal["auto", "f32", "f64"] | None = None,
        adapter: int | str | None = None,
        threads: int = 0,
    ) -> None: ...
    @property
    def bounds(self) -> NDArray[np.float64]: ...
    def __call__(self, x: ArrayLike) -> float | NDArray[np.float64]: ...
