# Types of featherdyn._mjcf_native, the MJCF loader's fast path (mjcf_cpp/mjcf_native.cpp; docs/architecture.md).
from collections.abc import Callable
from typing import Any

def configure(max_depth: int, max_attribute_length: int, max_length: float, max_mass: float, max_inertia: float,
              hypot: Callable[..., float], /) -> None: ...
def read(text: str, strict: bool, mesh_exists: Callable[[str, str | None, str | None], bool] = ...,
         mesh_properties: Callable[..., tuple[float, tuple[float, ...], tuple[float, ...]]] = ..., /,
         ) -> tuple[str | None, tuple[float, float, float], bool, list[str], float, list[tuple[Any, ...]]] | None: ...
