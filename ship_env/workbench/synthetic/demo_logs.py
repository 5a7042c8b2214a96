"""``ship-env demo-logs``: simulated model-test logs to try the workbench on, with effects hidden in them.

The simulator sails the model-test programme (:func:`~ship_env.workbench.synthetic.synthetic.model_test_programme`:
three zig-zags and three turns, scaled to the ship) with the speed-scheduled Nomoto ship plus the
``--hidden`` effects, and sensors add their noise (:data:`SENSORS`). The logs are written in the
workbench's standard CSV format, the zig-zags into ``DIR/zigzag`` and the turns into ``DIR/turning``,
so ``ship-env fit DIR/zigzag --validate-on DIR/turning`` and the other workbench examples run from an
install alone. ``DIR/truth.json`` holds what is hidden, with its values keyed and in the units of
``ship-env fit --json``; ``DIR/README.txt`` says the same in words, with the commands to try.

A hidden effect takes the ship preset's values, except :data:`~ship_env.workbench.synthetic.synthetic.HIDDEN_VALUES`
and, where the preset holds the null value (an aligned rudder, a slipstream inside K*),
:data:`~ship_env.workbench.synthetic.synthetic.NULL_PRESET_VALUES`.
"""

from __future__ import annotations

import argparse
import json
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from ship_env.command_line import Command, UsageError, name_list, number, whole_number
from ship_env.model import REQUIRED_EFFECTS, ShipModel
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.fitting.terms import effect_terms, make_term, value_of
from ship_env.workbench.logs.logs import Log, write_log
from ship_env.workbench.outputs import OutputError, claim_folder
from ship_env.workbench.synthetic.synthetic import (
    HIDDEN_EFFECTS,
    HIDDEN_VALUES,
    NULL_PRESET_VALUES,
    PROGRAMME_SHIP,
    SEA_TRIAL_NOISE,
    LogSettings,
    SensorNoise,
    hidden_effect_logs,
    model_test_programme,
)


@dataclass(frozen=True)
class Sensors:
    """What logs the runs: the sensors' noise and the sample interval (s). The workbench's default error
    scales follow the ship's length and speed, so its commands need no options for either sensor."""

    noise: SensorNoise
    dt: float
    description: str


#: The sensors ``--sensors`` picks.
SENSORS: dict[str, Sensors] = {
    "basin": Sensors(SensorNoise(), LogSettings.dt, "a model basin's (0.2 deg compass, 2 cm positions, 5 Hz)"),
    "sea-trial": Sensors(
        SEA_TRIAL_NOISE, 1.0, "a sea trial's (0.5 deg compass, 3 m GPS, rudder read to 0.5 deg, 1 Hz)"
    ),
}
#: Hidden effects whose logs the standard CSV format cannot carry, and why.
NOT_IN_CSV: dict[str, str] = {
    "steering_machine": "its logs record the ordered rudder (the actual one would show the steering machine), "
    "which the standard format reads as the actual rudder",
}
#: The effects ``--hidden`` takes.
DEMO_EFFECTS = tuple(effect for effect in HIDDEN_EFFECTS if effect not in NOT_IN_CSV)
#: The subfolder each kind of run goes into.
RUN_FOLDERS = {"zigzag": "zigzag", "turn": "turning"}
TRUTH_FILE = "truth.json"
README_FILE = "README.txt"


@dataclass(frozen=True)
class DemoLogs:
    """Logs sailed by a known truth: the truth, the ship as named (preset or YAML file), the hidden
    effects, and the logs by subfolder."""

    truth: ReplayModel
    ship: str
    hidden: tuple[str, ...]
    logs: dict[str, list[Log]]

    def truth_values(self) -> dict[str, float]:
        """The hidden effects' fitted terms at their true values, SI units, keyed as ``ship-env fit --json``."""
        return {key: value_of(self.truth, key) for effect in self.hidden for key in effect_terms(effect)}


