"""A fitted preset carries its operating point and says where it is sailed beyond what its runs covered.

Synthetic zig-zags sailed by the Esso Osaka model's Nomoto ship with a propeller slipstream (the rudder's
inflow grows with the propeller rate) at 12 rps are fitted and written as a preset. The preset states
12 rps as its service condition, and the simulator, the environments and the manoeuvres sail it there by
default; sailing it at 0 rps or at 35 deg rudder (the runs steered 20 deg) warns once. A steady current
found in the runs stays a finding about them: nothing sails it unless asked (``site_conditions``).
"""

from __future__ import annotations

import dataclasses
import math
import shutil
import warnings
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import yaml

import ship_env
from ship_env.baselines.filter_health import FilterDivergenceError
from ship_env.baselines.presys import indirect_adaptive_controller
from ship_env.cli import main
from ship_env.envs.tracks import TrackError, steady_turn_radius
from ship_env.leaderboard.board import run_leaderboard
from ship_env.leaderboard.entrants import CLASSIC_BUILDERS
from ship_env.leaderboard.suites import COURSE_CHANGE, NOMINAL, SuiteSpec
from ship_env.manoeuvres.turning_circle import turning_circle
from ship_env.model import Conditions, ShipModel, Simulator
from ship_env.model import state as S
from ship_env.model.operating_point import CoverageWarning, FittedRanges
from ship_env.workbench import FitOptions, ReplayModel, cross_validate, simulate
from ship_env.workbench.fitting.errors import ErrorScales
from ship_env.workbench.judging.free_running import compare_free_running
from ship_env.workbench.reporting.presets import fitted_current, preset_document, site_conditions, write_preset
from ship_env.workbench.synthetic.synthetic import Manoeuvre, hidden_effect_logs

SHIP = "esso_osaka_model"
RATE = 12.0  # rps, the fitted runs' propeller rate
HARD_OVER = math.radians(35.0)


def _fitted_preset(folder: Path, name: str, hidden: str, keys: list[str]) -> tuple[ShipModel, Path]:
    """Two 20/20 zig-zags at RATE sailed with ``hidden``, fitted for ``keys`` and written as a preset:
    (the fitted model, the preset's path)."""
    manoeuvres = [
        Manoeuvre(f"zigzag_{i}", "zigzag", math.radians(sign * 20.0), 40.0, approach=5.0, propeller_rate=RATE)
        for i, sign in enumerate((1, -1))
    ]
    _, logs = hidden_effect_logs((hidden,), SHIP, seed=3, manoeuvres=manoeuvres)
    setup = ReplayModel(ShipModel(SHIP, ["yaw", "kinematics", hidden]))
    options = FitOptions(scales=ErrorScales.for_runs(setup.model, logs), workers=1)
    validation = cross_validate(setup, logs, keys, options)
    path = folder / f"{name}.yaml"
    write_preset(preset_document(validation, logs, "ship-env fit (test)", name), path)
    return validation.fit.setup.model, path


@pytest.fixture(scope="module")
def slipstream(tmp_path_factory):
    """The preset fitted to the slipstream ship's runs at RATE: (the fitted model, the preset's path)."""
    return _fitted_preset(
        tmp_path_factory.mktemp("slipstream"),
        "slipstream",
        "propeller_slipstream",
        ["propeller_slipstream.coefficient"],
    )


def _steady_rate(model: ShipModel, conditions: Conditions | None = None) -> float:
    """The rate of turn (rad/s) after 300 s at 35 deg rudder, started at the service speed."""
    simulator = Simulator(model, dt=0.2)
    simulator.reset(seed=0, conditions=conditions)
    for _ in range(1500):
        simulator.step(HARD_OVER)
    return float(simulator.rate_of_turn[0])


def _copy(path: Path, folder: Path) -> Path:
    """The preset under a fresh path: a preset file not yet warned of in this process."""
    copied = folder / path.name
    shutil.copy(path, copied)
    return copied


