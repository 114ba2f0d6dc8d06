"""``featherdyn info --build`` and ``_core.build_info()`` (issue 31): how the compiled core was built, and the SIMD
kernels it runs (``FEATHERDYN_SIMD=baseline`` forces the portable ones)."""

from __future__ import annotations

import os
import platform
import re
import subprocess
import sys

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.core import _core
from featherdyn.tools.cli import main

KEYS = {"compiler", "build_type", "processor", "simd_compiled", "simd", "simd_lanes", "numpy_headers", "numpy_api",
        "numpy_target_api", "numpy_minimum", "nanobind", "python", "stable_abi", "jax_ffi"}


def _version(text: str) -> tuple[int, ...]:
    return tuple(int(x) for x in re.findall(r"\d+", text)[:2])


def test_build_info_names_the_build() -> None:
    info = _core.build_info()
    assert set(info) == KEYS
    assert re.fullmatch(r"(GNU|Clang|AppleClang) \d+\.\d+.*", str(info["compiler"])), info["compiler"]
    assert info["build_type"] in ("Release", "RelWithDebInfo", "Debug", "MinSizeRel"), info["build_type"]
    assert re.fullmatch(r"\d+\.\d+\.\d+", str(info["nanobind"]))
    # the kernels in use are the ones the module runs (simd()), and among those compiled
    assert (info["simd"], info["simd_lanes"]) == _core.simd()
    assert isinstance(info["simd_compiled"], tuple) and info["simd"] in info["simd_compiled"]
    # the NumPy C API: built with NumPy 2's headers, for a NumPy no newer than the one running
    assert _version(str(info["numpy_headers"])) >= (2, 0)
    assert _version(str(info["numpy_minimum"])) <= _version(np.__version__)
    assert int(str(info["numpy_target_api"]), 16) <= int(str(info["numpy_api"]), 16)
    assert _version(str(info["python"])) == sys.version_info[:2]
    # featherdyn.jax's handler: built with jaxlib's headers where jaxlib has wheels (a build requirement there)
    if platform.machine().lower() in ("x86_64", "amd64", "aarch64", "arm64"):
        assert re.fullmatch(r"jaxlib \d+\.\d+\.\d+.*", str(info["jax_ffi"])), info["jax_ffi"]
        assert hasattr(_core, "jax_handler")


def test_x86_64_has_every_kernel_and_other_processors_the_portable_one() -> None:
    compiled = _core.build_info()["simd_compiled"]
    if platform.machine().lower() in ("x86_64", "amd64"):
        assert compiled == ("baseline", "avx2", "avx512")
    else:
        assert compiled == ("baseline",)


def _in_fresh_process(code: str, **env: str) -> str:
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                         env=dict(os.environ, **env))
    assert res.returncode == 0, res.stderr
    return res.stdout


def test_featherdyn_simd_baseline_forces_the_portable_kernels() -> None:
    out = _in_fresh_process("from featherdyn.core import _core; print(_core.build_info()['simd'], _core.simd()[1])",
                            FEATHERDYN_SIMD="baseline")
    assert out.split() == ["baseline", "2"]


def test_info_build_prints_the_build(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["info", "--build"]) == 0
    out = capsys.readouterr().out
    info = _core.build_info()
    assert out.startswith(f"featherdyn {fd.__version__} (")
    for text in (f"compiler: {info['compiler']}, {info['build_type']} build", f"SIMD: {info['simd']} × ",
                 f"NumPy C API: NumPy {info['numpy_headers']}'s headers", f"for NumPy >= {info['numpy_minimum']}",
                 f"nanobind {info['nanobind']}", f"NumPy {np.__version__}"):
        assert text in out, (text, out)


def test_info_without_a_robot_or_build_is_a_usage_error(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["info"]) == 2
    assert "give a ROBOT or URDF, or --build" in capsys.readouterr().err
