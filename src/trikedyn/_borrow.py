"""Array views that do not count references, for the compiled loops' hot paths.

numba counts the references to every array it holds: taking a view (``stack[lane]``, ``x[:n]``) increments
the count of the array's memory and dropping it decrements it, each an atomic instruction (``lock incq``). LLVM's
reference-count pruning removes such pairs within simple code, but few in a function as branchy as a
lockstep batch's stage, which takes a dozen views of each lane's rows for every right-hand side: in the lane
batch, ``NRT_incref``/``NRT_decref`` were 12 % of a ``perf`` profile (``benchmarks/batch.py``'s closed-loop
runs).

:func:`borrowed` returns the same view without an owner: its memory-info pointer is null, so numba's
reference counting skips it (a test and a branch, no atomic instruction). The view is valid while the array
it was taken from lives; use it only for a view of an array that outlives it (a workspace or a record the
loop owns), never return it or store it.
"""

from __future__ import annotations

from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

__all__ = ["borrowed"]


@intrinsic
def borrowed(typingctx, array):
    """``array`` as a view that holds no reference to its memory (see the module docstring).

    Parameters
    ----------
    array : numpy.ndarray
        A view, of any shape and layout, of an array that outlives the result.

    Returns
    -------
    numpy.ndarray
        The same view (data, shape, strides), without an owner.
    """
    if not isinstance(array, types.Array):
        return None

    def codegen(context, builder, signature, args):
        """The view's struct: the source's data, shape and strides, a null owner."""
        source = context.make_array(signature.args[0])(context, builder, value=args[0])
        view = context.make_array(signature.return_type)(context, builder)
        view.meminfo = cgutils.get_null_value(view.meminfo.type)
        view.parent = cgutils.get_null_value(view.parent.type)
        view.nitems = source.nitems
        view.itemsize = source.itemsize
        view.data = source.data
        view.shape = source.shape
        view.strides = source.strides
        return view._getvalue()

    return array(array), codegen
