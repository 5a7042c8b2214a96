"""Manoeuvre results as a readable text report and as a JSON-ready dictionary.

The report has one block per kind of manoeuvre, a row per figure with its unit in the row header
and a column per run, then the spiral's table and the IMO criteria with pass or fail.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from ship_env.manoeuvres.extrapolation import beyond_coverage
from ship_env.manoeuvres.imo import CriterionCheck
from ship_env.manoeuvres.results import KNOT, Figure, ManoeuvreResult, fixed
from ship_env.manoeuvres.spiral import SpiralTest
from ship_env.model import ShipModel
from ship_env.model.external import NATIVE

LABEL_WIDTH = 44  # row headers: a figure and its unit
CRITERION_WIDTH = 64  # row headers of the criteria: clause, figure, run and unit
COLUMN_WIDTH = 12
#: Per result (in the order given), a figure's standard error by its key (:mod:`.uncertainty`).
FigureErrors = Sequence[Mapping[str, float]]


def ship_line(model: ShipModel, approach_speed: float, dynamics: str | None = None) -> str:
    """The ship, its test speed and the effects of its model (or the external ``dynamics`` that sail it, or its
    preset's own: the ``dynamics:`` block), in one line."""
    if dynamics is None and model.ship.dynamics is not None:
        dynamics = f"its preset's dynamics: the fitted MMG model ({model.ship.dynamics.source})"
    native = dynamics is None or dynamics == NATIVE
    sailed_by = f"effects: {', '.join(model.effects)}" if native else f"sailed by {dynamics}"
    return (
        f"{model.ship.name}: L = {model.length:.1f} m, V = {approach_speed / KNOT:.1f} kn "
        f"({approach_speed:.2f} m/s), L/V = {model.length / approach_speed:.1f} s; {sailed_by}"
    )


def _row(header: str, cells: Sequence[str], width: int = LABEL_WIDTH, column: int = COLUMN_WIDTH) -> str:
    """A header left-aligned in ``width`` characters, then the cells right-aligned in columns ``column`` wide."""
    return f"{header:<{width}}" + "".join(f"{cell:>{column}}" for cell in cells)


def _figures_block(results: Sequence[ManoeuvreResult], errors: FigureErrors) -> list[str]:
    """Results of one kind side by side: a row per figure, a column per run (with its standard error, if any), the
    columns widened where a figure with its error would fill one."""
    figures_per_run = [result.figures() for result in results]
    rows = [(results[0].manoeuvre.capitalize(), [result.label for result in results])]
    for same_figure in zip(*figures_per_run, strict=True):
        unit = f" [{same_figure[0].unit}]" if same_figure[0].unit else ""
        pairs = zip(same_figure, errors, strict=True)
        rows.append((f"  {same_figure[0].label}{unit}", [f.text_with_error(e.get(f.key)) for f, e in pairs]))
    column = max(COLUMN_WIDTH, *(len(cell) + 2 for _, cells in rows for cell in cells))
    return [_row(header, cells, column=column) for header, cells in rows]


def _spiral_table(spiral: SpiralTest) -> list[str]:
    """The spiral's steady points, one row each, sorted by rate of turn."""
    lines = [_row("  steady points", ("rudder [deg]", "r [deg/s]", "r* [-]", "speed [kn]"))]
    for point in spiral.table.itertuples():
        cells = (
            fixed(math.degrees(point.rudder), 2),
            fixed(math.degrees(point.rate_of_turn), 3),
            fixed(point.normalised_rate, 3),
            fixed(point.speed / KNOT, 1),
            "hard over" if point.hard_over else "",
        )
        lines.append(_row("", cells))
    return lines


def _criteria_block(checks: Sequence[CriterionCheck]) -> list[str]:
    """One row per criterion: the figure, its limit, pass or FAIL."""
    lines = [_row("IMO MSC.137(76) 5.3 criteria", ("value", "limit", "result"), CRITERION_WIDTH)]
    for check in checks:
        header = f"  {check.clause} {check.description} [{check.unit}]"
        cells = (fixed(check.value, 2), f"<= {check.limit:.2f}", "pass" if check.passed else "FAIL")
        lines.append(_row(header, cells, CRITERION_WIDTH))
    return lines


def format_report(
    header: str,
    results: Sequence[ManoeuvreResult],
    checks: Sequence[CriterionCheck],
    errors: FigureErrors | None = None,
) -> str:
    """The text report: ``header``, a block per kind of manoeuvre (each figure +- its standard error in ``errors``,
    where given), the spiral table, the criteria."""
    lines = [header]
    errors = errors if errors is not None else [{} for _ in results]
    kinds = list(dict.fromkeys(type(result) for result in results))
    for kind in kinds:
        same_kind = [i for i, result in enumerate(results) if type(result) is kind]
        lines += ["", *_figures_block([results[i] for i in same_kind], [errors[i] for i in same_kind])]
        for result in (results[i] for i in same_kind):
            if isinstance(result, SpiralTest):
                lines += _spiral_table(result)
    if checks:
        lines += ["", *_criteria_block(checks)]
    return "\n".join(line.rstrip() for line in lines)


def _number(value: float | str) -> float | str | None:
    """A figure for JSON: NaN (an event not reached) becomes null."""
    return None if isinstance(value, float) and math.isnan(value) else value


def _figure_entry(figure: Figure, error: float | None) -> dict[str, object]:
    """A figure for JSON: value and unit, and its standard error where one is given."""
    entry: dict[str, object] = {"value": _number(figure.value), "unit": figure.unit}
    if error is not None and not isinstance(figure.value, str):
        entry["std_error"] = _number(error)
    return entry


def report_dict(
    model: ShipModel,
    results: Sequence[ManoeuvreResult],
    checks: Sequence[CriterionCheck],
    errors: FigureErrors | None = None,
) -> dict:
    """The report as plain data for JSON: ship, results' figures (display units, with their standard errors in
    ``errors`` where given), spiral tables, criteria."""
    errors = errors if errors is not None else [{} for _ in results]
    manoeuvres = []
    for result, run_errors in zip(results, errors, strict=True):
        entry: dict[str, object] = {
            "manoeuvre": result.manoeuvre,
            "label": result.label,
            "figures": {f.key: _figure_entry(f, run_errors.get(f.key)) for f in result.figures()},
        }
        if model.fitted_ranges is not None:
            entry["beyond_coverage"] = beyond_coverage(result, model)
        if isinstance(result, SpiralTest):
            entry["table"] = [
                {
                    "rudder_deg": math.degrees(point.rudder),
                    "rate_of_turn_deg_s": math.degrees(point.rate_of_turn),
                    "normalised_rate": point.normalised_rate,
                    "speed_m_s": point.speed,
                    "hard_over": bool(point.hard_over),
                }
                for point in result.table.itertuples()
            ]
        manoeuvres.append(entry)
    return {
        "ship": model.ship.name,
        "effects": list(model.effects),
        "length_m": model.length,
        "approach_speed_m_s": results[0].approach_speed if results else None,
        "manoeuvres": manoeuvres,
        "criteria": [
            {
                "clause": c.clause,
                "description": c.description,
                "value": _number(c.value),
                "limit": c.limit,
                "unit": c.unit,
                "passed": c.passed,
            }
            for c in checks
        ],
    }