def test_a_preset_fitted_at_n_rps_sails_at_n_rps_by_default(slipstream, tmp_path):
    """Simulator, gym.make and the manoeuvres sail the preset at the propeller rate its runs had: the steady
    turn at 35 deg is the fitted model's at 12 rps, not at 0 rps where its rudder is much weaker."""
    fitted, path = slipstream
    document = yaml.safe_load(path.read_text())
    assert document["service_conditions"]["propeller_rate"]["value"] == RATE
    assert "median propeller rate of 2 fitted logs" in document["service_conditions"]["propeller_rate"]["source"]
    model = ShipModel(_copy(path, tmp_path))
    assert model.service_propeller_rate == RATE
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoverageWarning)  # 35 deg: beyond the runs' 20 deg
        at_fit = _steady_rate(fitted, Conditions(propeller_rate=RATE))
        at_zero = _steady_rate(fitted, Conditions(propeller_rate=0.0))
        assert _steady_rate(model) == at_fit  # the same model at the same rate: bit for bit
        circle = turning_circle(model, HARD_OVER)  # as ship-env manoeuvre sails it
        # The tracks' turns, cached per model: the same record at another operating point turns on another circle.
        assert steady_turn_radius(fitted, HARD_OVER) > 1.2 * steady_turn_radius(model, HARD_OVER)
    assert at_fit > 1.3 * at_zero  # the rate a preset sailed at 0 rps loses
    assert circle.steady_rate_of_turn == pytest.approx(at_fit, rel=0.02)
    env = gym.make("ship_env/CourseChange-v0", ship=str(model.ship.path))
    env.reset(seed=0)
    assert env.unwrapped.batch.simulator.conditions[0, S.PROPELLER_RATE] == RATE
    # At another speed the propeller turns in proportion (the same advance ratio), as at the leaderboard's half speed.
    simulator = Simulator(model)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoverageWarning)  # 6 rps: below the runs' 12 rps
        simulator.reset(conditions=Conditions(service_speed=0.5 * model.service_speed))
    assert simulator.conditions[0, S.PROPELLER_RATE] == pytest.approx(0.5 * RATE, rel=1e-15)


def test_a_log_without_a_propeller_channel_is_replayed_at_the_presets_service_rate(slipstream, tmp_path):
    """The workbench's replay of a log that records no propeller rate sails the preset's operating point."""
    _, path = slipstream
    manoeuvre = Manoeuvre("zigzag", "zigzag", math.radians(20.0), 40.0, approach=5.0, propeller_rate=RATE)
    _, (log,) = hidden_effect_logs(("propeller_slipstream",), SHIP, seed=4, manoeuvres=[manoeuvre])
    setup = ReplayModel(ShipModel(_copy(path, tmp_path)))
    measured, unmeasured = simulate(setup, [log, dataclasses.replace(log, propeller_rate=None)])
    np.testing.assert_array_equal(unmeasured.heading, measured.heading)


def test_a_builtin_preset_sails_at_propeller_rate_zero_and_warns_not_at_its_service_condition():
    """A preset stating no service condition sails at 0 rps as before. The built-in Esso Osaka preset, itself
    fitted (to zig-zags and turning runs), turns hard over inside its coverage; one without a coverage never warns."""
    model = ShipModel("esso_osaka_model", ["yaw", "kinematics", "propeller_slipstream"])
    assert model.service_propeller_rate == 0.0 and model.fitted_ranges is not None
    assert ShipModel("container_226m").fitted_ranges is None
    with warnings.catch_warnings():
        warnings.simplefilter("error", CoverageWarning)
        assert _steady_rate(model) == _steady_rate(model, Conditions(propeller_rate=0.0))
        turning_circle(ShipModel("esso_osaka_model"), -HARD_OVER)


def test_sailing_beyond_the_fitted_runs_warns_once_naming_the_quantity_the_value_and_the_range(slipstream, tmp_path):
    _, path = slipstream
    ranges = yaml.safe_load(path.read_text())["fitted"]["coverage"]["ranges"]
    model = ShipModel(_copy(path, tmp_path))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        simulator = Simulator(model, dt=0.2)  # starts at the service condition, 12 rps: inside
        for _ in range(100):
            simulator.step(math.radians(10.0))  # inside the runs' 20 deg
        assert not [w for w in caught if issubclass(w.category, CoverageWarning)]
        for seed in range(3):  # a training loop's resets and steps: one warning per quantity in all
            Simulator(model).reset(seed=seed, conditions=Conditions(propeller_rate=0.0))
            simulator.reset(seed=seed, conditions=Conditions(propeller_rate=0.0))
            for _ in range(100):
                simulator.step(HARD_OVER)
    messages = [str(w.message) for w in caught if issubclass(w.category, CoverageWarning)]
    propeller = [message for message in messages if "propeller rate" in message]
    rudder = [message for message in messages if "at rudder" in message]
    assert len(propeller) == 1 and len(rudder) == 1 and len(messages) == len(set(messages)) <= 4
    assert (
        f"sailed at propeller rate 0 rps, beyond the range its fitted runs covered (propeller rate {RATE:g} to "
        in (propeller[0])
    )
    assert "sailed at rudder 35 deg" in rudder[0]
    assert f"(|rudder| <= {math.degrees(ranges['rudder']['high']):.3g} deg)" in rudder[0]
    assert str(model.ship.path) in rudder[0]


