"""The contract every fuzzed case is held to, and the mutations that make the cases.

Every case must exit 0 or 2 (``vehicle check`` also 1: inconsistent findings); stderr holds only
``trikedyn: error: ...`` and ``trikedyn: warning: ...`` lines and no traceback; an error is one line (with
``one_line``, the *only* line: no warning before it); ``--json`` output is always valid JSON (no NaN or
Infinity); and nothing takes longer than :data:`LIMIT_S` (an alarm breaks a case that blocks, so a hang is a
failure, not a stuck run).
"""

from __future__ import annotations

import contextlib
import io
import signal
import time

from hypothesis import strategies as st

from trikedyn.cli import main

from ..conftest import strict_json

TOKENS = ["nan", "inf", "-inf", "1e308", "-1e308", "1e-300", "0", "-0", "-1", "99999999999999999999999999",
          "1e9", "''", '""', "[]", "{}", "true", "../../../../etc/passwd", "/etc/passwd", "\x00", "é", ",", "=",
          "\n", "[", "]", "#", '"', "0x1F", "1_000", "NaN", "$", "/dev/zero", "fifo.csv"]
LIMIT_S = 60.0
"""A case taking longer than this counts as a hang."""


class Hang(BaseException):
    """Raised by the alarm in a case that runs past :data:`LIMIT_S` (a BaseException: the CLI's error
    boundary does not turn it into an exit code)."""


@st.composite
def mutated(draw, seed: bytes) -> bytes:
    """``seed`` with 1-4 random edits: delete, duplicate or swap spans and lines, replace a byte, insert a
    troublesome token, truncate."""
    data = bytearray(seed)
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(st.sampled_from(["delete", "duplicate", "replace", "token", "truncate", "swap_lines"]))
        n = len(data)
        i = draw(st.integers(0, max(n - 1, 0)))
        j = min(n, i + draw(st.integers(1, 40)))
        if kind == "delete":
            del data[i:j]
        elif kind == "duplicate":
            data[i:i] = data[i:j]
        elif kind == "replace" and n:
            data[i] = draw(st.integers(0, 255))
        elif kind == "token":
            data[i:i] = draw(st.sampled_from(TOKENS)).encode("utf-8")
        elif kind == "truncate":
            del data[i:]
        elif kind == "swap_lines":
            lines = bytes(data).split(b"\n")
            if len(lines) > 2:
                a = draw(st.integers(0, len(lines) - 1))
                b = draw(st.integers(0, len(lines) - 1))
                lines[a], lines[b] = lines[b], lines[a]
                data = bytearray(b"\n".join(lines))
    return bytes(data)


def _alarm(signum, frame):  # noqa: ARG001
    raise Hang(f"over {LIMIT_S:g} s")


def run_cli(args: list[str]) -> tuple[int, str, str]:
    """``trikedyn ARGS`` in this process: exit code, stdout, stderr; a case past :data:`LIMIT_S` fails."""
    out, err = io.StringIO(), io.StringIO()
    start = time.perf_counter()
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, LIMIT_S + 5.0)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(args)
    except Hang:
        raise AssertionError(f"{args}: still running after {LIMIT_S + 5:g} s (a hang)") from None
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, previous)
    assert time.perf_counter() - start < LIMIT_S, f"{args}: took {time.perf_counter() - start:.0f} s"
    return code, out.getvalue(), err.getvalue()


def check_contract(args: list[str], *, one_line: bool = False) -> int:
    """Run ``trikedyn ARGS`` and assert the contract (module docstring); returns the exit code."""
    code, out, err = run_cli(args)
    ok = (0, 1, 2) if args[:2] == ["vehicle", "check"] else (0, 2)  # vehicle check: 1 = inconsistent findings
    assert code in ok, f"{args}: exit {code}\n{err[-3000:]}"
    lines = [line for line in err.splitlines() if line]
    assert all(line.startswith(("trikedyn: error: ", "trikedyn: warning: ")) for line in lines), err[-3000:]
    assert "Traceback" not in err
    if code == 2:
        assert sum(line.startswith("trikedyn: error: ") for line in lines) == 1, err
        if one_line:
            assert len(lines) == 1 and err.count("\n") == 1, f"{args}: more than the error line\n{err[-3000:]}"
    if "--json" in args:
        strict_json(out)
    return code
