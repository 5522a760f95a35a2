import os
from collections.abc import Callable, Mapping
from typing import Any, Literal

def sweep(
    sweep: str | os.PathLike[str] | Mapping[str, Any],
    *,
    threads: int = 0,
    backend: Literal["cpu", "gpu"] = "cpu",
    precision: Literal["auto", "f32", "f64"] | None = None,
    adapter: int | str | None = None,
    progress: bool | Callable[[dict[str, Any]], object] = False,
) -> Any: ...