def _with_speed_coverage(folder: Path, low: float, high: float) -> Path:
    """The ``kvlcc2`` preset (with its speed loss) as a fit whose runs sailed at ``low`` to ``high`` times its service
    speed."""
    document = yaml.safe_load((Path(ship_env.__file__).parent / "configs" / "ships" / "kvlcc2.yaml").read_text())
    service_speed = ShipModel("kvlcc2").service_speed
    speed = {"low": low * service_speed, "high": high * service_speed}
    document["fitted"] = {"coverage": {"ranges": {"speed": speed}}}
    path = folder / f"speeds_{low}_{high}.yaml"
    path.write_text(yaml.safe_dump(document))
    return path


def test_a_turn_that_slows_the_ship_below_the_fitted_runs_speeds_warns_once(tmp_path):
    """A hard-over turn that loses more speed than the fitted zig-zags did sails a speed loss, a rudder inflow and a
    slipstream share the fit never saw: the speed is checked after every step as r* is."""
    model = ShipModel(_with_speed_coverage(tmp_path, 0.8, 1.01))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        simulator = Simulator(model, dt=1.0)
        for _ in range(100):
            simulator.step(math.radians(10.0))  # a 10 deg turn keeps 98 % of the speed: inside
        assert not caught
        for seed in range(2):
            simulator.reset(seed=seed)
            for _ in range(600):
                simulator.step(HARD_OVER)
            speed_loss = float(simulator.state[0, S.SPEED_LOSS])
    (message,) = (str(w.message) for w in caught if issubclass(w.category, CoverageWarning))
    service_speed = model.service_speed
    assert speed_loss > 0.2  # the turn loses more than the runs' 20 %
    assert (
        "sailed at speed " in message
        and f"(speed {0.8 * service_speed:.3g} to {1.01 * service_speed:.3g} m/s)" in message
    )
    assert float(message.split("sailed at speed ")[1].split(" m/s")[0]) < 0.8 * service_speed


def test_a_ship_faster_than_the_fitted_runs_warns_at_its_first_step(tmp_path):
    model = ShipModel(_with_speed_coverage(tmp_path, 0.5, 0.9))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        Simulator(model, dt=1.0).step(0.0)
    (message,) = (str(w.message) for w in caught if issubclass(w.category, CoverageWarning))
    assert f"sailed at speed {model.service_speed:.3g} m/s" in message


def test_the_workbench_sails_a_new_fit_beyond_its_starting_presets_runs_without_their_warning(tmp_path):
    """The workbench's free-running validation sails each fit through the runs. A fit's values are new, so the
    coverage its starting preset records is not theirs (the preset the fit writes records its own): that sailing
    warns of nothing, and the user's own sailing of the starting preset still warns."""
    model = ShipModel(_with_speed_coverage(tmp_path, 0.5, 0.9))  # its service speed beyond the runs
    speed = model.service_speed
    zigzag = Manoeuvre("zigzag_20", "zigzag", math.radians(20.0), 1000.0, 50.0, start_speed=speed, final_speed=speed)
    _, logs = hidden_effect_logs((), "kvlcc2", manoeuvres=[zigzag])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        (result,) = compare_free_running(ReplayModel(model), logs)
        assert result.manoeuvre.kind == "zig-zag" and not result.cannot_sail
        assert not caught
        Simulator(model, dt=1.0).step(0.0)
    assert [warning.category for warning in caught] == [CoverageWarning]


