"""featherdyn.testing: the dtype-aware tolerances and the comparison helper."""

from __future__ import annotations

import numpy as np
import pytest

from featherdyn.testing import assert_close, comparison_dtype, max_error, tolerance


def test_tolerance_by_dtype():
    assert tolerance(np.float64) == (1e-10, 1e-10)
    assert tolerance(np.float32) == (1e-4, 1e-4)
    assert tolerance(object) == tolerance(np.float64)
    assert tolerance(np.complex64) == tolerance(np.float32)
    assert tolerance(np.int64) == tolerance(np.float64)


def test_comparison_dtype_is_the_weaker_side():
    assert comparison_dtype(np.ones(2), np.ones(2, np.float32)) == np.float32
    assert comparison_dtype(np.ones(2), [1, 2]) == np.float64


def test_assert_close_passes_within_tolerance():
    assert_close(np.ones(3) + 1e-11, np.ones(3), "x")
    assert_close(np.float32(1.00005), 1.0, "x")  # float32 side: 1e-4
    assert_close([np.inf, -np.inf], [np.inf, -np.inf], "matching infinities")
    assert_close(np.zeros(0), np.zeros(0), "empty")


def test_assert_close_message_names_quantity_place_and_worst_index():
    actual = np.zeros((2, 3))
    actual[1, 2] = 0.5
    actual[0, 0] = 1e-3
    with pytest.raises(AssertionError) as info:
        assert_close(actual, np.zeros((2, 3)), "X* f", where="robot 'panda'")
    text = str(info.value)
    assert text.startswith("X* f (robot 'panda'):")
    assert "index (1, 2)" in text and "0.5" in text and "2 of 6 elements" in text and "float64" in text


def test_assert_close_is_strict_about_dtype_and_shape():
    with pytest.raises(AssertionError, match="float64"):
        assert_close(np.float64(1.00005), 1.0, "x")
    assert_close(np.float64(1.00005), 1.0, "x", dtype=np.float32)
    with pytest.raises(AssertionError, match=r"shape mismatch, actual \(3,\) vs expected \(1, 3\)"):
        assert_close(np.ones(3), np.ones((1, 3)), "x")
    with pytest.raises(AssertionError):
        assert_close([np.nan], [np.nan], "NaN never matches")
    with pytest.raises(AssertionError):
        assert_close([np.inf], [1.0], "inf vs finite")


def test_scale_widens_only_the_absolute_part():
    assert_close(5e-10, 0.0, "x", scale=10.0)
    with pytest.raises(AssertionError):
        assert_close(5e-10, 0.0, "x")


def test_max_error():
    assert max_error([1.0, 2.0, 3.0], [1.0, 2.5, 3.0]) == (0.5, (1,))
    assert max_error([1.0, np.nan], [1.0, 1.0]) == (np.inf, (1,))
    assert max_error([np.inf], [np.inf]) == (0.0, (0,))
