"""Log formats: which column of a measurement file holds which signal, and in which unit.

A :class:`LogFormat` maps the workbench's channels (``time``, ``heading``, ``rudder``...) to the
columns of a CSV or Parquet file and declares each column's unit; the loader converts everything
to SI units and radians. Formats are written in Python or in YAML::

    name: my_trial
    rudder_kind: actual          # the log records the actual rudder (or: ordered)
    columns:
      time: {column: "Time", unit: s}
      heading: {column: "HDG", unit: deg}
      rudder: {column: "Rudder", unit: deg, sign: -1}   # this log counts port rudder positive
      speed: {column: "STW", unit: kn}

Built in: ``esso_osaka`` (the FRT-DS-ESSO free-running model tests, ``../shared/data/esso_osaka``)
and ``standard`` (the channel names as headers, SI units: what :meth:`Log.to_frame` writes).
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import yaml

#: Units each kind of quantity may be given in, with the factor to its SI unit (first entry).
UNITS: dict[str, dict[str, float]] = {
    "time": {"s": 1.0, "ms": 1e-3, "min": 60.0, "h": 3600.0},
    "angle": {"rad": 1.0, "deg": math.pi / 180.0},
    "angular_rate": {"rad/s": 1.0, "deg/s": math.pi / 180.0, "deg/min": math.pi / 180.0 / 60.0},
    "length": {"m": 1.0, "km": 1000.0, "nmi": 1852.0},
    "speed": {"m/s": 1.0, "kn": 1852.0 / 3600.0, "km/h": 1.0 / 3.6},
    "rotation_rate": {"rps": 1.0, "Hz": 1.0, "rpm": 1.0 / 60.0},
}


@dataclass(frozen=True)
class Channel:
    """A signal the workbench knows: its quantity, whether a log must have it, what it means."""

    name: str
    quantity: str
    required: bool
    meaning: str


#: The channels, in the order of the standard format. Angles clockwise from north (heading) or
#: positive to starboard (rudder); wind direction where the true wind comes *from*.
CHANNELS: dict[str, Channel] = {
    channel.name: channel
    for channel in (
        Channel("time", "time", True, "time of the sample"),
        Channel("heading", "angle", True, "heading psi, clockwise from north"),
        Channel("rudder", "angle", True, "rudder angle, positive turns to starboard"),
        Channel("rate_of_turn", "angular_rate", False, "rate of turn r, positive to starboard"),
        Channel("north", "length", False, "position x0, north"),
        Channel("east", "length", False, "position y0, east"),
        Channel("speed", "speed", False, "forward speed through the water u"),
        Channel("propeller_rate", "rotation_rate", False, "propeller revolutions n"),
        Channel("wind_speed", "speed", False, "true wind speed"),
        Channel("wind_direction", "angle", False, "true wind direction, where it comes from, clockwise from north"),
    )
}
#: Channels that only make sense together.
PAIRED_CHANNELS: tuple[tuple[str, str], ...] = (("north", "east"), ("wind_speed", "wind_direction"))
RUDDER_KINDS = ("actual", "ordered")


class FormatError(ValueError):
    """A log format that is not well formed (unknown channel, unit or key)."""


@dataclass(frozen=True)
class Column:
    """Where a channel is in the file: the column header, its unit and sign.

    ``optional`` columns may be absent from a file (the channel is then not measured); a missing
    column that is not optional is an error.
    """

    name: str
    unit: str
    sign: float = 1.0
    optional: bool = False


@dataclass(frozen=True)
class LogFormat:
    """A declared column mapping.

    Attributes:
        name: the format's name.
        columns: channel name -> :class:`Column`.
        rudder_kind: ``"actual"`` when the log records the rudder's actual angle, ``"ordered"``
            when it records the order (then a steering-machine rate limit shows in the data).
        description: where such logs come from.
    """

    name: str
    columns: Mapping[str, Column]
    rudder_kind: str = "actual"
    description: str = ""
    notes: tuple[str, ...] = field(default_factory=tuple)

    def __post_init__(self) -> None:
        for channel, column in self.columns.items():
            if channel not in CHANNELS:
                raise FormatError(f"format {self.name!r}: unknown channel {channel!r}; known: {', '.join(CHANNELS)}")
            units = UNITS[CHANNELS[channel].quantity]
            if column.unit not in units:
                raise FormatError(
                    f"format {self.name!r}: channel {channel!r} (column {column.name!r}) has unit {column.unit!r}; "
                    f"use one of {', '.join(units)}"
                )
            if column.sign not in (1.0, -1.0):
                raise FormatError(
                    f"format {self.name!r}: channel {channel!r}: sign must be 1 or -1, got {column.sign!r}"
                )
        missing = [name for name, channel in CHANNELS.items() if channel.required and name not in self.columns]
        if missing:
            raise FormatError(f"format {self.name!r}: the channels {', '.join(missing)} are required")
        for first, second in PAIRED_CHANNELS:
            if (first in self.columns) != (second in self.columns):
                raise FormatError(f"format {self.name!r}: give both {first!r} and {second!r}, or neither")
        if self.rudder_kind not in RUDDER_KINDS:
            raise FormatError(
                f"format {self.name!r}: rudder_kind must be one of {RUDDER_KINDS}, got {self.rudder_kind!r}"
            )

    def factor(self, channel: str) -> float:
        """The factor (unit and sign) that turns the channel's column into SI units."""
        column = self.columns[channel]
        return column.sign * UNITS[CHANNELS[channel].quantity][column.unit]


