# Types of featherdyn._mjcf_native, the MJCF loader's fast path (mjcf_cpp/mjcf_native.cpp; docs/architecture.md).
from collections.abc import Callable
from typing import Any

def configure(max_depth: int, max_attribute_length: int, max_length: float, max_mass: float, max_inertia: float,
              hypot: Callable[..., float], max_include_depth: int, max_includes: int, /) -> None: ...
def read(text: str, strict: bool, files: Any = ..., /,
         ) -> tuple[str | None, tuple[float, float, float], bool, list[str], float, list[tuple[Any, ...]]] | None: ...
