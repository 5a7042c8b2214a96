"""The workbench on real measurements: the Esso Osaka 3 m model's free-running tests.

The data lives beside the project (``../shared/data/esso_osaka``, see its README) and is not
copied into the repository; these tests skip where it is absent. The quick tests check that the
built-in log format reads every run; the slow ones fit the nine zig-zags and run the documented
commands, checking each figure ``docs/results/workbench.md`` states for them.

A figure is checked against its recomputation within two jackknife standard errors over the runs
(:func:`~ship_env.workbench.fitting.errors.pooled_jackknife`): the pooled error with each run left out in
turn shows how much the figure owes to which runs were measured, so a stated figure that lies
further off than that is no longer the result of these commands.
"""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path

import pytest

from ship_env.cli import main
from ship_env.model import REQUIRED_EFFECTS, ShipModel
from ship_env.workbench import (
    LogWarning,
    cross_validate,
    fit_each_run,
    load_log,
    load_logs,
)
from ship_env.workbench.fitting.errors import RunErrors, pooled, pooled_jackknife

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "esso_osaka"
pytestmark = pytest.mark.skipif(
    not DATA.is_dir(), reason=f"the Esso Osaka data is not at {DATA} (../shared/data/esso_osaka beside the repository)"
)
SHIP = "esso_osaka_model"


def zigzags():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", LogWarning)
        return load_logs([DATA / "zigzag"])


def test_every_run_loads_with_the_built_in_format():
    with pytest.warns(LogWarning, match="13_50_28.csv: dropped the last 327 rows"):
        runs = load_logs([DATA / "zigzag", DATA / "turning"])
    assert len(runs) == 24
    for run in runs:
        assert run.rudder_kind == "ordered" and run.has_position and run.has_wind
        assert max(abs(run.rudder)) < math.radians(41) and max(run.propeller_rate) < 17.0
        assert 0.005 < run.time[1] - run.time[0] < 0.2
    turn = load_log(DATA / "turning" / "turn_14-Oct-2020_14_08_51.csv")
    assert any("unwrapped" in note for note in turn.notes)
    assert abs(turn.heading[-1] - turn.heading[0]) > 2 * math.pi  # whole turns, continuous


@pytest.mark.slow
def test_the_base_model_fits_runs_on_their_own_but_generalises_poorly():
    runs = zigzags()
    base = ShipModel(SHIP, REQUIRED_EFFECTS)
    validation = cross_validate(base, runs)
    per_run = pooled([result.errors[0] for result in fit_each_run(base.with_effects("rudder_offset"), runs)])
    held_out = validation.pooled
    print(
        f"\nbase: in-sample {math.degrees(validation.fit.pooled.heading):.1f} deg, held out "
        f"{math.degrees(held_out.heading):.1f} deg, track {held_out.track:.2f} m; "
        f"each run fitted on its own (with a rudder offset): {math.degrees(per_run.heading):.1f} deg"
    )
    assert math.degrees(per_run.heading) < 6.0
    assert math.degrees(held_out.heading) > 2.5 * math.degrees(per_run.heading)
    assert held_out.track > 1.5


#: The effects the error ladder on the zig-zags added (``ship-env improve .../zigzag``) while the replay imposed the
#: measured speed, the design notes' physics of these runs; with the speed predicted the ladder takes others
#: (docs/results/workbench.md), and the tests that expect these fail until it finds them again.
ZIGZAG_EFFECTS = ("current", "wind_moment", "norrbin", "propeller_slipstream", "asymmetry", "wind_drift")
#: The effects the zig-zags' ladder adds now that the replay predicts the speed (docs/results/workbench.md).
LADDER_EFFECTS = ("rudder_offset", "current", "steering_machine", "wind_drift")
#: The effects every fit to these runs has on: the base model, with the speed loss that predicts the measured speed.
BASE_EFFECTS = (*REQUIRED_EFFECTS, "speed_loss")
#: Two jackknife standard errors: how far a recomputed figure may lie from the stated one.
MARGIN_SIGMAS = 2.0


def command(folder: Path, *arguments: str) -> dict:
    """Run a documented command in this process with ``--json``; its document (the CLI's own defaults
    throughout; ``improve``'s report goes beside the document, not into the working directory)."""
    stem = folder / f"{len(list(folder.iterdir()))}-{arguments[0]}"
    report = ["--report", f"{stem}-report"] if arguments[0] == "improve" else []
    assert main([*arguments, *report, "--json", f"{stem}.json"]) == 0
    return json.loads(Path(f"{stem}.json").read_text())


def per_run(section: dict, pooled_name: str) -> list[RunErrors]:
    """The runs' errors of a document's section (display units: deg, deg/s, m), without its pooled row."""
    return [
        RunErrors(name, row["samples"], row["heading"], row["rate_of_turn"], row["position"], row["track"])
        for name, row in section.items()
        if name != pooled_name
    ]


def check_figure(runs: list[RunErrors], channel: str, stated: float) -> None:
    """The stated figure lies within ``MARGIN_SIGMAS`` jackknife standard errors of the pooled recomputed one."""
    value, spread = getattr(pooled(runs), channel), getattr(pooled_jackknife(runs), channel)
    print(f"{channel}: {value:.3f} (stated {stated}; jackknife standard error {spread:.3f})")
    assert abs(value - stated) <= MARGIN_SIGMAS * spread, (channel, value, stated, spread)


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("esso")


@pytest.fixture(scope="module")
def base_fit(folder: Path) -> dict:
    """``ship-env fit .../zigzag --validate-on .../turning``: the base model, held out and on the turning runs."""
    return command(folder, "fit", str(DATA / "zigzag"), "--validate-on", str(DATA / "turning"))