def test_a_value_just_beyond_the_range_is_shown_apart_from_it():
    ranges = FittedRanges("just_beyond.yaml", {"rate": (None, 0.2371), "propeller": (10.2, 10.2)})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ranges.check("rate", 0.23718, 0.23718)
        ranges.check("propeller", 10.2, 10.2)  # at the runs' constant rate: inside
        ranges.check("propeller", 10.2 * (1.0 + 1e-12), 10.2 * (1.0 + 1e-12))
    first, second = (str(w.message) for w in caught)
    assert "sailed at r* 0.2372, beyond the range its fitted runs covered (|r*| <= 0.2371)" in first
    assert "sailed at propeller rate 10.20000000001 rps" in second and "(propeller rate 10.2 to 10.2 rps)" in second


@pytest.fixture(scope="module")
def in_current(tmp_path_factory):
    """A preset fitted to runs in a steady current (a towing tank's circulation, say): (model, path)."""
    return _fitted_preset(
        tmp_path_factory.mktemp("current"), "in_current", "current", ["current.north", "current.east"]
    )


def test_a_fitted_current_is_sailed_only_where_asked(in_current, tmp_path):
    """The runs' current stays in ``fitted.conditions``: the environments and the simulator's default conditions
    sail none; ``site_conditions`` sails it, the ground track then drifting by the current times the time."""
    _, path = in_current
    model = ShipModel(_copy(path, tmp_path))
    north, east = fitted_current(model)
    assert math.hypot(north, east) > 0.01 * model.service_speed  # the fit found it
    env = gym.make("ship_env/CourseChange-v0", ship=str(model.ship.path))
    env.reset(seed=0)
    conditions = env.unwrapped.batch.simulator.conditions[0]
    assert conditions[S.CURRENT_SPEED] == 0.0 and conditions[S.CURRENT_NORTH] == conditions[S.CURRENT_EAST] == 0.0
    env.reset(seed=0, options={"conditions": site_conditions(model)})  # asked for
    conditions = env.unwrapped.batch.simulator.conditions[0]
    np.testing.assert_allclose(conditions[[S.CURRENT_NORTH, S.CURRENT_EAST]], [north, east], rtol=1e-12, atol=1e-15)
    positions = []
    for asked in (None, site_conditions(model)):
        simulator = Simulator(model, dt=0.5)
        simulator.reset(seed=0, conditions=asked)
        for _ in range(200):
            simulator.step(math.radians(5.0))
        positions.append(simulator.position[0].copy())
    np.testing.assert_allclose(positions[1] - positions[0], np.array([north, east]) * 100.0, rtol=1e-9, atol=1e-9)


def test_the_leaderboard_leaves_out_in_one_line_a_track_the_ship_cannot_turn_on(tmp_path, capsys):
    """A ship that turns too wide at 10 deg rudder for TrackFollow's legs (here the Esso Osaka model with a
    third of its K*) sails the CourseChange suites; TrackFollow is left out in one line, no traceback."""
    document = yaml.safe_load((Path(__file__).parents[1] / "ship_env/configs/ships/esso_osaka_model.yaml").read_text())
    document["effects"]["yaw"]["gain"]["value"] *= 0.3
    preset = tmp_path / "wide_turner.yaml"
    preset.write_text(yaml.safe_dump(document, sort_keys=False))
    arguments = ["leaderboard", "--ship", str(preset), "--no-shipped", "--no-plots", "--no-progress"]
    arguments += ["--course-changes", "15", "--disturbances", "calm", "--conditions", "nominal", "--tracks", "T1"]
    assert main([*arguments, "--out", str(tmp_path / "board")]) == 0
    output = capsys.readouterr()
    lines = output.err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in output.err
    assert lines[0].startswith(
        "ship-env leaderboard: left out TrackFollow-v0: esso_osaka_model: T1: the turns at the ends"
    )
    assert "radii" in lines[0] and " L)" in lines[0]
    written = (tmp_path / "board" / "leaderboard.md").read_text()  # the terminal has a summary
    assert "### CourseChange calm | nominal" in written and "### TrackFollow" not in written
    only_tracks = SuiteSpec(
        course_changes_deg=(), course_change_disturbances=(), tracks=("T1",), conditions=(NOMINAL,), ship=str(preset)
    )
    with pytest.raises(TrackError, match=r"^TrackFollow-v0: esso_osaka_model: T1: the turns at the ends of leg 0"):
        run_leaderboard(only_tracks, shipped=False, progress=False)


