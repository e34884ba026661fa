"""trikedyn._borrow: views without reference counts, for the compiled loops' hot paths."""

import numpy as np
import pytest
from numba import njit
from numba.core.errors import TypingError

from trikedyn._borrow import borrowed


@njit
def _row_sums_and_scale(stack, factor):
    """Each row's sum through a borrowed view, then each row scaled in place through one."""
    sums = np.empty(stack.shape[0])
    for i in range(stack.shape[0]):
        row = borrowed(stack[i])
        sums[i] = row.sum()
        for j in range(row.shape[0]):
            row[j] *= factor
    return sums


@njit
def _strided_column(stack, j):
    """Column ``j`` read through a borrowed (non-contiguous) view."""
    column = borrowed(stack[:, j])
    out = np.empty(column.shape[0])
    for i in range(column.shape[0]):
        out[i] = column[i]
    return out


def test_a_borrowed_view_reads_and_writes_the_arrays_memory():
    stack = np.arange(12.0).reshape(3, 4)
    sums = _row_sums_and_scale(stack, 2.0)
    assert np.array_equal(sums, [6.0, 22.0, 38.0])
    assert np.array_equal(stack, 2.0 * np.arange(12.0).reshape(3, 4))  # written through the views


def test_a_borrowed_view_keeps_shape_and_strides():
    stack = np.arange(12.0).reshape(3, 4)
    assert np.array_equal(_strided_column(stack, 2), stack[:, 2])


def test_only_arrays_can_be_borrowed():
    @njit
    def scalar(x):
        return borrowed(x)

    with pytest.raises(TypingError):
        scalar(1.0)
