"""Measurement logs: read a CSV or Parquet time series, check it, and hold it in SI units.

:func:`load_log` reads a file with a declared :class:`~ship_env.workbench.logs.formats.LogFormat`
(or the built-in one whose columns the file has), converts every channel to SI units and radians
and checks what would otherwise give silently wrong fits. Each problem is an error that names the
file, the column and the offending value:

- a declared column that is missing, or holds text;
- time that repeats or goes back;
- NaN: trailing NaN rows (a logger left running) are cut with a warning, a NaN gap inside the
  log or at its start is an error;
- an angle declared in radians that exceeds 2 pi (it looks like degrees), or a heading whose
  derivative is ~57 times the rate of turn;
- a heading wrapped to +-180 deg or 0..360 deg is unwrapped (and the log says so in its notes);
- a sample beyond a physical limit of its channel, for any ship from a model to a tanker (a speed
  above ``MAX_SPEED``, a rate of turn above ``MAX_RATE_OF_TURN``, a wind above ``MAX_WIND_SPEED``,
  a position that moves between two samples by more than ``MAX_SPEED`` allows plus
  ``POSITION_TOLERANCE``) is an error naming its row; a sample of the ship's motion (heading, rate
  of turn, position, speed: its inertia keeps them continuous) that is possible but jumps away from
  both its neighbours and back (a spike: both changes beyond ``OUTLIER_DEVIATIONS`` robust standard
  deviations of the channel's own sample-to-sample changes, in opposite directions) is a warning
  naming its row. A manoeuvre changes the motion smoothly, never out and back in one sample, so it
  does not warn; the inputs (rudder, propeller, wind) may step by nature and are not checked for spikes.

The user's file is only read, never written.
"""

from __future__ import annotations

import difflib
import functools
import math
import warnings
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import pandas as pd

from ship_env.workbench.logs.channel_smoother import smoothed_rate
from ship_env.workbench.logs.formats import (
    CHANNELS,
    FormatError,
    LogFormat,
    detect_format,
    resolve_format,
)

#: The loader's readers by file ending; a CSV's numbers read exactly as written (pandas' default parser may be
#: a unit in the last place off, and ``write_log`` writes the shortest text that reads back exactly).
READERS = {
    ".csv": functools.partial(pd.read_csv, float_precision="round_trip"),
    ".parquet": pd.read_parquet,
    ".pq": pd.read_parquet,
}
#: No ship turns faster than this, rad/s; a heading in "rad" that seems to is in degrees.
MAX_PLAUSIBLE_RATE = 1.0
#: Fewest samples a log must keep.
MIN_SAMPLES = 10
#: No ship sails faster than this through the water or over the ground, m/s (about 97 kn).
MAX_SPEED = 50.0
#: No ship turns faster than this, rad/s: a rate of turn beyond it is not a measurement.
MAX_RATE_OF_TURN = 3.0
#: No true wind at sea blows harder than this, m/s.
MAX_WIND_SPEED = 120.0
#: A position fix may err by this much, m, beyond what the ship's largest speed moves it between samples.
POSITION_TOLERANCE = 50.0
#: Robust standard deviations (1.4826 MAD) of a channel's sample-to-sample change beyond which a spike warns
#: (the Esso Osaka model tests' speed channel dips by up to 33 for one sample and back).
OUTLIER_DEVIATIONS = 50.0
#: Noise standard deviations within which a log's median true wind is calm air (:attr:`Log.has_wind_beyond_noise`):
#: a wind the anemometer's own scatter could make, which no wind effect can be fitted on.
CALM_AIR_DEVIATIONS = 3.0
#: The channels of the ship's motion, which its inertia keeps continuous: a spike in them is an outlier.
CONTINUOUS_CHANNELS = ("heading", "rate_of_turn", "north", "east", "speed")


class LogError(ValueError):
    """A log that cannot be used as it is; the message names the file, the column and the value."""


class LogWarning(UserWarning):
    """Something the loader changed in its copy of a log (trailing NaN rows cut)."""


