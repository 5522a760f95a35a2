from collections.abc import Iterable, Sequence
from typing import Literal

from .campaign import Campaign

class Parameter:
    name: str
    value: float
    min: float | None
    max: float | None
    vary: bool
    scale: str
    unit: str
    experiment: str | None
    init: float | None
    stderr: float | None
    interval95: tuple[float | None, float | None] | None
    determined: bool | None
    at_bound: Literal["lower", "upper"] | None
    correlated_with: list[str]
    elite_range: Sequence[float] | None
    uncertainty_note: str | None
    def __init__(
        self,
        name: str,
        value: float | None = None,
        min: float | None = None,
        max: float | None = None,
        vary: bool = False,
        scale: str = "linear",
        unit: str = "",
        experiment: str | None = None,
        init: float | None = None,
        stderr: float | None = None,
        interval95: tuple[float | None, float | None] | None = None,
        determined: bool | None = None,
        at_bound: Literal["lower", "upper"] | None = None,
        correlated_with: Iterable[str] = (),
        elite_range: Sequence[float] | None = None,
        uncertainty_note: str | None = None,
    ) -> None: ...
    def set(
        self,
        value: float | None = None,
        vary: bool | None = None,
        min: float | None = None,
        max: float | None = None,
        scale: str | None = None,
    ) -> None: ...

class Parameters(dict[str, Parameter]):
    @property
    def campaign(self) -> Campaign | None: ...
    def valuesdict(self) -> dict[str, float]: ...
    def free(self) -> Parameters: ...
    def add(
        self,
        name: str,
        value: float | None = None,
        vary: bool = True,
        min: float | None = None,
        max: float | None = None,
        scale: str | None = None,
    ) -> None: ...
    def copy(self) -> Parameters: ...
    def pretty_print(self) -> None: ...
    def pretty(self) -> str: ...