ESSO_OSAKA = LogFormat(
    name="esso_osaka",
    columns={
        "time": Column("t [s]", "s"),
        "heading": Column("psi_hat [rad]", "rad"),
        "rudder": Column("delta_rudder [rad]", "rad"),
        "rate_of_turn": Column("r_angvelo [rad/s]", "rad/s"),
        "north": Column("x_position_mid [m]", "m"),
        "east": Column("y_position_mid [m]", "m"),
        "speed": Column("u_velo [m/s]", "m/s"),
        "propeller_rate": Column("n_prop [rps]", "rps"),
        "wind_speed": Column("wind_velo_true [m/s]", "m/s"),
        "wind_direction": Column("wind_dir_true [rad]", "rad"),
    },
    # The rudder record jumps 25 deg within one 0.1 s sample: it is the order.
    rudder_kind="ordered",
    description="FRT-DS-ESSO free-running tests of the 3 m Esso Osaka model (Osaka University, 2020)",
    notes=(
        (
            "position, heading and wind are those of midship; the true wind is the dataset's, derived from "
            "the relative wind with the same convention as the model (2.74)"
        ),
    ),
)

STANDARD = LogFormat(
    name="standard",
    columns={
        name: Column(name, next(iter(UNITS[channel.quantity])), optional=not channel.required)
        for name, channel in CHANNELS.items()
    },
    description="channel names as headers, SI units (what Log.to_frame writes)",
)

FORMATS: dict[str, LogFormat] = {fmt.name: fmt for fmt in (ESSO_OSAKA, STANDARD)}


def _column(channel: str, entry: object, where: str) -> Column:
    if not isinstance(entry, Mapping) or "column" not in entry:
        raise FormatError(f"{where}: channel {channel!r}: expected a mapping with 'column' and 'unit', got {entry!r}")
    unknown = set(entry) - {"column", "unit", "sign", "optional"}
    if unknown:
        raise FormatError(f"{where}: channel {channel!r}: unknown keys {sorted(unknown)}")
    default_unit = next(iter(UNITS[CHANNELS[channel].quantity])) if channel in CHANNELS else ""
    return Column(
        str(entry["column"]),
        str(entry.get("unit", default_unit)),
        float(entry.get("sign", 1.0)),
        bool(entry.get("optional", False)),
    )


def read_format(path: str | Path) -> LogFormat:
    """Read a log format from a YAML file (see the module's docstring)."""
    path = Path(path)
    try:
        document = yaml.safe_load(path.read_text())
    except OSError as error:
        raise FormatError(f"format file {str(path)!r}: {error.strerror}") from None
    if not isinstance(document, Mapping) or not isinstance(document.get("columns"), Mapping):
        raise FormatError(f"{path}: expected a mapping with 'columns' (channel -> {{column, unit}})")
    unknown = set(document) - {"name", "columns", "rudder_kind", "description"}
    if unknown:
        raise FormatError(f"{path}: unknown keys {sorted(unknown)}")
    return LogFormat(
        name=str(document.get("name", path.stem)),
        columns={
            str(channel): _column(str(channel), entry, str(path)) for channel, entry in document["columns"].items()
        },
        rudder_kind=str(document.get("rudder_kind", "actual")),
        description=str(document.get("description", "")),
    )