@dataclass(frozen=True)
class Log:
    """One measured run in SI units and radians; absent channels are ``None``.

    Attributes:
        name: the run's name (the file's stem).
        time: sample times, s, strictly increasing (as in the file).
        heading: heading psi, rad, unwrapped (continuous through whole turns).
        rudder: rudder angle, rad; see ``rudder_kind``.
        rudder_kind: ``"actual"`` or ``"ordered"`` (the order a steering machine follows).
        rate_of_turn: r, rad/s.
        north, east: position x0, y0, m.
        speed: forward speed through the water u, m/s.
        propeller_rate: n, rps.
        wind_speed, wind_direction: true wind, m/s, and where it comes from, rad from north.
        service_speed: U0, m/s, the run's straight-course speed where known: for a log without a speed channel
            the speed it sails at (``None``: the ship's); beside a speed channel, the speed the ship
            accelerates towards (``None``: estimated from the speed, ``replay.service_speed``).
        source: the file it was read from.
        notes: what the loader changed or noticed.
    """

    name: str
    time: np.ndarray
    heading: np.ndarray
    rudder: np.ndarray
    rudder_kind: str = "actual"
    rate_of_turn: np.ndarray | None = None
    north: np.ndarray | None = None
    east: np.ndarray | None = None
    speed: np.ndarray | None = None
    propeller_rate: np.ndarray | None = None
    wind_speed: np.ndarray | None = None
    wind_direction: np.ndarray | None = None
    service_speed: float | None = None
    source: str = ""
    notes: tuple[str, ...] = field(default_factory=tuple)
    _rate_of_turn: np.ndarray = field(init=False, repr=False, compare=False)  # rate_of_turn_or_smoothed

    def __post_init__(self) -> None:
        count = len(self.time)
        for name in CHANNELS:
            values = getattr(self, name)
            if values is None:
                continue
            if values.shape != (count,) or not np.all(np.isfinite(values)):
                raise LogError(f"log {self.name!r}: channel {name!r} must be {count} finite values")
        if count < MIN_SAMPLES or np.any(np.diff(self.time) <= 0.0):
            raise LogError(f"log {self.name!r}: time must hold at least {MIN_SAMPLES} increasing samples")
        # Smoothed here, once, not on first use: a log must not change while a worker's pickler reads it.
        rate = smoothed_rate(self.time, self.heading) if self.rate_of_turn is None else self.rate_of_turn
        object.__setattr__(self, "_rate_of_turn", rate)

    @property
    def samples(self) -> int:
        return len(self.time)

    @property
    def duration(self) -> float:
        return float(self.time[-1] - self.time[0])

    @property
    def rate_of_turn_or_smoothed(self) -> np.ndarray:
        """The measured rate of turn, rad/s, or where the log has none the heading's rate smoothed as the heading's
        own noise asks (:func:`~ship_env.workbench.logs.channel_smoother.smoothed_rate`): a compass of 0.5 deg read
        every second makes the plain derivative's noise 0.35 deg/s, a tanker's whole rate in a zig-zag."""
        return self._rate_of_turn

    @property
    def has_position(self) -> bool:
        return self.north is not None

    @property
    def has_wind(self) -> bool:
        return self.wind_speed is not None

    @property
    def has_wind_beyond_noise(self) -> bool:
        """Whether the log's true wind blows: its median speed exceeds ``CALM_AIR_DEVIATIONS`` times the
        anemometer's noise, estimated from the sample-to-sample changes (white noise e_i of deviation s makes
        changes of deviation sqrt(2) s, read robustly by :func:`change_scale`). A calm basin logged through a
        noisy anemometer reads a wind of a few hundredths of the noise's size at its median; a wind effect fitted
        there would fit the ship's own motion through still air instead."""
        if self.wind_speed is None:
            return False
        noise = change_scale(np.diff(self.wind_speed)) / math.sqrt(2.0)
        return float(np.median(self.wind_speed)) > CALM_AIR_DEVIATIONS * noise

    def channels(self) -> list[str]:
        """The names of the channels this log has."""
        return [name for name in CHANNELS if getattr(self, name) is not None]

    def to_frame(self) -> pd.DataFrame:
        """The log as a table in the standard format (channel names as headers, SI units)."""
        return pd.DataFrame({name: getattr(self, name) for name in self.channels()})

    def with_notes(self, *notes: str) -> Log:
        return replace(self, notes=self.notes + notes)


