import os
from collections.abc import Mapping, Sequence
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _rigfit
from .ensemble import Objective
from .params import Parameter, Parameters

_Backend = Literal["auto", "gpu", "cpu"]
_Precision = Literal["auto", "f32", "f64"]
_Path = str | os.PathLike[str]

class Campaign:
    def __init__(
        self,
        inner: _rigfit.Campaign,
        base_dir: _Path,
        origin: str,
        records: Mapping[str, tuple[str, bytes]] | None = None,
        kept: Sequence[tuple[str, bytes]] | None = None,
    ) -> None: ...
    @classmethod
    def from_json(cls, path: _Path) -> Campaign: ...
    @classmethod
    def from_dict(
        cls,
        campaign: Mapping[str, Any],
        base_dir: _Path | None = None,
        origin: str = "<dict>",
        *,
        pending: bool = False,
    ) -> Campaign: ...
    @property
    def pending(self) -> list[str]: ...
    def to_dict(self) -> dict[str, Any]: ...
    def copy(self) -> Campaign: ...
    def __deepcopy__(self, memo: dict[int, Any]) -> Campaign: ...
    @property
    def name(self) -> str: ...
    @property
    def rig(self) -> str: ...
    @property
    def description(self) -> str: ...
    @property
    def path(self) -> str: ...
    @property
    def experiments(self) -> list[str]: ...
    @property
    def outputs(self) -> list[tuple[str, str]]: ...
    @property
    def warnings(self) -> list[str]: ...
    @property
    def substeps(self) -> int: ...
    @property
    def genes(self) -> list[str]: ...
    @property
    def bounds(self) -> NDArray[np.float64]: ...
    @property
    def params(self) -> Parameters: ...
    @property
    def search_method(self) -> str: ...
    def experiment_info(self, name: str) -> dict[str, Any]: ...
    def set_data(
        self,
        name: str,
        frame: Any,
        *,
        time_column: str | None = None,
        column: str | None = None,
        time_scale: float | None = None,
        scale: float | Mapping[str, float] | None = None,
    ) -> None: ...
    def set_params(
        self,
        params: Mapping[str, Parameter | Mapping[str, float | bool | str] | float] | None = None,
        /,
        **changes: Parameter | Mapping[str, float | bool | str] | float,
    ) -> None: ...
    def objective(
        self,
        vectorized: bool = True,
        *,
        backend: _Backend | None = "cpu",
        precision: _Precision | None = None,
        adapter: int | str | None = None,
        threads: int = 0,
    ) -> Objective: ...
    def simulate(self, theta: ArrayLike | Mapping[str, Any], **kwargs: Any) -> Any: ...
    def residuals(
        self,
        theta: ArrayLike | Mapping[str, Any],
        *,
        backend: _Backend | None = "cpu",
        precision: _Precision | None = None,
        adapter: int | str | None = None,
        threads: int = 0,
    ) -> NDArray[np.float64]: ...

def shipped_rigs() -> dict[str, dict[str, Any]]: ...