def resolve_format(name_or_path: str | Path | LogFormat) -> LogFormat:
    """A built-in format by name, a format read from a YAML file, or the format itself."""
    if isinstance(name_or_path, LogFormat):
        return name_or_path
    text = str(name_or_path)
    if text in FORMATS:
        return FORMATS[text]
    if text.endswith((".yaml", ".yml")):
        return read_format(text)
    raise FormatError(f"unknown log format {text!r}; built in: {', '.join(FORMATS)} (or a YAML file)")


#: Words in a column header (its unit in brackets left out) that suggest each channel, for the
#: format template a failed detection prints; a header with "wind" in it suggests only the wind's.
HEADER_WORDS: dict[str, frozenset[str]] = {
    "time": frozenset({"time", "t"}),
    "heading": frozenset({"heading", "hdg", "psi"}),
    "rudder": frozenset({"rudder", "delta"}),
    "rate_of_turn": frozenset({"rot", "r", "rate", "turn"}),
    "north": frozenset({"north", "x"}),
    "east": frozenset({"east", "y"}),
    "speed": frozenset({"speed", "stw", "u"}),
    "propeller_rate": frozenset({"propeller", "prop", "n", "rpm", "rps"}),
    "wind_speed": frozenset({"speed", "velo", "velocity"}),
    "wind_direction": frozenset({"dir", "direction"}),
}
_UNIT_IN_HEADER = re.compile(r"[\[(]\s*([^\])]*?)\s*[\])]")


def _header_channel(header: str, taken: set[str]) -> str | None:
    """The first channel not in ``taken`` that ``header``'s words suggest (:data:`HEADER_WORDS`)."""
    words = set(re.findall(r"[a-z]+", _UNIT_IN_HEADER.sub(" ", header.lower())))
    wind = "wind" in words
    for channel, hints in HEADER_WORDS.items():
        if channel not in taken and channel.startswith("wind") == wind and words & hints:
            return channel
    return None


def format_template(headers: Iterable[str]) -> str:
    """A format file for a log with these headers, to fill in: each channel with the header its words
    suggest (:data:`HEADER_WORDS`) and the unit in the header's brackets, where a known one; a required
    channel (or the partner of one found, :data:`PAIRED_CHANNELS`) that no header suggests with column "?"."""
    found: dict[str, str] = {}
    for header in headers:
        suggested = _header_channel(header, set(found))
        if suggested is not None:
            found[suggested] = header
    lines = [
        "name: my_log",
        "rudder_kind: actual   # or ordered, where the log records the rudder's order",
        "columns:",
    ]
    partners = {first: second for pair in PAIRED_CHANNELS for first, second in (pair, pair[::-1])}
    for name, channel in CHANNELS.items():
        if name not in found and not channel.required and partners.get(name) not in found:
            continue
        units = UNITS[channel.quantity]
        header = found.get(name, "?")
        in_brackets = _UNIT_IN_HEADER.search(header)
        unit = in_brackets.group(1) if in_brackets and in_brackets.group(1) in units else next(iter(units))
        note = f"{channel.meaning}; unit: {', '.join(units)}"
        if name == "rudder":
            note += "; sign: -1 where port rudder is positive"
        if name not in found:
            note = f"no header named like it: write its column; {note}"
        lines.append(f"  {name}: {{column: {json.dumps(header)}, unit: {unit}}}   # {note}")
    return "\n".join(lines) + "\n"


def detect_format(headers: Iterable[str], source: str) -> LogFormat:
    """The built-in format whose columns the file has, or a FormatError naming the required channels the
    standard format misses and printing a format file (:func:`format_template`) to write."""
    headers = list(headers)
    present = set(headers)
    for fmt in FORMATS.values():
        if all(column.name in present for column in fmt.columns.values() if not column.optional):
            return fmt
    required = [name for name, channel in CHANNELS.items() if channel.required]
    missing = [name for name in required if name not in present]
    others = [name for name in FORMATS if name != STANDARD.name]
    raise FormatError(
        f"{source}: no built-in log format fits the columns {sorted(present)}: a log needs the channels "
        f"{', '.join(required)}, which the standard format reads from columns of those names (missing: "
        f"{', '.join(missing)}; the other built-in formats: {', '.join(others)}). "
        "Write which column holds which channel to a format file and pass it with --format FILE.yaml; "
        f"for these columns, check and fill in:\n\n{format_template(headers)}"
    )
