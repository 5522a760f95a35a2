from collections.abc import Mapping
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .campaign import Campaign

DIVERGED: float

class Residuals:
    campaign: Campaign
    def __init__(
        self,
        campaign: Campaign,
        *,
        backend: Literal["auto", "gpu", "cpu"] | None = "cpu",
        precision: Literal["auto", "f32", "f64"] | None = None,
        adapter: int | str | None = None,
        threads: int = 0,
    ) -> None: ...
    @property
    def size(self) -> int: ...
    def __call__(self, theta: ArrayLike | Mapping[str, Any]) -> NDArray[np.float64]: ...

def residuals(
    campaign: Campaign,
    theta: ArrayLike | Mapping[str, Any],
    *,
    backend: Literal["auto", "gpu", "cpu"] | None = "cpu",
    precision: Literal["auto", "f32", "f64"] | None = None,
    adapter: int | str | None = None,
    threads: int = 0,
) -> NDArray[np.float64]: ...

__all__ = ["DIVERGED", "Residuals", "residuals"]