def _read_table(path: Path) -> pd.DataFrame:
    reader = READERS.get(path.suffix.lower())
    if not path.exists():
        raise LogError(f"{path}: no such file or folder" if reader is None else f"{path}: no such file")
    if reader is None:
        raise LogError(f"{path}: cannot read {path.suffix or 'files without an ending'}; use {', '.join(READERS)}")
    if not path.is_file():
        raise LogError(f"{path}: not a file")
    try:
        return reader(path)
    except (ValueError, OSError, ImportError) as error:
        raise LogError(f"{path}: cannot read it as {path.suffix[1:]}: {error}") from None


def _check_columns(frame: pd.DataFrame, fmt: LogFormat, source: str) -> dict[str, str]:
    """channel -> column header for the channels present; a LogError for a missing declared column."""
    headers = [str(header) for header in frame.columns]
    used: dict[str, str] = {}
    missing = []
    for channel, column in fmt.columns.items():
        if column.name in headers:
            used[channel] = column.name
        elif not column.optional:
            close = difflib.get_close_matches(column.name, headers, n=1, cutoff=0.5)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            missing.append(f"{column.name!r} ({channel}){hint}")
    if missing:
        raise LogError(
            f"{source}: missing column{'s' * (len(missing) > 1)} {', '.join(missing)}; the file has {headers}"
        )
    return used


def _numeric(frame: pd.DataFrame, used: dict[str, str], source: str) -> pd.DataFrame:
    """The used columns as floats; a LogError naming the first value that is not a number."""
    table = pd.DataFrame(index=frame.index)
    for channel, header in used.items():
        values = pd.to_numeric(frame[header], errors="coerce")
        bad = values.isna() & frame[header].notna()
        if bad.any():
            row = int(np.flatnonzero(bad.to_numpy())[0])
            raise LogError(
                f"{source}: column {header!r} ({channel}) holds {frame[header].iloc[row]!r} at row {row + 1}, "
                "not a number"
            )
        table[channel] = values.astype(float)
    return table.reset_index(drop=True)


def _trim_nan(table: pd.DataFrame, used: dict[str, str], source: str) -> tuple[pd.DataFrame, list[str]]:
    """Cut trailing rows with NaN (warning); a LogError for NaN at the start or inside."""
    finite = np.isfinite(table.to_numpy())
    good_rows = np.flatnonzero(finite.all(axis=1))
    if len(good_rows) == 0:
        raise LogError(f"{source}: every row has NaN in one of the columns {sorted(used.values())}")
    last = int(good_rows[-1])
    inside = ~finite[: last + 1]
    if inside.any():
        row, column = (int(i) for i in np.argwhere(inside)[0])
        channel = table.columns[column]
        stop = row
        while stop + 1 <= last and not finite[stop + 1, column]:
            stop += 1
        where = "at the start" if row == 0 else "inside the log"
        times = table["time"].to_numpy()
        span = f"t = {times[row]:g}..{times[stop]:g} s" if np.isfinite(times[[row, stop]]).all() else "time unknown"
        raise LogError(
            f"{source}: column {used[channel]!r} ({channel}) is NaN at rows {row + 1}..{stop + 1} ({span}) {where}; "
            f"fill the gap or cut the log there"
        )
    notes = []
    dropped = len(table) - last - 1
    if dropped:
        columns = sorted(used[c] for c in table.columns[~finite[last + 1 :].all(axis=0)])
        message = f"dropped the last {dropped} rows: NaN in {', '.join(map(repr, columns))}"
        warnings.warn(f"{source}: {message}", LogWarning, stacklevel=4)
        notes.append(message)
    return table.iloc[: last + 1], notes


