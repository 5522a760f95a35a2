import os
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .params import Parameters

class ExperimentResult:
    summary: dict[str, Any]
    name: str
    r2: float
    one_minus_r2: float
    residual_rms: float | None
    unit: str
    columns: list[str]
    output_columns: list[str]
    full_precision: bool
    t: NDArray[np.float64]
    t_model: NDArray[np.float64]
    measured: NDArray[np.float64]
    model: NDArray[np.float64]
    residual: NDArray[np.float64]
    in_fit_window: NDArray[np.bool_]
    def __init__(
        self,
        summary: dict[str, Any],
        csv_bytes: bytes,
        arrays: Mapping[str, Any] | None = None,
        _label: str | None = None,
    ) -> None: ...
    @property
    def cleaned_force(self) -> NDArray[np.float64] | None: ...
    def to_dataframe(self) -> Any: ...

class FitResult:
    files: dict[str, bytes]
    summary: dict[str, Any]
    params: Parameters
    var_names: list[str]
    correlation: NDArray[np.float64] | None
    experiments: dict[str, ExperimentResult]
    fitness: float
    r2: dict[str, float]
    seed: int
    backend: str
    device: str
    stop_reason: str
    warnings: list[str]
    def __init__(
        self,
        files: Mapping[str, bytes],
        arrays: Mapping[str, Any] | None = None,
        _folder: str | None = None,
    ) -> None: ...
    @property
    def best_values(self) -> dict[str, float]: ...
    @property
    def x(self) -> NDArray[np.float64]: ...
    @property
    def stderr(self) -> NDArray[np.float64]: ...
    @property
    def covariance(self) -> NDArray[np.float64] | None: ...
    @property
    def ndata(self) -> int: ...
    @property
    def nvarys(self) -> int: ...
    @property
    def nfree(self) -> int: ...
    @property
    def chisqr(self) -> float: ...
    @property
    def redchi(self) -> float: ...
    @property
    def aic(self) -> float: ...
    @property
    def bic(self) -> float: ...
    @property
    def nfev(self) -> int: ...
    @property
    def success(self) -> bool: ...
    @property
    def message(self) -> str: ...
    @property
    def history(self) -> dict[str, NDArray[np.float64]]: ...
    def to_dataframe(self) -> Any: ...
    def params_dataframe(self) -> Any: ...
    def fit_report(self) -> str: ...
    def report(self, path: str | os.PathLike[str], overwrite: bool = False) -> str: ...
    def save(self, folder: str | os.PathLike[str], overwrite: bool = False) -> str: ...

def load_result(path: str | os.PathLike[str]) -> FitResult: ...
def read_result_files(folder: str | os.PathLike[str]) -> dict[str, bytes]: ...