def hidden_values(ship: str, hidden: Sequence[str]) -> dict[str, float]:
    """The values the hidden effects take on ``ship`` (see the module's docstring); a ValueError
    naming the effect where its logs cannot be written (:data:`NOT_IN_CSV`) or every fitted term of
    it would still sit at its null value."""
    for effect in hidden:
        if effect in NOT_IN_CSV:
            raise ValueError(f"{effect} cannot be hidden in CSV logs: {NOT_IN_CSV[effect]}")
    values = dict(HIDDEN_VALUES)
    preset = ReplayModel(ShipModel(ship, [*REQUIRED_EFFECTS, *hidden]))

    def at_null(key: str) -> bool:
        return values.get(key, value_of(preset, key)) == make_term(key, preset).null

    for effect in hidden:
        keys = [key for key in effect_terms(effect) if not make_term(key, preset).is_condition]
        values.update({key: NULL_PRESET_VALUES[key] for key in keys if key in NULL_PRESET_VALUES and at_null(key)})
        if keys and all(at_null(key) for key in keys):
            raise ValueError(
                f"{effect} is off in the preset of {ship} (its terms at their null values): nothing to hide"
            )
    return values


def sail_demo(hidden: Sequence[str], ship: str, seed: int, sensors: Sensors, duration: float | None = None) -> DemoLogs:
    """Sail the model-test programme on ``ship`` with the ``hidden`` effects; each run ``duration`` s long
    (default: the programme's, 90 s on the 3 m model, scaled with the ship's L / U)."""
    time_scale = model_test_programme(1.0, ship)[0].duration  # the ship's seconds per second of the 3 m model
    programme = (
        model_test_programme(ship=ship) if duration is None else model_test_programme(duration / time_scale, ship)
    )
    truth, logs = hidden_effect_logs(
        hidden, ship, seed, programme, sensors.noise, hidden_values(ship, hidden), sensors.dt
    )
    by_folder: dict[str, list[Log]] = {folder: [] for folder in RUN_FOLDERS.values()}
    for manoeuvre, log in zip(programme, logs, strict=True):
        by_folder[RUN_FOLDERS[manoeuvre.kind]].append(log)
    return DemoLogs(truth, ship, tuple(hidden), by_folder)


def truth_document(demo: DemoLogs, seed: int, sensors: str) -> dict:
    """What ``truth.json`` holds: the ship, the base model, the hidden effects' values and units, the runs."""
    values = demo.truth_values()
    return {
        "ship": demo.ship,
        "base_model": list(REQUIRED_EFFECTS),
        "hidden": list(demo.hidden),
        "values": values,
        "units": {key: make_term(key, demo.truth).unit for key in values},
        "sensors": sensors,
        "seed": seed,
        "runs": {folder: [log.name for log in logs] for folder, logs in demo.logs.items()},
    }


def _with_unit(value: float, unit: str) -> str:
    """A value with its SI unit, an angle in degrees too."""
    if unit == "rad":
        return f"{value:.6g} rad ({math.degrees(value):.4g} deg)"
    return f"{value:.6g}" if unit in ("", "-") else f"{value:.6g} {unit}"


def readme_text(folder: Path, document: dict) -> str:
    """``README.txt``: what the logs are, what is hidden in them, and the commands to try."""
    ship = document["ship"]
    sensors = SENSORS[document["sensors"]]
    options = "" if ship == PROGRAMME_SHIP else f" --ship {ship}"
    zigzag, turning = folder / RUN_FOLDERS["zigzag"], folder / RUN_FOLDERS["turn"]
    hidden = document["hidden"]
    lines = [
        f"Simulated model-test logs of {ship}, written by 'ship-env demo-logs' (seed {document['seed']}).",
        f"Zig-zags in {zigzag}/, turns in {turning}/; standard CSV format, SI units; sensors: {sensors.description}.",
        f"Sailed by the base model ({', '.join(document['base_model'])})"
        + (f" plus the hidden effects {', '.join(hidden)}:" if hidden else " alone: nothing is hidden."),
        *(f"  {key} = {_with_unit(value, document['units'][key])}" for key, value in document["values"].items()),
        f"The same in {TRUTH_FILE}, keyed as 'ship-env fit --json' writes its values (SI units).",
        "Each run accelerates from its start speed to its service speed by the speed-loss equation (tau_u* = 1, "
        "no loss in a turn: K_u* = 0); the logs measure the speed, so a fit predicts it and fits the speed loss.",
        "",
        "Try:",
        f"  ship-env fit {zigzag}{options} --validate-on {turning}",
        f"  ship-env diagnose {zigzag}{options}",
        f"  ship-env improve {zigzag}{options} --validate-on {turning} --report report/",
    ]
    if hidden:
        lines += [
            f"  ship-env fit {zigzag}{options} --add {','.join(hidden)} --json fit.json",
            f"  ship-env compare {turning}{options} --parameters fit.json --plot plots/",
        ]
    return "\n".join(lines) + "\n"