def _check_time(time: np.ndarray, header: str, source: str) -> None:
    steps = np.diff(time)
    bad = np.flatnonzero(steps <= 0.0)
    if len(bad):
        row = int(bad[0])
        verb = "repeats" if steps[row] == 0.0 else "goes back"
        raise LogError(
            f"{source}: time column {header!r} {verb} at row {row + 2}: t = {time[row + 1]:g} after {time[row]:g}; "
            f"the time must increase"
        )


def _check_radians(values: np.ndarray, channel: str, header: str, source: str) -> None:
    largest = float(np.max(np.abs(values)))
    if largest > 2.0 * math.pi:
        raise LogError(
            f"{source}: column {header!r} ({channel}) is declared in rad but reaches {largest:g}, beyond 2 pi: "
            f"it looks like degrees; declare its unit as deg"
        )


def _unwrap_heading(
    heading: np.ndarray, time: np.ndarray, header: str, degrees_hint: bool, source: str
) -> tuple[np.ndarray, list[str]]:
    """The heading unwrapped, after checking that a heading in "rad" is not in degrees."""
    steps = np.diff(heading)
    jumps = np.abs(steps) > math.pi
    smooth = np.abs(steps[~jumps]) / np.diff(time)[~jumps]
    apparent_rate = float(np.percentile(smooth, 99)) if len(smooth) else 0.0
    if (
        degrees_hint
        and np.max(np.abs(heading)) > 2.0 * math.pi
        and (apparent_rate > MAX_PLAUSIBLE_RATE or np.any(np.abs(np.abs(steps[jumps]) - 360.0) < 30.0))
    ):
        raise LogError(
            f"{source}: column {header!r} (heading) is declared in rad but reaches {np.max(np.abs(heading)):g} "
            f"and turns at {apparent_rate:g} rad/s: it looks like degrees; declare its unit as deg"
        )
    if not jumps.any():
        return heading, []
    return np.unwrap(heading), [f"heading was wrapped: unwrapped {int(jumps.sum())} jumps of 2 pi"]


#: The channels with a physical limit on their value (SI units): channel -> (largest magnitude, what it is).
_VALUE_LIMITS: dict[str, tuple[float, str]] = {
    "speed": (MAX_SPEED, f"{MAX_SPEED:g} m/s, faster than any ship"),
    "rate_of_turn": (MAX_RATE_OF_TURN, f"{MAX_RATE_OF_TURN:g} rad/s, faster than any ship turns"),
    "wind_speed": (MAX_WIND_SPEED, f"{MAX_WIND_SPEED:g} m/s, harder than any wind at sea"),
}


def _check_limits(values: dict[str, np.ndarray], table: pd.DataFrame, used: dict[str, str], source: str) -> None:
    """A LogError for the first sample beyond a physical limit of its channel (see the module's docstring)."""
    for channel, (limit, what) in _VALUE_LIMITS.items():
        if channel in values:
            beyond = np.flatnonzero(np.abs(values[channel]) > limit)
            if len(beyond):
                row = int(beyond[0])
                raise LogError(
                    f"{source}: column {used[channel]!r} ({channel}) holds {table[channel].iloc[row]:g} at row "
                    f"{row + 1}, beyond {what}; correct or remove the sample"
                )
    steps = np.diff(values["time"])
    for channel in ("north", "east"):
        if channel in values:
            allowed = MAX_SPEED * steps + POSITION_TOLERANCE
            beyond = np.flatnonzero(np.abs(np.diff(values[channel])) > allowed)
            if len(beyond):
                row = int(beyond[0]) + 1
                raw = table[channel]
                raise LogError(
                    f"{source}: column {used[channel]!r} ({channel}) jumps from {raw.iloc[row - 1]:g} to "
                    f"{raw.iloc[row]:g} at row {row + 1} in {steps[row - 1]:g} s, farther than any ship sails "
                    f"({MAX_SPEED:g} m/s, and {POSITION_TOLERANCE:g} m for the fix); correct or remove the sample"
                )


