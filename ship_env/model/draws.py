"""The random numbers effects draw for each ship where it starts: their ``DRAWS``, in one row per ship.

An effect that is on gets a slice of the row for each of its :class:`~ship_env.model.contributions.Draw` s,
in registration order; its start is a field of the parameter record (``<effect>_<draw>_start``),
which the composed code (``dynamics``) reads the slice by. The k-th draw of the registered effects
takes its uniform samples from the ship's key at the counters ``noise.DRAW_DOMAIN + k
noise.DRAW_STRIDE`` on, so what one effect draws does not depend on which others are on, nor on
the other ships of a batch.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ship_env.model import noise
from ship_env.model import state as S
from ship_env.model.contributions import Draw
from ship_env.model.registry import EFFECTS, RegisteredEffect


@dataclass(frozen=True)
class PlacedDraw:
    """One draw of an effect that is on, placed in the row.

    Attributes:
        entry: the effect that draws it.
        draw: its declaration.
        stream: its position among the registered effects' draws (which counters it draws from).
        start: where its numbers start in the row.
        shape: its shape for one ship.
        uniforms: the shape of the uniform samples it takes for one ship.
        arguments: what its function reads.
    """

    entry: RegisteredEffect
    draw: Draw
    stream: int
    start: int
    shape: tuple[int, ...]
    uniforms: tuple[int, ...]
    arguments: tuple[str, ...]

    @property
    def size(self) -> int:
        return math.prod(self.shape)


def start_field(effect: str, draw: Draw) -> str:
    """The record field that holds where a draw starts in the row (``wave_spectrum_waves_start``)."""
    return f"{effect}_{draw.name}_start"


def sizes(entry: RegisteredEffect, shape: tuple[int | str, ...], record: np.void) -> tuple[int, ...]:
    """A declared shape with the effect's parameters' values in place of their names."""
    return tuple(int(record[entry.effect.field_name(size)]) if isinstance(size, str) else size for size in shape)


def layout(effects: Sequence[str], record: np.void) -> tuple[PlacedDraw, ...]:
    """The draws of a record's effects that are on, placed one after another.

    Args:
        effects: the record's effects, in registration order (``dynamics.record_effects``).
        record: a parameter record (a row of ``ShipModel.record``), for the flags and the sizes.
    """
    placed: list[PlacedDraw] = []
    stream = 0
    start = 0
    for name in effects:
        entry = EFFECTS.entry(name)
        for draw in entry.draws:
            if record[entry.effect.flag_name]:
                shape = sizes(entry, draw.shape, record)
                uniforms = shape if draw.uniforms is None else sizes(entry, draw.uniforms, record)
                placed.append(PlacedDraw(entry, draw, stream, start, shape, uniforms, entry.arguments(draw.function)))
                start += placed[-1].size
            stream += 1
    return tuple(placed)


def row_size(records: np.ndarray) -> int:
    """The longest row of draws among parameter records (``ShipModel.record`` rows, one model each)."""
    total = np.zeros(len(records), dtype=np.int64)
    for name in EFFECTS:
        entry = EFFECTS.entry(name)
        if entry.effect.flag_name not in (records.dtype.names or ()):
            continue
        for declared in entry.draws:
            size = np.ones(len(records), dtype=np.int64)
            for dimension in declared.shape:
                size *= (
                    records[entry.effect.field_name(dimension)].astype(np.int64)
                    if isinstance(dimension, str)
                    else dimension
                )
            total += np.where(records[entry.effect.flag_name], size, 0)
    return int(total.max(initial=0))


def draw(
    placed: Sequence[PlacedDraw],
    record: np.void,
    keys: np.ndarray,
    conditions: np.ndarray,
    start_conditions: Mapping[str, np.ndarray],
) -> np.ndarray:
    """Every ship's row of draws: (ships, row size).

    Args:
        placed: the draws (``layout``).
        record: the parameter record the draws' functions read parameters from.
        keys: the ships' random keys (``noise.keys_from_seeds``).
        conditions: (ships, CONDITION_SIZE) the conditions each ship starts in.
        start_conditions: those the rows do not hold (``state.START_CONDITION_NAMES``), one value per ship.

    Raises:
        ValueError: a draw's function gives numbers of another shape or not finite, naming the
            effect, where it comes from and the draw.
    """
    count = len(keys)
    row = np.empty((count, sum(item.size for item in placed)))
    for item in placed:
        entry, declared = item.entry, item.draw
        domain = noise.DRAW_DOMAIN + np.uint64(item.stream * noise.DRAW_STRIDE)
        uniforms = noise.uniform_table(keys, domain, math.prod(item.uniforms)).reshape(count, *item.uniforms)
        own = {parameter.name for parameter in entry.effect.parameters}
        arguments = {}
        for argument in item.arguments:
            if argument == "uniforms":
                arguments[argument] = uniforms
            elif argument in S.CONDITION_NAMES:
                arguments[argument] = conditions[:, S.CONDITION_NAMES.index(argument)]
            elif argument in start_conditions:
                arguments[argument] = start_conditions[argument]
            elif argument in own:
                arguments[argument] = float(record[entry.effect.field_name(argument)])
            else:
                arguments[argument] = float(record[argument])  # a principal particular or a record field
        values = np.asarray(declared.function(**arguments), dtype=float)
        where = f"effect {entry.effect.name!r} from {entry.origin}: draw {declared.name!r}"
        if values.shape != (count, *item.shape):
            raise ValueError(
                f"{where}: its function gave numbers of shape {values.shape}, expected {(count, *item.shape)}"
            )
        if not np.isfinite(values).all():
            raise ValueError(
                f"{where}: its function gave numbers that are not finite: {values[~np.isfinite(values)][:3]}"
            )
        row[:, item.start : item.start + item.size] = values.reshape(count, item.size)
    return row