@pytest.fixture(scope="module")
def ladder(folder: Path) -> dict:
    """``ship-env improve .../zigzag``: the error ladder of the nine zig-zags (about 1.5 minutes on 2 cores)."""
    return command(folder, "improve", str(DATA / "zigzag"))


@pytest.mark.slow
def test_the_zigzag_ladder_adds_the_effects_the_results_page_names_and_halves_the_track_error(ladder, base_fit):
    """As docs/results/workbench.md states it: the rudder offset, the current, then the steering machine with
    the wind drift; the held-out track error falls by half or more and the heading error falls (its figures:
    ``test_the_ladder_gives_the_readmes_held_out_errors``)."""
    print("\n" + "\n".join(f"{rung['added']}: {rung['held_out']}" for rung in ladder["ladder"]))
    start, final = ladder["ladder"][0]["held_out"], ladder["held_out"]["held out"]
    base = base_fit["held_out"]["held out"]  # the ladder starts where ``fit`` leaves the base model
    assert (start["heading"], start["track"]) == pytest.approx((base["heading"], base["track"]), rel=1e-9)
    assert set(ladder["effects"]) == {*BASE_EFFECTS, *LADDER_EFFECTS}
    assert final["heading"] < start["heading"]
    assert final["track"] <= 0.5 * start["track"]


@pytest.mark.slow
def test_the_ladder_gives_the_readmes_held_out_errors(ladder, base_fit):
    """As docs/results/workbench.md states it:
    held-out heading 21.1 -> 16.7 deg, held-out track 2.14 -> 0.80 m (20.1 -> 6.4 deg, 2.15 -> 0.80 m with
    the speed imposed)."""
    before, after = per_run(base_fit["held_out"], "held out"), per_run(ladder["held_out"], "held out")
    check_figure(before, "heading", 21.1)
    check_figure(after, "heading", 16.7)
    check_figure(before, "track", 2.14)
    check_figure(after, "track", 0.80)


@pytest.mark.slow
def test_the_zigzags_effects_carry_to_the_turning_runs(folder, base_fit):
    """As docs/results/workbench.md states it:
    fitted on the zig-zags with the effects the ladder added with the speed imposed and validated on the
    turning runs, rate of turn 0.89 -> 0.76 deg/s, track 3.67 -> 1.59 m (1.23 -> 0.61 deg/s, 3.68 -> 1.60 m
    with the speed imposed)."""
    turning = ("--validate-on", str(DATA / "turning"))
    fitted = command(folder, "fit", str(DATA / "zigzag"), "--add", ",".join(ZIGZAG_EFFECTS), *turning)
    before, after = per_run(base_fit["validation"], "validation"), per_run(fitted["validation"], "validation")
    check_figure(before, "rate_of_turn", 0.87)
    check_figure(after, "rate_of_turn", 0.73)
    check_figure(before, "track", 3.68)
    check_figure(after, "track", 1.59)


@pytest.mark.slow
def test_a_ladder_with_the_turning_runs_as_validation_refuses_what_worsens_them(folder, base_fit):
    """As docs/results/workbench.md states it: ``improve`` with the turning runs as validation runs adds the
    rudder offset and the wind drift (turning runs' heading 148 -> 98 deg, track 1.64 m) and refuses the
    steering machine with the current, which would raise the turning runs' score."""
    ladder = command(folder, "improve", str(DATA / "zigzag"), "--validate-on", str(DATA / "turning"))
    before, after = per_run(base_fit["validation"], "validation"), per_run(ladder["validation"], "validation")
    check_figure(before, "heading", 148.0)
    check_figure(after, "heading", 98.0)
    check_figure(after, "track", 1.64)
    assert set(ladder["effects"]) == {*BASE_EFFECTS, "rudder_offset", "wind_drift"}
    assert "steering_machine + current" in ladder["stopped"] and "validation runs" in ladder["stopped"]


@pytest.mark.slow
def test_the_berthing_ladder_on_whole_runs(folder):
    """As docs/results/workbench.md states it: on the berthing runs the ladder on whole runs adds nothing,
    held-out heading 17.5 deg (with the speed imposed it added the wind moment, the steering machine, the Norrbin
    terms and the slipstream with sway: the runs are mostly outside the envelope)."""
    base = command(folder, "fit", str(DATA / "berthing"))
    ladder = command(folder, "improve", str(DATA / "berthing"))
    check_figure(per_run(base["held_out"], "held out"), "heading", 17.5)
    check_figure(per_run(ladder["held_out"], "held out"), "heading", 17.5)
    assert set(ladder["effects"]) == set(BASE_EFFECTS)


@pytest.mark.slow
def test_the_berthing_ladder_inside_the_envelope(folder):
    """As docs/results/workbench.md states it: on the berthing segments inside the envelope (``--inside
    --refit 4``), the Norrbin terms, the rudder's drag, then the slipstream with sway: held-out heading
    14.3 -> 3.0 deg, track 0.36 -> 0.19 m."""
    base = command(folder, "fit", str(DATA / "berthing"), "--inside")
    ladder = command(folder, "improve", str(DATA / "berthing"), "--inside", "--refit", "4")
    before, after = per_run(base["held_out"], "held out"), per_run(ladder["held_out"], "held out")
    check_figure(before, "heading", 14.3)
    check_figure(after, "heading", 3.0)
    check_figure(before, "track", 0.36)
    check_figure(after, "track", 0.19)
    added = {"norrbin", "rudder_drag", "propeller_slipstream", "sway"}
    assert set(ladder["effects"]) == {*BASE_EFFECTS, *added}