def change_scale(changes: np.ndarray) -> float:
    """The robust standard deviation 1.4826 median |d - m| of a channel's changes d about their median m."""
    return 1.4826 * float(np.median(np.abs(changes - np.median(changes))))


def _spikes(values: np.ndarray) -> np.ndarray:
    """Indices of the samples that jump away from both neighbours and back (see ``OUTLIER_DEVIATIONS``).

    The changes d_i = x_(i+1) - x_i are measured against their median m and robust standard deviation
    s = 1.4826 median |d - m|, but not below the channel's resolution (its smallest change): sample i is
    a spike where d_(i-1) - m and d_i - m both exceed ``OUTLIER_DEVIATIONS`` s and differ in sign.
    """
    changes = np.diff(values)
    if len(changes) < 2 or not np.any(changes):
        return np.zeros(0, dtype=int)
    deviations = changes - np.median(changes)
    resolution = float(np.min(np.abs(changes[changes != 0.0])))
    scale = max(change_scale(changes), resolution)
    before, after = deviations[:-1], deviations[1:]
    spikes = (np.abs(before) > OUTLIER_DEVIATIONS * scale) & (np.abs(after) > OUTLIER_DEVIATIONS * scale)
    return np.flatnonzero(spikes & (np.sign(before) != np.sign(after))) + 1


def _warn_spikes(values: dict[str, np.ndarray], table: pd.DataFrame, used: dict[str, str], source: str) -> list[str]:
    """A LogWarning (and a note) per channel with spikes, naming the first one's row and value."""
    notes = []
    for channel in (name for name in CONTINUOUS_CHANNELS if name in values):
        rows = _spikes(values[channel])
        if len(rows):
            row = int(rows[0])
            raw = table[channel]
            others = f" and {len(rows) - 1} more" if len(rows) > 1 else ""
            message = (
                f"column {used[channel]!r} ({channel}) jumps to {raw.iloc[row]:g} at row {row + 1} and back "
                f"(from {raw.iloc[row - 1]:g}, then {raw.iloc[row + 1]:g}){others}: an outlier? check the sample"
            )
            warnings.warn(f"{source}: {message}", LogWarning, stacklevel=4)
            notes.append(message)
    return notes


def _check_rate_against_heading(log: Log, fmt: LogFormat, source: str) -> None:
    """A LogError when the heading's derivative and the rate of turn differ by a unit factor."""
    rate = log.rate_of_turn
    if rate is None or np.std(rate) == 0.0:
        return
    derivative = np.gradient(log.heading, log.time)
    ratio = float(np.dot(derivative, rate) / np.dot(rate, rate))
    if not 0.2 < abs(ratio) < 5.0:
        raise LogError(
            f"{source}: the heading {fmt.columns['heading'].name!r} changes {ratio:.3g} times as fast as the rate of "
            f"turn {fmt.columns['rate_of_turn'].name!r} says (57.3 or 1/57.3: one of them is in degrees); "
            "check their units"
        )