def write_demo(folder: Path, demo: DemoLogs, seed: int, sensors: str, force: bool = False) -> list[Path]:
    """Write the logs, ``truth.json`` and ``README.txt`` into ``folder`` and return their paths; an OutputError,
    before anything is written, where a file would be overwritten or the folder holds files of its own (unless
    ``force``)."""
    log_files = {folder / name / f"{log.name}.csv": log for name, logs in demo.logs.items() for log in logs}
    targets = [*log_files, folder / TRUTH_FILE, folder / README_FILE]
    existing = [path for path in targets if path.exists()]
    if existing and not force:
        raise OutputError(f"DIR: {str(existing[0])!r} exists; choose another folder or pass --force to overwrite it")
    for claimed in (folder, *(folder / name for name in demo.logs)):
        claim_folder(claimed, force, "DIR")
    for path, log in log_files.items():
        write_log(log, path)
    document = truth_document(demo, seed, sensors)
    (folder / TRUTH_FILE).write_text(json.dumps(document, indent=2) + "\n")
    (folder / README_FILE).write_text(readme_text(folder, document))
    return targets


def run_demo_logs(args: argparse.Namespace) -> int:
    """``ship-env demo-logs``: sail, write, and say what was written and what is hidden."""
    try:
        ShipModel(args.ship)
    except (ValueError, TypeError, OSError) as error:
        raise UsageError("--ship", str(error)) from None
    try:
        demo = sail_demo(list(dict.fromkeys(args.hidden)), args.ship, args.seed, SENSORS[args.sensors], args.duration)
    except ValueError as error:
        raise UsageError("--hidden", str(error)) from None
    write_demo(args.folder, demo, args.seed, args.sensors, args.force)
    print((args.folder / README_FILE).read_text(), end="")
    return 0


def _arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("folder", type=Path, metavar="DIR", help="folder for the logs, truth.json and README.txt")
    parser.add_argument(
        "--hidden",
        type=name_list("effect", HIDDEN_EFFECTS),
        default=[],
        metavar="EFFECT[,EFFECT]",
        help=f"effects the logs are sailed with and the base model lacks: {', '.join(DEMO_EFFECTS)} (default: none)",
    )
    parser.add_argument(
        "--ship",
        default=PROGRAMME_SHIP,
        metavar="NAME",
        help="ship preset or YAML file; the workbench then needs the same --ship (default: %(default)s)",
    )
    parser.add_argument("--seed", type=whole_number(0), default=1, metavar="N", help="noise seed (default: 1)")
    parser.add_argument(
        "--sensors",
        choices=list(SENSORS),
        default="basin",
        help="; ".join(f"{name}: {sensors.description}" for name, sensors in SENSORS.items()) + " (default: basin)",
    )
    parser.add_argument(
        "--duration",
        type=number("a positive number of seconds", above=0.0),
        default=None,
        metavar="S",
        help="length of each run, s (default: 90 s on the 3 m model, scaled with the ship's L / U)",
    )
    parser.add_argument("--force", action="store_true", help="overwrite logs in DIR or write into a folder of yours")


COMMAND = Command(
    "demo-logs",
    description=(
        "Sail three zig-zags (into DIR/zigzag) and three turns (into DIR/turning) with the simulator, the\n"
        "speed-scheduled Nomoto ship plus the --hidden effects, add sensor noise and write them as CSV in\n"
        "the workbench's standard format; DIR/truth.json and DIR/README.txt say what is hidden and its\n"
        "values, so you can check what 'ship-env diagnose' and 'ship-env improve' find."
    ),
    examples=(
        "ship-env demo-logs demo --hidden rudder_offset,propeller_slipstream",
        "ship-env improve demo/zigzag --validate-on demo/turning --report report/",
        "ship-env demo-logs demo_226m --ship container_226m --sensors sea-trial --hidden current",
    ),
    handler=run_demo_logs,
    arguments=_arguments,
)