def test_the_leaderboard_leaves_out_in_one_line_an_autopilot_whose_filter_diverges(monkeypatch):
    """A classic autopilot whose filter declares itself diverged (here: the indirect adaptive PD's, told so
    in its second course change) is left out of that suite's table with one line naming why and where; the
    others are ranked on every episode. The Esso Osaka zig-zag preset at its 12 rps ended in this traceback
    on the K*, tau* x0.5 suites."""
    adaptive = "indirect adaptive PD"
    built = []

    def diverging(task):
        controller = indirect_adaptive_controller(task)
        built.append(controller)
        if len(built) == 2:
            gate = controller.autopilot.yaw_filter.gate
            monkeypatch.setattr(gate, "accepts", lambda *_: (_ for _ in ()).throw(FilterDivergenceError("diverged")))
        return controller

    monkeypatch.setitem(CLASSIC_BUILDERS[COURSE_CHANGE], adaptive, diverging)
    spec = SuiteSpec(course_changes_deg=(15.0,), tracks=(), conditions=(NOMINAL,), course_change_disturbances=("calm",))
    board = run_leaderboard(spec, shipped=False, progress=False)
    assert board.left_out == (
        f"{adaptive} on CourseChange calm | nominal: FilterDivergenceError: diverged (episode -15 deg, seed 1); "
        "not ranked on that suite",
    )
    rows = [line for line in board.markdown().splitlines() if "| classic |" in line]
    assert len(rows) == 3 and not any(adaptive in row for row in rows) and all("| 2/2 |" in row for row in rows)


ESSO = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "esso_osaka"


@pytest.mark.skipif(
    not ESSO.is_dir(), reason=f"the Esso Osaka data is not at {ESSO} (../shared/data beside the repository)"
)
def test_the_esso_zigzag_preset_sails_at_its_runs_propeller_rate_and_the_leaderboard_sails_it(tmp_path, capsys):
    """The measured zig-zags (10 to 16.7 rps) fitted with the propeller slipstream: the preset states their median
    rate, 12 rps, and the leaderboard sails it or says in one line per thing left out why, never a traceback."""
    preset = tmp_path / "esso_zigzag.yaml"
    fit = ["fit", str(ESSO / "zigzag"), "--ship", "esso_osaka_model", "--model", "base", "--every", "2"]
    assert main([*fit, "--add", "propeller_slipstream", "--workers", "1", "--preset", str(preset)]) == 0
    assert ShipModel(preset).service_propeller_rate == 12.0
    capsys.readouterr()
    board = ["leaderboard", "--ship", str(preset), "--no-shipped", "--no-plots", "--no-progress", "--tracks", "T1"]
    board += ["--course-changes", "15", "--disturbances", "calm", "--conditions", "nominal"]
    assert main([*board, "--out", str(tmp_path / "board")]) == 0
    errors = capsys.readouterr().err.strip().splitlines()
    assert all(line.startswith("ship-env leaderboard: left out ") for line in errors), errors


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (
            lambda d: d["service_conditions"].update(wind_speed={"value": 3.0, "source": "x"}),
            "service_conditions: unknown condition 'wind_speed'; known: propeller_rate",
        ),
        (
            lambda d: d["service_conditions"]["propeller_rate"].update(unit="deg"),
            "service_conditions.propeller_rate: unit 'deg' cannot be converted to 'rps'",
        ),
        (
            lambda d: d["fitted"]["coverage"]["ranges"]["rudder"].update(high="wide"),
            "fitted.coverage.ranges.rudder: expected finite 'low' (or null) and 'high', got",
        ),
        (
            lambda d: d["fitted"]["coverage"]["ranges"].update(heel={"low": None, "high": 1.0}),
            "fitted.coverage.ranges.heel: unknown quantity; known: speed, rate, drift, rudder, propeller",
        ),
    ],
)
def test_a_bad_operating_point_names_the_file_and_the_field(slipstream, tmp_path, edit, message):
    _, path = slipstream
    document = yaml.safe_load(path.read_text())
    edit(document)
    edited = tmp_path / "edited.yaml"
    edited.write_text(yaml.safe_dump(document, sort_keys=False))
    with pytest.raises((ValueError, TypeError)) as error:
        ShipModel(edited)
    assert "edited.yaml" in str(error.value) and message in str(error.value)