def log_from_frame(
    frame: pd.DataFrame,
    fmt: str | Path | LogFormat | None = None,
    name: str = "log",
    source: str | None = None,
    service_speed: float | None = None,
) -> Log:
    """Check a table and convert it to a :class:`Log` (see the module's docstring for the checks).

    Args:
        frame: the table as read; it is not modified.
        fmt: the log format (a built-in name, a YAML path or a LogFormat); ``None`` detects it.
        name: the run's name.
        source: what error messages call the table (the file path).
        service_speed: U0 in m/s for a log without a speed channel.
    """
    source = source or name
    try:
        fmt = detect_format(map(str, frame.columns), source) if fmt is None else resolve_format(fmt)
    except FormatError as error:
        raise LogError(str(error)) from None
    used = _check_columns(frame, fmt, source)
    table, notes = _trim_nan(_numeric(frame, used, source), used, source)
    if len(table) < MIN_SAMPLES:
        raise LogError(f"{source}: only {len(table)} usable rows; a log needs at least {MIN_SAMPLES}")
    values = {channel: table[channel].to_numpy() * fmt.factor(channel) for channel in used}
    _check_time(values["time"], used["time"], source)
    for channel in ("rudder", "wind_direction"):
        if channel in values and fmt.columns[channel].unit == "rad":
            _check_radians(values[channel], channel, used[channel], source)
    values["heading"], unwrap_notes = _unwrap_heading(
        values["heading"], values["time"], used["heading"], fmt.columns["heading"].unit == "rad", source
    )
    _check_limits(values, table, used, source)
    spike_notes = _warn_spikes(values, table, used, source)
    log = Log(
        name=name,
        rudder_kind=fmt.rudder_kind,
        service_speed=service_speed,
        source=source,
        notes=tuple(notes + unwrap_notes + spike_notes),
        **values,
    )
    _check_rate_against_heading(log, fmt, source)
    return log


def load_log(
    path: str | Path,
    fmt: str | Path | LogFormat | None = None,
    service_speed: float | None = None,
) -> Log:
    """Read one CSV or Parquet log (read only) and check it; see :func:`log_from_frame`."""
    path = Path(path)
    return log_from_frame(_read_table(path), fmt, name=path.stem, source=str(path), service_speed=service_speed)


def every_nth(log: Log, step: int) -> Log:
    """The log with every ``step``-th sample: a coarser replay step, for faster fits."""
    if step < 1:
        raise LogError(f"log {log.name!r}: the sample step must be a positive whole number, got {step!r}")
    if step == 1:
        return log
    kept = {name: getattr(log, name)[::step] for name in log.channels()}
    return replace(log, notes=log.notes + (f"every {step}th sample used",), **kept)


def _folders_of_logs(folder: Path) -> str:
    """The sentence naming ``folder``'s subfolders that hold logs, to pass instead (empty where none)."""
    holding = sorted(
        sub for sub in folder.iterdir() if sub.is_dir() and any(p.suffix.lower() in READERS for p in sub.iterdir())
    )
    if not holding:
        return ""
    return (
        f"; its folders {', '.join(sub.name for sub in holding)} hold logs: pass one or several of them "
        f"(say {holding[0]})"
    )


def log_paths(paths: Iterable[str | Path]) -> list[Path]:
    """Files named, and the readable files inside folders named, sorted per folder."""
    found: list[Path] = []
    for item in map(Path, paths):
        if item.is_dir():
            inside = sorted(p for p in item.iterdir() if p.suffix.lower() in READERS)
            if not inside:
                raise LogError(f"{item}: no {', '.join(READERS)} files in this folder{_folders_of_logs(item)}")
            found.extend(inside)
        else:
            found.append(item)
    return found


def load_logs(
    paths: Sequence[str | Path],
    fmt: str | Path | LogFormat | None = None,
    service_speed: float | None = None,
) -> list[Log]:
    """Read several logs (files or folders of them); names must be unique."""
    logs = [load_log(path, fmt, service_speed) for path in log_paths(paths)]
    names = [log.name for log in logs]
    repeated = sorted({n for n in names if names.count(n) > 1})
    if repeated:
        raise LogError(f"logs: the run names {repeated} repeat; give each file its own name")
    return logs


def write_log(log: Log, path: str | Path) -> Path:
    """Write a log in the standard format (CSV or Parquet by the path's ending)."""
    path = Path(path)
    frame = log.to_frame()
    if path.suffix.lower() == ".csv":
        frame.to_csv(path, index=False)
    elif path.suffix.lower() in (".parquet", ".pq"):
        frame.to_parquet(path, index=False)
    else:
        raise LogError(f"{path}: write .csv or .parquet")
    return path


__all__ = [
    "Log",
    "LogError",
    "LogWarning",
    "every_nth",
    "load_log",
    "load_logs",
    "log_from_frame",
    "log_paths",
    "write_log",
]
