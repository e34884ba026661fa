"""``wt901sd-binary``: raw 11-byte 0x55 WIT frames as the WT901SD logger writes them to its card."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ...errors import LogFormatError
from .._log_tables import _DEG, _G, _assemble, _one_sensor
from ..clocktime import clock_fields, seconds
from ..imu_log import CHANNELS, TEMP, TIME, ImuLog
from .base import LogFormat, ReadOptions, register

_BIN_SCALE = {0x51: 16.0 / 32768 * _G, 0x52: 2000.0 / 32768 * _DEG, 0x53: 180.0 / 32768 * _DEG}
_BIN_CHANNELS = {0x51: CHANNELS[0:3], 0x52: CHANNELS[3:6], 0x53: CHANNELS[6:9],
                 0x54: ("magx", "magy", "magz")}


def _valid_starts(b: np.ndarray) -> np.ndarray:
    """For every offset, whether a frame with a WIT type (0x50-0x5F) and a good checksum starts there."""
    m = b.size - 10
    if m <= 0:
        return np.zeros(0, bool)
    c = np.concatenate([[0], np.cumsum(b, dtype=np.int64)])
    return (b[:m] == 0x55) & ((b[1:m + 1] & 0xF0) == 0x50) & (((c[10:10 + m] - c[:m]) & 0xFF) == b[10:10 + m])


def _scan_frames(b: np.ndarray, path: Path, notes: list[str]) -> np.ndarray:
    """Offsets of the good frames; after a bad one, skip to the next valid 0x55 and count the frames lost."""
    ok = _valid_starts(b)
    valid = np.flatnonzero(ok)
    starts, pos, bad, first_bad = [], 0, 0, None
    while pos <= b.size - 11:
        run = ok[pos::11][:4096]  # a run of good frames, taken in blocks
        good = run.size if run.all() else int(np.argmin(run))
        if good:
            starts.append(np.arange(pos, pos + 11 * good, 11))
            pos += 11 * good
            continue
        k = np.searchsorted(valid, pos)
        nxt = int(valid[k]) if k < valid.size else b.size
        first_bad = pos if first_bad is None else first_bad
        bad += max(1, round((nxt - pos) / 11))
        pos = nxt
    starts = np.concatenate(starts) if starts else np.zeros(0, np.int64)
    if bad > 0.1 * (starts.size + bad):
        raise LogFormatError(f"{bad} of about {starts.size + bad} frames are bad (more than 10 %); expected "
                             "11-byte frames: 0x55, type, 8 data bytes, checksum = low byte of the sum "
                             "of the first 10", where=f"{path}: byte {first_bad}")
    if bad:
        notes.append(f"skipped {bad} bad frame(s) (checksum or sync), the first at byte {first_bad}")
    if pos < b.size:
        notes.append(f"ignored {b.size - pos} byte(s) at the end of the file (a partial frame)")
    return starts

def _read_binary(raw: bytes, path: Path, rate: float | None, notes: list[str]) -> ImuLog:
    b = np.frombuffer(raw, np.uint8)
    starts = _scan_frames(b, path, notes)
    frames = b[starts[:, None] + np.arange(11)] if starts.size else np.zeros((0, 11), np.uint8)
    types = frames[:, 1]
    sid = np.cumsum(types == 0x51) - 1
    sid[:-1] += (types[:-1] == 0x50) & (types[1:] == 0x51)  # a chip time right before 0x51 is that sample's
    n = int((types == 0x51).sum())
    if n == 0:
        raise LogFormatError("no complete sample: no 0x51 acceleration frame; expected WT901SD frames",
                             where=f"{path}: byte 0")
    words = np.ascontiguousarray(frames[:, 2:10]).view("<i2").astype(float)
    cols, original, have = {}, {}, np.ones(n, bool)
    key, counts = np.unique(sid[sid >= 0] * 256 + types[sid >= 0], return_counts=True)
    have[key[counts > 1] // 256] = False  # a type twice in one sample: its 0x51 was lost; do not mix samples
    for typ, names in _BIN_CHANNELS.items():
        sel = (types == typ) & (sid >= 0)
        if sel.any():
            arr = np.full((n, 4), np.nan)
            arr[sid[sel]] = words[sel]
            have &= ~np.isnan(arr[:, 0]) | (typ == 0x54)  # the magnetometer is an extra a sample may lack
            cols |= {name: arr[:, k] * _BIN_SCALE.get(typ, 1.0) for k, name in enumerate(names)}
            original |= {name: f"0x{typ:02X} word {k}" for k, name in enumerate(names)}
            if typ == 0x51:
                cols[TEMP], original[TEMP] = arr[:, 3] / 100.0, "0x51 word 3"
    sel = (types == 0x50) & (sid >= 0)
    fields = np.full((n, 7), np.nan)
    if sel.any():
        fields[sid[sel]] = np.column_stack([frames[sel, 2:8], frames[sel, 8] + 256.0 * frames[sel, 9]])
        have &= ~np.isnan(fields[:, 0])
    if not have.all():
        notes.append(f"dropped {int((~have).sum())} incomplete sample(s) (a frame missing or repeated)")
    if not have.any():
        raise LogFormatError("no complete sample: every sample misses a frame", where=f"{path}: byte 0")
    locs, cols = starts[types == 0x51][have], {k: v[have] for k, v in cols.items()}
    if sel.any():
        f = fields[have]
        t, _ = seconds(f[:, :3] + [2000, 0, 0], f[:, 3:6], f[:, 6] / 1000.0)
        if np.isnan(t).any():  # a chip whose date was never set: use the clock alone
            t, wraps = seconds(None, f[:, 3:6], f[:, 6] / 1000.0)
            notes.append(f"0x50 chip-time dates are not valid; used the clock alone ({wraps} midnight(s))")
        bad = np.flatnonzero(np.isnan(t))
        if bad.size:
            raise LogFormatError("0x50 chip time is not a valid clock; expected hh < 24, mm < 60, ss < 60",
                                 where=f"{path}: byte {locs[bad[0]]}")
        original[TIME] = "0x50 chip time"
    else:
        t = np.arange(have.sum()) / (rate or 10.0)
        notes.append(f"the file stores no time (no 0x50 frames): time built from sample_rate_hz="
                     f"{rate or 10.0:g}" + ("" if rate else " (assumed: pass sample_rate_hz= to set it)"))
    return _assemble(path, "wt901sd-binary", t, locs, cols, original, notes, binary=True)


def _write_binary(data: pd.DataFrame, path: Path) -> None:
    n = len(data)
    f = clock_fields(data[TIME].to_numpy(float), path, "wt901sd-binary")
    temp = np.round(data[TEMP].to_numpy(float) * 100) if TEMP in data else np.zeros(n)
    ms = f["ms"].to_numpy()
    payloads = {0x50: np.column_stack([f["year"] - 2000, f["month"], f["day"], f["hour"], f["minute"],
                                       f["second"], ms & 0xFF, ms >> 8]).astype(np.uint8)}
    for typ, names in _BIN_CHANNELS.items():
        present = [c for c in names if c in data]
        if len(present) < (3 if typ == 0x51 else 1 if present else 0) or 0 < len(present) < 3:
            raise LogFormatError(f"format 'wt901sd-binary' stores {', '.join(names)} together (and needs the "
                                 f"0x51 acceleration); the log has {', '.join(present) or 'none'}",
                                 where=str(path))
        if present:
            scale = _BIN_SCALE.get(typ, 1.0)
            raw = np.column_stack([np.round(data[c].to_numpy(float) / scale) for c in names])
            raw = (raw + 32768) % 65536 - 32768 if typ == 0x53 else raw  # angles wrap at +-180 deg
            raw = np.column_stack([raw, temp])
            if (np.abs(raw + 0.5) > 32768).any() or np.isnan(raw).any():
                raise LogFormatError(f"a value of {', '.join(names)} or {TEMP} is outside the int16 range of "
                                     "format 'wt901sd-binary'", where=str(path))
            payloads[typ] = raw.astype("<i2").view(np.uint8).reshape(n, 8)
    frames = np.zeros((n, len(payloads), 11), np.uint8)
    for k, (typ, payload) in enumerate(payloads.items()):
        frames[:, k, 0], frames[:, k, 1], frames[:, k, 2:10] = 0x55, typ, payload
        frames[:, k, 10] = frames[:, k, :10].sum(axis=1, dtype=np.int64) & 0xFF
    path.write_bytes(frames.tobytes())


class Wt901sdBinary(LogFormat):
    """Raw 11-byte 0x55 WIT frames as the WT901SD logger writes them to its card (see the module docstring)."""

    name = "wt901sd-binary"
    description = "raw 11-byte 0x55 WIT frames as the WT901SD logger writes them to its card"
    order = 40

    def sniff(self, head):
        """100 when the file starts with valid WIT frames (0x55, a WIT type, a good checksum) at its first (up to
        four) 11-byte steps, else 0.

        Parameters
        ----------
        head : Head
            The file's first bytes.

        Returns
        -------
        float
            The score.
        """
        ok = _valid_starts(np.frombuffer(head.raw, np.uint8))
        fits = head.raw[:1] == b"\x55" and ok.size and all(ok[i] for i in range(0, min(ok.size, 34), 11))
        return 100.0 if fits else 0.0

    def read(self, raw: bytes, path: Path, options: ReadOptions) -> ImuLog:
        """The frames as an :class:`~trikedyn.measure.logs.ImuLog`: a sample per 0x51 acceleration frame, time
        from the 0x50 chip time, or from ``options.sample_rate_hz`` [Hz] (10 if not given) without it.

        Parameters
        ----------
        raw : bytes
            The file's bytes.
        path : Path
            The file, for errors.
        options : ReadOptions
            What the caller asked for (sensor, rate [Hz], columns, units, ...).

        Returns
        -------
        ImuLog
            The log, SI columns (time [s], accelerations [m/s^2], rates [rad/s], angles [rad]).
        """
        _one_sensor(options.sensor, self.name, path)
        return _read_binary(raw, path, options.sample_rate_hz, [])

    def write(self, data: pd.DataFrame, path: Path) -> None:
        """The SI columns as frames, one set per sample: 0x50 chip time, 0x51 accelerations (required), 0x52
        rates, 0x53 angles and 0x54 magnetometer (each group whole or absent), temperature in each.

        Parameters
        ----------
        data : pandas.DataFrame
            SI columns (``time_s`` [s] increasing, ...).
        path : Path
            The file to write.
        """
        _write_binary(data, path)


register(Wt901sdBinary())
