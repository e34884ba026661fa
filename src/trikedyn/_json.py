"""JSON that is always valid: non-finite numbers made null (and where), numpy values and paths made plain."""

from __future__ import annotations

from pathlib import Path

__all__ = ["finite", "json_default"]


def json_default(obj):
    """``json.dumps``' ``default``: numpy arrays and scalars as lists and numbers, paths as text."""
    import numpy as np

    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def finite(node, path: str = ""):
    """``node`` with every non-finite float replaced by None, and the paths where that happened."""
    import math

    if isinstance(node, dict):
        out, bad = {}, []
        for key, value in node.items():
            out[key], sub = finite(value, f"{path}.{key}" if path else str(key))
            bad += sub
        return out, bad
    if isinstance(node, list | tuple):
        out, bad = [], []
        for i, value in enumerate(node):
            item, sub = finite(value, f"{path}[{i}]")
            out.append(item)
            bad += sub
        return out, bad
    if hasattr(node, "tolist") and not isinstance(node, str):  # numpy arrays and scalars
        return finite(node.tolist(), path)
    if isinstance(node, float) and not math.isfinite(node):
        return None, [path]
    return node, []
