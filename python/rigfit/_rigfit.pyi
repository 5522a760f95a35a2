# The compiled half of the package: its classes and the functions the
# pure-Python half calls. Users call the pure-Python API (rigfit.*);
# what is not listed here is typed Any.
from collections.abc import Sequence
from typing import Any, final

import numpy as np
from numpy.typing import NDArray

__version__: str

@final
class Campaign:
    @staticmethod
    def load(path: str) -> Campaign: ...
    @staticmethod
    def from_text(
        json: str, base_dir: str, origin: str, records: Sequence[tuple[str, bytes | Record]] = ...
    ) -> Campaign: ...
    @staticmethod
    def build(
        json: str, base_dir: str, origin: str, records: Sequence[tuple[str, bytes | Record]] = ...
    ) -> tuple[Campaign, list[tuple[str, bytes | Record]]]: ...
    @staticmethod
    def load_kept(path: str, base_dir: str) -> tuple[Campaign, list[tuple[str, bytes | Record]]]: ...
    @property
    def raw_json(self) -> str: ...
    @staticmethod
    def pending(json: str, base_dir: str, origin: str) -> Campaign: ...
    def info(self) -> str: ...

@final
class Objective:
    notes: list[str]
    def __new__(
        cls,
        campaign: Campaign,
        *,
        backend: str | None = None,
        precision: str | None = None,
        adapter: str | None = None,
        threads: int = 0,
    ) -> Objective: ...
    def costs(self, theta: NDArray[np.float64]) -> NDArray[np.float64]: ...

@final
class Residuals:
    notes: list[str]
    def __new__(
        cls,
        campaign: Campaign,
        *,
        backend: str | None = None,
        precision: str | None = None,
        adapter: str | None = None,
        threads: int = 0,
    ) -> Residuals: ...
    @property
    def size(self) -> int: ...
    def of(self, theta: NDArray[np.float64]) -> tuple[NDArray[np.float64], list[str]]: ...

@final
class Record:
    @property
    def names(self) -> list[str]: ...

def record_of(names: Sequence[str], columns: Sequence[NDArray[np.float64]]) -> Record: ...
def shipped_rigs() -> list[tuple[str, str]]: ...
def report_html(folder: str) -> str: ...
def save_result(folder: str, files: Sequence[tuple[str, bytes]], overwrite: bool) -> None: ...
def __getattr__(name: str) -> Any: ...
