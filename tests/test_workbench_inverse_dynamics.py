"""The MMG standard's 3-DOF forces identified by inverse dynamics (``ship-env fit-mmg``), and the fitted ship sailed.

A ship of the form with known coefficients (``TRUTH``, a fit to the MMG basin truth's zig-zags rounded) sails
zig-zags; the identification must give its forces back from the logs alone (smoothed states and accelerations,
the noise estimated from the logs), and its hard-over turn, which no run holds. The fitted model is sailed by a
second integrator (scipy's adaptive RK45) to check the adapter's RK4, and through the commands and environments
a user would sail it with.
"""

from __future__ import annotations

import math
import re
from functools import partial
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import yaml
from scipy.integrate import solve_ivp

import ship_env  # noqa: F401  (registers the environments)
from ship_env.cli import main
from ship_env.manoeuvres import TrialSettings, turning_circle, zigzag
from ship_env.model import ShipModel
from ship_env.model.mmg_fitted import MmgFitted, MmgRecord, mmg_document, read_mmg
from ship_env.model.mmg_form import INFLOW_TERMS, PROPELLER_POSITION, WAKE_DECAY, MmgForm, derivatives, force_regressors
from ship_env.workbench import ReplayModel
from ship_env.workbench.fitting.inverse_dynamics import IdentificationError, identify, rigid_body
from ship_env.workbench.fitting.smoothing import SmoothingError
from ship_env.workbench.logs.channel_smoother import noise_of, smooth_channels
from ship_env.workbench.logs.logs import Log, write_log
from ship_env.workbench.synthetic.synthetic import LogSettings, Manoeuvre, SensorNoise, sail_all

#: The 7 m KVLCC2 model of the MMG standard, as ``ship-env scale kvlcc2 --length 7`` writes it.
SCALED = ("scale", "kvlcc2", "--length", "7")
#: The truth's coefficients (module docstring).
TRUTH_INFLOW = np.array([6.5, 1.9, 4.5, 3.6, -1.05, 0.7])
TRUTH_SURGE = np.array([1.3e-3, -9.7e-4, -2.27e-2, -0.165, -0.092, -0.024, 2.05, 3.9e-4])
TRUTH_SWAY = np.array([-0.235, 0.069, -0.79, 4.07, 1.94, 0.389, 1.25e-3])
TRUTH_YAW = np.array([-0.126, -0.0454, -0.5, -1.77, -0.734, -0.107, -4.9e-4])
PROPELLER_RATE = 11.86  # rps
EXACT = SensorNoise(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


@pytest.fixture(scope="module")
def model_preset(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("preset") / "kvlcc2_model.yaml"
    assert main([*SCALED, "-o", str(path)]) == 0
    return path


@pytest.fixture(scope="module")
def truth(model_preset: Path) -> MmgRecord:
    model = ShipModel(model_preset)
    body = rigid_body(model)
    form = MmgForm(body, TRUTH_INFLOW, TRUTH_SURGE, TRUTH_SWAY, TRUTH_YAW)
    return MmgRecord(
        form, model.parameter("steering_machine.rudder_rate"), model.rudder_limit, PROPELLER_RATE, model.service_speed
    )


def _zigzags(
    model: ShipModel, record: MmgRecord, noise: SensorNoise, seed: int = 1, rudder_kind: str = "actual"
) -> list[Log]:
    """Six zig-zags (10/10, 20/20 and 35/5 to both sides) sailed by ``record``'s ship, logged at 5 Hz."""
    unit = model.length / model.service_speed
    programme = ((10, 10), (-10, 10), (20, 20), (-20, 20), (35, 5), (-35, 5))
    manoeuvres = [
        Manoeuvre(
            f"zigzag_{a}_{b}",
            "zigzag",
            math.radians(a),
            25.0 * unit,
            approach=2.0 * unit,
            zigzag_angle=math.radians(b),
            start_speed=model.service_speed,
            final_speed=model.service_speed,
            propeller_rate=PROPELLER_RATE,
            wind_speed=0.0,
        )
        for a, b in programme
    ]
    settings = LogSettings(dt=0.2, noise=noise, rudder_kind=rudder_kind)
    return sail_all(ReplayModel(model), manoeuvres, seed, settings, partial(MmgFitted, record))


def _turns(model: ShipModel, record: MmgRecord, noise: SensorNoise, seed: int = 1) -> list[Log]:
    """The hard-over turning circles to both sides (two circles), sailed by ``record``'s ship, logged at 5 Hz."""
    unit = model.length / model.service_speed
    manoeuvres = [
        Manoeuvre(
            f"turning_35_{side}",
            "turn",
            sign * model.rudder_limit,
            40.0 * unit,
            approach=2.0 * unit,
            start_speed=model.service_speed,
            final_speed=model.service_speed,
            propeller_rate=PROPELLER_RATE,
            wind_speed=0.0,
        )
        for side, sign in (("stbd", 1.0), ("port", -1.0))
    ]
    return sail_all(ReplayModel(model), manoeuvres, seed, LogSettings(dt=0.2, noise=noise), partial(MmgFitted, record))


@pytest.fixture(scope="module")
def exact_logs(model_preset: Path, truth: MmgRecord) -> list[Log]:
    return _zigzags(ShipModel(model_preset), truth, EXACT)


def _turn(model: ShipModel, record: MmgRecord, side: float = 1.0) -> dict[str, float]:
    settings = TrialSettings(dt=0.2, dynamics=partial(MmgFitted, record))
    return {f.key: f.value for f in turning_circle(model, side * model.rudder_limit, settings).figures()}


#: The issue's bounds on a fit's predictions: (figure, bound, relative).
BOUNDS = (
    ("advance_lengths", 0.05, True),
    ("tactical_diameter_lengths", 0.05, True),
    ("steady_rate_of_turn", 0.10, True),
    ("speed_loss", 0.10, True),
    ("first_overshoot", 2.0, False),
)


def _judged(model: ShipModel, record: MmgRecord) -> dict[str, float]:
    """The hard-over turn's figures to starboard and the 10/10 zig-zag's first overshoot."""
    settings = TrialSettings(dt=0.2, dynamics=partial(MmgFitted, record))
    figures = _turn(model, record)
    overshoot = zigzag(model, math.radians(10.0), math.radians(10.0), settings).figures()
    return {**figures, **{f.key: f.value for f in overshoot}}


def _within_bounds(predicted: dict[str, float], expected: dict[str, float]) -> list[str]:
    """The figures outside the issue's bounds, with their errors."""
    outside = []
    for key, bound, relative in BOUNDS:
        error = predicted[key] - expected[key]
        if (abs(error) / abs(expected[key]) if relative else abs(error)) > bound:
            outside.append(f"{key}: {predicted[key]:.4g} against {expected[key]:.4g}")
    return outside


# -- smoothing ------------------------------------------------------------------------------------------------
def test_the_noise_of_a_smooth_channel_is_read_from_its_third_differences():
    time = np.arange(0.0, 300.0, 0.2)
    signal = 20.0 * np.sin(time / 15.0) + 0.01 * time**2
    noise = np.random.default_rng(3).normal(0.0, 0.02, len(time))
    assert noise_of(signal + noise) == pytest.approx(0.02, rel=0.1)  # the MAD's spread over 1500 samples: 4 %


def test_an_acceleration_that_ramps_is_smoothed_without_lag():
    """A rudder moving at its machine's rate ramps the yaw acceleration: the smoothed acceleration of an exact track
    whose acceleration ramps (integrated a thousand times finer than it is sampled) follows it at the samples, where
    a model holding the acceleration constant over each step (filterpy's discrete white noise) lags half a sample:
    an error of half the ramp's change per sample."""
    from scipy.integrate import cumulative_trapezoid

    fine = np.arange(0.0, 40.0, 2e-4)
    slope = 1e-3  # m/s^3, from 10 s to 20 s
    acceleration = slope * np.clip(fine - 10.0, 0.0, 10.0)
    track = cumulative_trapezoid(cumulative_trapezoid(acceleration, fine, initial=0.0), fine, initial=0.0)
    dt = 0.2
    time = np.arange(0.0, 40.0, dt)
    smoothed = smooth_channels(np.interp(time, fine, track)[:, None], dt)
    ramp = (time > 11.0) & (time < 19.0)  # a second from the kinks
    error = smoothed[ramp, 2] - np.interp(time[ramp], fine, acceleration)
    assert np.max(np.abs(error)) < 0.01 * 0.5 * slope * dt  # a hundredth of the half-sample lag's


def test_a_constant_acceleration_track_is_smoothed_into_its_exact_rate_and_acceleration():
    """The filter's model holds a constant acceleration exactly: its smoother gives back the rate and acceleration
    of such a track from its positions alone."""
    time = np.arange(0.0, 60.0, 0.2)
    track = 3.0 + 1.2 * time + 0.5 * 0.04 * time**2
    smoothed = smooth_channels(track[:, None], 0.2)
    assert np.allclose(smoothed[:, 0], track, rtol=0, atol=1e-9)
    assert np.allclose(smoothed[:, 1], 1.2 + 0.04 * time, rtol=0, atol=1e-9)
    assert np.allclose(smoothed[:, 2], 0.04, rtol=0, atol=1e-9)


# -- the adapter ------------------------------------------------------------------------------------------------
def test_the_adapters_rk4_sails_as_an_adaptive_integrator_does(model_preset, truth):
    """A hard-over turn held for ten ship lengths: the adapter's fixed-step RK4 (0.2 s, 1/30 of L/U) against scipy's
    RK45 at 1e-10, the rudder moving at the steering machine's rate in both. RK4's error is of order (h U / L)^4,
    1e-6 of each quantity's scale per L/U sailed."""
    model = ShipModel(model_preset)
    adapter = MmgFitted(truth)
    from ship_env.model.external import ShipMotion
    from ship_env.model.simulator import Conditions

    speed = model.service_speed
    adapter.reset(ShipMotion(0.0, 0.0, 0.0, 0.0, speed), Conditions(service_speed=speed), 0)
    dt, steps = 0.2, round(10.0 * model.length / speed / 0.2)
    for _ in range(steps):
        motion = adapter.step(truth.rudder_limit, None, dt)
    duration = steps * dt

    def moving(time: float, state: np.ndarray) -> np.ndarray:  # the rudder as the adapter moves it: linear in a step
        step, within = divmod(time, dt)
        start = min(step * truth.rudder_rate * dt, truth.rudder_limit)
        end = min((step + 1) * truth.rudder_rate * dt, truth.rudder_limit)
        return derivatives(state, start + (end - start) * within / dt, PROPELLER_RATE, truth.form)

    exact = solve_ivp(
        moving, (0.0, duration), [speed, 0, 0, 0, 0, 0], rtol=1e-10, atol=1e-12, max_step=0.05, method="RK45"
    ).y[:, -1]
    sailed = np.array([motion.speed, -motion.speed * math.tan(motion.drift), motion.rate_of_turn])
    assert np.allclose(sailed, exact[:3], rtol=0, atol=1e-5 * np.array([speed, speed, speed / model.length]))
    assert math.hypot(motion.north - exact[3], motion.east - exact[4]) < 1e-5 * model.length
    assert motion.heading == pytest.approx(exact[5], abs=1e-5)


@pytest.mark.parametrize("drift_deg, turn", [(0.0, 0.0), (10.0, 0.0), (-20.0, 0.0), (12.0, 0.4), (-5.0, -0.6)])
def test_the_propellers_inflow_grows_with_the_drift_at_the_propeller_as_the_mmg_standards_wake(truth, drift_deg, turn):
    """Yasukawa & Yoshimura (2015) eq. 16: (1 - w_P) / (1 - w_P0) = 1 + (C_2 - 1)(1 - exp(-C_1 |beta_P|)), beta_P =
    beta - x_P' r'. The thrust's u n T column and the rudder's inflow u_R^2 = u_P^2 + b_un u_P nT + c_nn (nT)^2 are
    written with u times that factor; on a straight course (beta_P = 0) it is 1."""
    body = truth.form.body
    speed, drift = 1.2, math.radians(drift_deg)
    u, v, r = speed * math.cos(drift), -speed * math.sin(drift), turn * speed / body.length
    factor = 1.0 + TRUTH_INFLOW[5] * (1.0 - math.exp(-WAKE_DECAY * abs(drift - PROPELLER_POSITION * turn)))
    surge, sway, _ = force_regressors(u, v, r, 0.3, PROPELLER_RATE, TRUTH_INFLOW, body)
    assert surge[0, 1] == pytest.approx(factor * u * PROPELLER_RATE * body.draught, rel=1e-12)
    assert surge[0, 2] == pytest.approx(u * u, rel=1e-12)  # the resistance: on the speed, not the inflow
    n_t = PROPELLER_RATE * body.draught
    inflow_squared = (factor * u) ** 2 + TRUTH_INFLOW[0] * factor * u * n_t + TRUTH_INFLOW[1] * n_t**2
    beta_r = math.atan2(-v, u) - TRUTH_INFLOW[4] * turn
    lateral = (TRUTH_INFLOW[2] if beta_r >= 0.0 else TRUTH_INFLOW[3]) * speed * beta_r
    normal = (inflow_squared + lateral**2) * math.sin(0.3 - math.atan2(lateral, math.sqrt(inflow_squared)))
    assert sway[0, 6] == pytest.approx(-normal * math.cos(0.3), rel=1e-12)
    assert surge[0, 7] == pytest.approx(-normal * math.sin(0.3), rel=1e-12)


def test_a_turn_to_port_mirrors_one_to_starboard_where_the_form_is_symmetric(model_preset, truth):
    """With gamma_R the same for both signs of beta_R, nothing in the form tells port from starboard."""
    from dataclasses import replace

    model = ShipModel(model_preset)
    inflow = truth.form.inflow.copy()
    inflow[3] = inflow[2]
    symmetric = replace(truth, form=replace(truth.form, inflow=inflow))
    starboard, port = _turn(model, symmetric, 1.0), _turn(model, symmetric, -1.0)
    for key in ("advance_lengths", "tactical_diameter_lengths", "speed_loss"):
        assert port[key] == pytest.approx(starboard[key], rel=1e-9)


def test_the_file_reads_back_as_written(tmp_path, truth):
    path = tmp_path / "hull.yaml"
    path.write_text(yaml.safe_dump(mmg_document(truth, {"Y_v": 0.01}, {"command": "test"})))
    read = read_mmg(path)
    for section in ("inflow", "surge", "sway", "yaw"):
        assert np.array_equal(getattr(read.form, section), getattr(truth.form, section))
    assert read.form.body == truth.form.body
    assert (read.rudder_rate, read.propeller_rate) == pytest.approx((truth.rudder_rate, truth.propeller_rate))


# -- identification ----------------------------------------------------------------------------------------------
def test_exact_logs_give_the_ships_forces_and_its_hard_over_turn_back(model_preset, truth, exact_logs):
    """From six zig-zags' logs alone (5 Hz, no noise), the forces explain 99.99 % of what moved the ship, and the
    hard-over turn, at an r* twice the zig-zags', comes back within 0.5 % on every figure and the 10/10 overshoot
    within 0.05 deg: only the smoother's interpolation between samples stands between the logs and the states
    (the exact states give the coefficients back to the last digit). The rudder's inflow parameters are weakly
    determined at the runs' one propeller rate (b_un about 7.1 against 6.5), what they predict is not; the wake's
    change with the drift at the propeller, which the turn's drift sails far beyond the zig-zags', comes back to
    0.05 % (0.7003 against 0.7). With the smoother's acceleration half a sample late (a discrete white-noise jerk)
    the rate of turn was 5.7 % off."""
    model = ShipModel(model_preset)
    identified = identify(exact_logs, model, jackknife=False)
    assert min(identified.fitted.determination) > 0.9999
    assert identified.record.form.inflow[INFLOW_TERMS.index("wake_drift")] == pytest.approx(TRUTH_INFLOW[5], rel=0.01)
    assert identified.record.coverage["rate"][1] < 0.6 * _turn_rate_star(model, truth)
    predicted, expected = _judged(model, identified.record), _judged(model, truth)
    for key, _, relative in BOUNDS:
        error = predicted[key] - expected[key]
        assert (abs(error) / abs(expected[key]) < 0.005) if relative else (abs(error) < 0.05), key


def _turn_rate_star(model: ShipModel, record: MmgRecord) -> float:
    figures = _turn(model, record)
    speed = model.service_speed * (1.0 - figures["speed_loss"] / 100.0)
    return model.length * math.radians(figures["steady_rate_of_turn"]) / speed


@pytest.fixture(scope="module")
def fitted_by_command(model_preset: Path, truth: MmgRecord, tmp_path_factory: pytest.TempPathFactory):
    """``ship-env fit-mmg`` on the zig-zags logged by the basin's sensors (2 cm position, 0.2 deg heading, 5 mm/s
    speed): (the file written, what it printed)."""
    import contextlib
    import io

    folder = tmp_path_factory.mktemp("noisy")
    model = ShipModel(model_preset)
    for kind, logs in (
        ("zigzag", _zigzags(model, truth, SensorNoise(), seed=5)),
        ("turning", _turns(model, truth, SensorNoise())),
    ):
        (folder / kind).mkdir()
        for log in logs:
            write_log(log, folder / kind / f"{log.name}.csv")
    output = folder / "hull.yaml"
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        arguments = ["--validate-on", str(folder / "turning"), "--plot", str(folder / "sailed.png"), "-o", str(output)]
        arguments += ["--preset", str(folder / "sailed_by_hull.yaml")]
        assert main(["fit-mmg", str(folder / "zigzag"), "--ship", str(model_preset), *arguments]) == 0
    return output, printed.getvalue()


def test_noisy_logs_give_the_turn_within_the_bounds_and_say_it_sails_beyond_the_runs(
    model_preset, truth, fitted_by_command
):
    output, printed = fitted_by_command
    fitted = read_mmg(output)
    assert len(fitted.folds) == 6  # one per run left out
    model = ShipModel(model_preset)
    assert _within_bounds(_judged(model, fitted), _judged(model, truth)) == []
    assert "+-" in printed  # the folds' spread of each figure
    beyond = printed.split("beyond the fitted runs")[1]
    assert "turning circle 35 deg stbd: r* up to" in beyond and "speed down to" in beyond


def _sailed_free_rows(printed: str, run: str) -> dict[str, tuple[float, float]]:
    """A run's rows of the command's table of the runs sailed free: figure -> (measured, predicted)."""
    block = printed.split("manoeuvres sailed free")[1]
    rows = {}
    for line in block.splitlines():
        match = re.match(rf"{run}\s+\S+\s+(.+?),\s+\S+\s+(\S+)\s+(\S+)(?:\s*\+-\S+)?\s+\S+$", line)
        if match:
            rows[match[1]] = (float(match[2]), float(match[3]))
    return rows


def test_turning_runs_never_fitted_are_sailed_free_within_the_bounds_and_the_zigzags_by_their_folds(
    fitted_by_command,
):
    """``fit-mmg --validate-on`` sails the turning runs it never saw through their own rudder programme, from their
    measured start: the issue's bounds hold, measured against predicted (advance and tactical diameter 5 %, the
    steady rate 10 %); each fitted zig-zag is sailed by the fold that left it out (first overshoot within 2 deg)."""
    output, printed = fitted_by_command
    for side in ("stbd", "port"):
        rows = _sailed_free_rows(printed, f"turning_35_{side}")
        for figure, bound in (("advance", 0.05), ("tactical diameter", 0.05), ("steady rate of turn", 0.10)):
            measured, predicted = rows[figure]
            assert abs(predicted - measured) <= bound * abs(measured), (side, figure, measured, predicted)
    for run in ("zigzag_10_10", "zigzag_-20_20", "zigzag_35_5"):
        measured, predicted = _sailed_free_rows(printed, run)["first overshoot"]
        assert abs(predicted - measured) <= 2.0, (run, measured, predicted)
    assert "disagrees:" not in printed
    assert (output.parent / "sailed.png").stat().st_size > 0


def test_the_truth_sails_its_own_turning_runs_back_from_their_measured_start(model_preset, truth):
    """The free-running validation sails a run from its measured state at the first execute: the ship that sailed
    the runs gives their figures back, within the track the ship sails in one sample interval (the execute is read
    at the samples), and the speed it loses within 1 % (the run's speed read at a sample)."""
    from ship_env.workbench.judging.free_running import compare_free_running

    model = ShipModel(model_preset)
    logs = _turns(model, truth, EXACT)
    sample = model.service_speed * 0.2 / model.length  # L sailed in one sample interval
    for result in compare_free_running(ReplayModel(model), logs, dynamics=partial(MmgFitted, truth)):
        assert not result.cannot_sail
        figures = {m.key: (m.value, p.value) for m, p in zip(result.measured, result.predicted, strict=True)}
        for key in ("advance_lengths", "transfer_lengths", "tactical_diameter_lengths"):
            measured, predicted = figures[key]
            assert abs(predicted - measured) <= sample, (result.run, key, measured, predicted)
        measured, predicted = figures["speed_loss"]
        assert abs(predicted - measured) <= 1.0, (result.run, measured, predicted)


def _turning_rows(printed: str) -> list[str]:
    """The turning circles' rows of a report, the jackknife errors and the alignment left out."""
    block = printed.split("Turning circle")[1].split("Zig-zag")[0]
    return [" ".join(re.sub(r"\s*\+-\S+", "", line).split()) for line in block.splitlines() if line.strip()]


def test_the_fitted_file_sails_in_the_manoeuvres_and_the_environments(
    model_preset, fitted_by_command, tmp_path, capsys
):
    """``ship-env manoeuvre --dynamics FILE`` gives the turning circles ``fit-mmg`` printed (sailed here without the
    folds, for time); ``gym.make(..., dynamics=FILE)`` sails it."""
    output, printed = fitted_by_command
    document = yaml.safe_load(output.read_text())
    document["jackknife"]["folds"] = []
    alone = tmp_path / "alone.yaml"
    alone.write_text(yaml.safe_dump(document))
    arguments = ["--ship", str(model_preset), "--dynamics", str(alone), "--dt", "0.2"]
    assert main(["manoeuvre", *arguments, "--turn-angle", "35", "-35", "--zigzag", "10/10"]) == 0
    assert _turning_rows(capsys.readouterr().out) == _turning_rows(printed)
    env = gym.make("ship_env/CourseChange-v0", ship=str(model_preset), dynamics=str(output))
    env.reset(seed=0)
    for _ in range(5):
        _, _, terminated, truncated, _ = env.step(env.action_space.sample())
    assert not terminated and not truncated
    assert env.unwrapped.batch.simulator.adapters[0].record.source == str(output)
    env.close()


def test_a_preset_written_with_its_fitted_model_sails_it_by_default_everywhere(model_preset, fitted_by_command, capsys):
    """``fit-mmg --preset P``: ``manoeuvre --ship P`` sails the preset's ``dynamics:`` block as ``--dynamics FILE``
    sails the fitted file (the same turning circles, digit for digit), ``gym.make(..., ship=P)`` sails it and
    ``dynamics="native"`` the preset's own effects; the preset carries the runs' propeller rate and speed."""
    from ship_env.model.external import ExternalSimulator

    output, _ = fitted_by_command
    preset = output.parent / "sailed_by_hull.yaml"
    model = ShipModel(preset)
    record = read_mmg(output)
    assert model.ship.dynamics is not None
    assert np.array_equal(model.ship.dynamics.form.yaw, record.form.yaw)
    assert model.service_propeller_rate == record.propeller_rate
    assert model.service_speed == record.service_speed
    common = ["--ship", str(preset), "--dt", "0.2", "--turn-angle", "35", "-35", "--zigzag", "10/10"]
    assert main(["manoeuvre", *common]) == 0
    by_default = capsys.readouterr().out
    assert "sailed by its preset's dynamics" in by_default
    assert main(["manoeuvre", *common, "--dynamics", str(output)]) == 0
    assert _turning_rows(by_default) == _turning_rows(capsys.readouterr().out)
    env = gym.make("ship_env/CourseChange-v0", ship=str(preset))
    env.reset(seed=0)
    env.step(env.action_space.sample())
    assert isinstance(env.unwrapped.batch.simulator.adapters[0], MmgFitted)
    native = gym.make("ship_env/CourseChange-v0", ship=str(preset), dynamics="native")
    native.reset(seed=0)
    assert not isinstance(native.unwrapped.batch.simulator, ExternalSimulator)


def test_a_preset_sailed_by_its_fitted_model_scales_as_froude_says(fitted_by_command, tmp_path):
    """``ship-env scale`` of a preset with a ``dynamics:`` block: the rigid body, steering rate, propeller rate and
    speed scale, the non-dimensional coefficients stay: the scaled ship turns the same circle in ship lengths,
    at lambda^-1/2 the rate of turn."""
    output, _ = fitted_by_command
    preset = output.parent / "sailed_by_hull.yaml"
    scaled = tmp_path / "full_scale.yaml"
    assert main(["scale", str(preset), "--length", "320", "-o", str(scaled)]) == 0
    factor = 320.0 / ShipModel(preset).length
    small, large = ShipModel(preset), ShipModel(scaled)
    assert large.ship.dynamics is not None and large.ship.dynamics.form.body.length == pytest.approx(320.0)
    assert large.service_propeller_rate == pytest.approx(small.service_propeller_rate / math.sqrt(factor))
    figures = [
        {f.key: f.value for f in turning_circle(ship, ship.rudder_limit, TrialSettings(dt=dt)).figures()}
        for ship, dt in ((small, 0.2), (large, 0.2 * math.sqrt(factor)))
    ]
    for key in ("advance_lengths", "tactical_diameter_lengths", "speed_loss"):
        assert figures[1][key] == pytest.approx(figures[0][key], rel=1e-6), key
    rate = figures[1]["steady_rate_of_turn"] * math.sqrt(factor)
    assert rate == pytest.approx(figures[0]["steady_rate_of_turn"], rel=1e-6)


def test_a_fit_on_runs_to_the_hard_over_rudder_writes_a_preset_sailed_by_the_mmg_forces(
    model_preset, truth, fitted_by_command, tmp_path, capsys
):
    """``fit --preset`` on zig-zags up to the hard-over rudder: the runs sailed free by the folds choose the MMG
    forces over the effects, and the preset sails them by default: its hard-over turn within the issue's bounds of
    the truth's, where its own effects (``dynamics="native"``) miss one."""
    output, _ = fitted_by_command
    preset = tmp_path / "fitted.yaml"
    arguments = ["--ship", str(model_preset), "--preset", str(preset), "--validate-on", str(output.parent / "turning")]
    assert main(["fit", str(output.parent / "zigzag"), *arguments]) == 0
    printed = capsys.readouterr().out
    assert "the preset sails the MMG model: its score" in printed
    sailed = printed.split("the --validate-on runs sailed free by the MMG model")[1]
    for side in ("stbd", "port"):  # the turning runs it never saw, as the preset sails them
        rows = _sailed_free_rows("manoeuvres sailed free" + sailed, f"turning_35_{side}")
        measured, predicted = rows["tactical diameter"]
        assert abs(predicted - measured) <= 0.05 * measured, (side, measured, predicted)
    document = yaml.safe_load(preset.read_text())
    choice = document["fitted"]["dynamics"]
    assert choice["sailed_by"] == "mmg_3dof" and choice["mmg_score"] < 0.95 * choice["effects_score"]
    model = ShipModel(preset)

    def judged(dynamics: str | None) -> dict[str, float]:
        settings = TrialSettings(dt=0.2, dynamics=dynamics)
        turn = turning_circle(model.without_coverage_check(), model.rudder_limit, settings).figures()
        overshoot = zigzag(model.without_coverage_check(), math.radians(10.0), math.radians(10.0), settings).figures()
        return {f.key: f.value for f in (*turn, *overshoot)}

    expected = _judged(ShipModel(model_preset), truth)
    assert _within_bounds(judged(None), expected) == []
    assert _within_bounds(judged("native"), expected) != []


def test_runs_the_mmg_form_cannot_be_fitted_to_leave_the_effects_preset_written(
    model_preset, fitted_by_command, tmp_path, capsys, monkeypatch
):
    """A run inverse dynamics cannot smooth (a gap in its time, say) stops the MMG fit, not the command: the preset
    sails its effects and says why."""
    from ship_env.workbench.fitting import inverse_dynamics
    from ship_env.workbench.fitting.smoothing import SmoothingError

    def gap(*args, **kwargs):
        raise SmoothingError("log 'zigzag_10_10': a gap of 3 s in its time")

    monkeypatch.setattr(inverse_dynamics, "identify", gap)
    output, _ = fitted_by_command
    preset = tmp_path / "fitted.yaml"
    assert main(["fit", str(output.parent / "zigzag"), "--ship", str(model_preset), "--preset", str(preset)]) == 0
    assert "the preset sails the effects: the MMG form: log 'zigzag_10_10': a gap" in capsys.readouterr().out
    document = yaml.safe_load(preset.read_text())
    assert "dynamics" not in document and document["fitted"]["dynamics"]["mmg_score"] == "not fitted"


def test_runs_to_the_hard_over_rudder_the_mmg_form_cannot_use_leave_the_reason_in_the_preset(
    model_preset, fitted_by_command, tmp_path, capsys, monkeypatch
):
    """Runs that reach the hard-over rudder but lack what inverse dynamics needs (here: said to sail in wind) are not
    fitted by it: the command says why, and the preset keeps it with its effects, as it keeps a lost comparison."""
    from ship_env.workbench.judging import dynamics_choice

    windy = "6 of 6 runs sail in wind beyond the anemometer's noise (zigzag_10_10, ...)"
    monkeypatch.setattr(dynamics_choice, "why_not_mmg", lambda logs, propeller_rate=None: windy)
    output, _ = fitted_by_command
    preset = tmp_path / "fitted.yaml"
    assert main(["fit", str(output.parent / "zigzag"), "--ship", str(model_preset), "--preset", str(preset)]) == 0
    reason = f"the effects: the MMG forces are not fitted: {windy}"
    assert f"the runs reach the hard-over rudder; the preset sails {reason}" in capsys.readouterr().out
    document = yaml.safe_load(preset.read_text())
    choice = document["fitted"]["dynamics"]
    assert "dynamics" not in document and choice["sailed_by"] == "effects" and choice["why"] == reason


def test_the_mmg_form_sails_the_preset_only_where_it_sails_every_run_materially_better():
    """The rule on the two scores: chosen where the MMG model's is at least ``min_gain`` below the effects'; not
    where it is not, nor where it cannot sail a run."""
    from ship_env.workbench.judging.dynamics_choice import preferred

    assert preferred(3.1, 1.5, [], 0.05) == (True, "the MMG model: its score 1.5 against 3.1")
    assert preferred(math.inf, 1.5, [], 0.05)[0]  # the effects cannot sail every run
    assert not preferred(3.1, 3.0, [], 0.05)[0]
    assert preferred(3.1, 1.5, ["zigzag_35_5"], 0.05) == (
        False,
        "the effects: the MMG model cannot sail zigzag_35_5",
    )


def test_a_run_sailed_free_is_scored_against_its_samples_on_the_workbenchs_scales(model_preset, truth):
    """``sailed_score``: the truth's own sailing of a run scores 0; its heading 1 deg off (one scale) over every
    sample, the rate of turn and speed exact, scores sqrt(1/3); a run that cannot be sailed, inf."""
    from dataclasses import replace

    from ship_env.workbench.fitting.errors import ErrorScales
    from ship_env.workbench.judging.free_running import RunFigures, Series, read_manoeuvre, sailed_score

    model = ShipModel(model_preset)
    log = _turns(model, truth, EXACT)[0]
    series = Series.of_log(log)
    assert series is not None
    result = RunFigures(log.name, read_manoeuvre(series), (), (), series)
    scales = ErrorScales.for_runs(model, [log])
    assert sailed_score([result], [log], scales) == 0.0
    turned = replace(result, predicted_series=replace(series, heading=series.heading + scales.heading))
    assert sailed_score([turned], [log], scales) == pytest.approx(math.sqrt(1.0 / 3.0), rel=1e-12)
    assert sailed_score([replace(result, cannot_sail="left its validity")], [log], scales) == math.inf


def test_the_leaderboard_sails_a_preset_with_a_fitted_model_calm_and_says_what_it_leaves_out(
    fitted_by_command,
):
    """The robustness conditions scale ship_env's model and the fitted MMG model has no wind or wave forces: the
    leaderboard's suites on such a preset are the nominal ship and its fitted uncertainty in calm water (TrackFollow
    too), each left out in a line."""
    from dataclasses import replace

    from ship_env.leaderboard.suites import DEV

    output, _ = fitted_by_command
    spec = replace(DEV, ship=str(output.parent / "sailed_by_hull.yaml"))
    suites = spec.suites()
    assert [(suite.task, suite.condition.name) for suite in suites] == [
        ("CourseChange calm", "nominal"),
        ("TrackFollow calm", "nominal"),
        ("CourseChange calm", "fitted uncertainty"),  # ships drawn from the model's jackknife
        ("TrackFollow calm", "fitted uncertainty"),
    ]
    assert suites[1].env_kwargs["disturbance"] == "calm"
    left_out = spec.left_out()
    assert len(left_out) == 5 and "CourseChange wind_current, wind_current_waves" in left_out[3]
    assert replace(DEV, ship="kvlcc2").left_out() == []


class _Fold:
    """Draws fold ``k``: the one draw :meth:`MmgRecord.drawn` makes of a generator."""

    def __init__(self, k: int) -> None:
        self.k = k

    def integers(self, count: int) -> int:
        return self.k


def test_ships_drawn_from_a_fitted_model_spread_as_its_jackknife_says(fitted_by_command):
    """Over its n folds, the drawn ships' coefficients have the jackknife's variance and mean the fitted values."""
    from ship_env.model.mmg_form import YAW_TERMS

    output, printed = fitted_by_command
    record = read_mmg(output)
    count = len(record.folds)
    draws = np.array([record.drawn(_Fold(k)).form.yaw for k in range(count)])  # type: ignore[arg-type]
    folds = np.array([fold.yaw for fold in record.folds])
    jackknife = (count - 1) / count * np.sum((folds - folds.mean(axis=0)) ** 2, axis=0)
    assert np.allclose(draws.var(axis=0), jackknife, rtol=1e-10, atol=0.0)
    assert np.allclose(draws.mean(axis=0), record.form.yaw, rtol=1e-12, atol=1e-15)
    document = yaml.safe_load(output.read_text())
    assert [document["yaw"][name]["std_error"] for name in YAW_TERMS] == pytest.approx(np.sqrt(jackknife))


def test_a_preset_sailed_by_its_fitted_model_draws_each_episodes_ship_from_its_seed(fitted_by_command):
    """``ship_variation="fitted"`` on a preset with a ``dynamics:`` block: each reset's adapter sails a ship drawn
    from the model's jackknife, the same for the same seed."""
    output, _ = fitted_by_command
    env = gym.make("ship_env/CourseChange-v0", ship=str(output.parent / "sailed_by_hull.yaml"), ship_variation="fitted")

    def sailed(seed: int) -> np.ndarray:
        env.reset(seed=seed)
        env.step(env.action_space.sample())
        return env.unwrapped.batch.simulator.adapters[0].sailed.form.sway

    first, again = sailed(1), sailed(1)
    assert np.array_equal(first, again)
    assert len({tuple(sailed(seed)) for seed in range(2, 12)}) > 1
    env.close()


def test_training_on_a_preset_sailed_by_its_fitted_model_draws_from_its_jackknife(fitted_by_command, tmp_path):
    """``ship-env train --ship FILE --ship-variation fitted`` on a ``fit-mmg --preset`` preset, whose effects carry
    no standard errors: its ships are drawn from the MMG model's jackknife, as the environments and the leaderboard
    draw them (it was refused, "gives none for yaw.gain, yaw.time_constant")."""
    import json

    output, _ = fitted_by_command
    config = tmp_path / "ppo.yaml"
    entry = {"n_envs": 2, "n_steps": 64, "batch_size": 64, "n_epochs": 1, "policy_kwargs": {"net_arch": [8]}}
    config.write_text(yaml.safe_dump({"ship_env/CourseChange-v0": entry}))
    preset = output.parent / "sailed_by_hull.yaml"
    assert ShipModel(preset).ship.std_errors == {}
    arguments = ["--steps", "128", "--config", str(config), "--no-progress", "--out", str(tmp_path / "run")]
    assert main(["train", "--algo", "ppo", "--ship", str(preset), "--ship-variation", "fitted", *arguments]) == 0
    metadata = json.loads((tmp_path / "run" / "metadata.json").read_text())
    assert metadata["env_kwargs"]["ship"] == str(preset) and metadata["env_kwargs"]["ship_variation"] == "fitted"


def test_a_preset_sailed_by_a_fit_without_its_jackknife_draws_no_ships(tmp_path, fitted_by_command):
    """``ship_variation="fitted"`` on a preset whose MMG model has no jackknife (``fit-mmg --no-jackknife``) is refused
    when the environment is made, saying why, not at its first episode."""
    output, _ = fitted_by_command
    document = yaml.safe_load((output.parent / "sailed_by_hull.yaml").read_text())
    del document["dynamics"]["jackknife"]
    alone = tmp_path / "without_jackknife.yaml"
    alone.write_text(yaml.safe_dump(document))
    gym.make("ship_env/CourseChange-v0", ship=str(alone))  # sails nominal
    with pytest.raises(ValueError, match=r"ship_variation='fitted': .*its jackknife has 0 folds; ships are drawn from"):
        gym.make("ship_env/CourseChange-v0", ship=str(alone), ship_variation="fitted")


def test_a_preset_whose_dynamics_block_is_malformed_is_refused_naming_the_field(tmp_path, fitted_by_command):
    output, _ = fitted_by_command
    document = yaml.safe_load((output.parent / "sailed_by_hull.yaml").read_text())
    del document["dynamics"]["rigid_body"]["draught"]
    broken = tmp_path / "broken.yaml"
    broken.write_text(yaml.safe_dump(document))
    with pytest.raises(ValueError, match=r"broken\.yaml: dynamics: rigid_body\.draught: expected a finite number"):
        ShipModel(broken)


def test_a_dynamics_option_that_cannot_be_sailed_is_named(model_preset, fitted_by_command, tmp_path, capsys):
    missing = tmp_path / "missing.yaml"
    with pytest.raises(SystemExit) as stopped:
        main(["manoeuvre", "--ship", str(model_preset), "--dynamics", str(missing)])
    assert stopped.value.code == 2
    assert f"argument --dynamics: dynamics: cannot read {str(missing)!r}" in capsys.readouterr().err
    output, _ = fitted_by_command  # fitted on the 7 m model; kvlcc2 is 320 m long
    with pytest.raises(SystemExit) as stopped:
        main(["manoeuvre", "--ship", "kvlcc2", "--dynamics", str(output)])
    assert stopped.value.code == 2
    assert "was fitted to a ship of length 7 m; --ship kvlcc2 is 320 m long" in capsys.readouterr().err


def test_uneven_sampling_rudder_orders_and_a_stated_propeller_rate_give_the_same_fit(model_preset, truth, exact_logs):
    """A log sampled at uneven intervals (interpolated onto even ones), one of rudder orders (followed at the
    steering machine's rate) and one without its constant propeller rate (given instead) are the same runs: the
    fitted turn is within 1 % of the one fitted to the logs as sailed."""
    from dataclasses import replace

    model = ShipModel(model_preset)
    jitter = np.random.default_rng(2).uniform(-0.03, 0.03, len(exact_logs[0].time))
    jitter[0] = jitter[-1] = 0.0

    def uneven(log: Log) -> Log:
        time = log.time + jitter[: len(log.time)] * (log.time[1] - log.time[0])
        channels = ("heading", "rudder", "rate_of_turn", "north", "east", "speed")
        return replace(log, time=time, **{name: np.interp(time, log.time, getattr(log, name)) for name in channels})

    orders = _zigzags(model, truth, EXACT, rudder_kind="ordered")  # the same runs, their orders logged
    assert orders[2].rudder_kind == "ordered" and not np.allclose(orders[2].rudder, exact_logs[2].rudder)
    changed = [uneven(exact_logs[0]), replace(exact_logs[1], propeller_rate=None), *orders[2:]]
    expected = _turn(model, identify(exact_logs, model, jackknife=False).record)
    predicted = _turn(model, identify(changed, model, jackknife=False, propeller_rate=PROPELLER_RATE).record)
    for key in ("advance_lengths", "tactical_diameter_lengths", "speed_loss"):
        assert predicted[key] == pytest.approx(expected[key], rel=0.01), key


def test_runs_with_gaps_in_their_time_are_smoothed_between_them_and_give_the_same_fit(model_preset, exact_logs):
    """A logger that dropped samples: 3 s gone from the middle of two runs, 2 s four samples after another's start.
    Each run is smoothed piece by piece between its gaps (no filter bridges them), so the fitted turn is within 1 %
    of the one fitted to the whole runs; before, the first gap stopped the fit ("split the run there")."""
    from dataclasses import replace

    from ship_env.workbench.fitting.smoothing import pieces_between_gaps, smooth_run

    model = ShipModel(model_preset)

    def dropped(log: Log, start: int, count: int) -> Log:
        kept = np.r_[0:start, start + count : len(log.time)]
        return replace(log, **{name: getattr(log, name)[kept] for name in log.channels()})

    gapped = [dropped(exact_logs[0], 300, 15), dropped(exact_logs[1], 450, 15), dropped(exact_logs[2], 4, 10)]
    assert [len(pieces_between_gaps(log)) for log in gapped] == [2, 2, 1]  # a piece of 4 samples is left out
    whole = smooth_run(exact_logs[0], model.length, math.radians(15.0), PROPELLER_RATE)
    cut = smooth_run(gapped[0], model.length, math.radians(15.0), PROPELLER_RATE)
    assert 0 < np.count_nonzero(cut.kept) < np.count_nonzero(whole.kept)
    expected = _turn(model, identify(exact_logs, model, jackknife=False).record)
    predicted = _turn(model, identify([*gapped, *exact_logs[3:]], model, jackknife=False).record)
    for key in ("advance_lengths", "tactical_diameter_lengths", "speed_loss"):
        assert predicted[key] == pytest.approx(expected[key], rel=0.01), key


def test_a_run_whose_pieces_between_gaps_are_all_short_is_refused_naming_it(model_preset, exact_logs):
    from dataclasses import replace

    model = ShipModel(model_preset)
    log = exact_logs[0]
    starts = np.arange(0, len(log.time), 40)  # 12 samples every 8 s: pieces of 2.4 s, each under a ship length
    chopped = np.sort(np.concatenate([starts + k for k in range(12)]))
    chopped = chopped[chopped < len(log.time)]
    short = replace(log, **{name: getattr(log, name)[chopped] for name in log.channels()})
    with pytest.raises(SmoothingError, match=f"log '{log.name}': time: its .* piece"):
        identify([short, *exact_logs[1:]], model, jackknife=False)


def test_the_mmg_form_is_tried_only_where_the_runs_reach_the_hard_over_rudder_in_calm_air(model_preset, exact_logs):
    """``fit``/``improve --preset`` try the MMG form where the runs reach the hard-over rudder (here the 35/5
    zig-zags) and log what it needs; not without a propeller rate (which the preset's service conditions may give),
    nor in wind, nor for runs that stop short of hard over."""
    from dataclasses import replace

    from ship_env.workbench.judging.dynamics_choice import mmg_applies, why_not_mmg

    model = ShipModel(model_preset)
    assert mmg_applies(exact_logs, model)
    unpropelled = [replace(exact_logs[0], propeller_rate=None), *exact_logs[1:]]
    assert not mmg_applies(unpropelled, model)
    assert why_not_mmg(unpropelled) == "1 of 6 runs log no propeller rate (zigzag_10_10)"
    # A preset that states the rate gives it to a log without the channel, as the replay takes it.
    document = yaml.safe_load(model_preset.read_text())
    document["service_conditions"] = {"propeller_rate": {"value": PROPELLER_RATE, "unit": "rps", "source": "basin"}}
    stated = model_preset.parent / "kvlcc2_model_at_its_rate.yaml"
    stated.write_text(yaml.safe_dump(document))
    assert mmg_applies(unpropelled, ShipModel(stated)) and why_not_mmg(unpropelled, PROPELLER_RATE) == ""
    assert not mmg_applies(exact_logs[:4], model)  # 10/10 and 20/20 only
    windy = replace(
        exact_logs[0],
        wind_speed=np.full_like(exact_logs[0].time, 3.0),
        wind_direction=np.zeros_like(exact_logs[0].time),
    )
    assert not mmg_applies([windy, *exact_logs[1:]], model)
    assert why_not_mmg([windy]).startswith("1 of 1 runs sail in wind beyond the anemometer's noise (zigzag_10_10)")


# -- bad input ---------------------------------------------------------------------------------------------------
def test_a_log_without_a_position_is_refused_naming_the_run_and_the_channel(model_preset, exact_logs):
    from dataclasses import replace

    logs = [replace(exact_logs[0], north=None, east=None), *exact_logs[1:]]
    with pytest.raises(
        SmoothingError, match=r"log 'zigzag_10_10': inverse dynamics needs the position \(channels 'north' and 'east'\)"
    ):
        identify(logs, ShipModel(model_preset), jackknife=False)


def test_one_run_is_refused(model_preset, exact_logs):
    with pytest.raises(IdentificationError, match="at least two runs, got 1"):
        identify(exact_logs[:1], ShipModel(model_preset))


def test_a_file_of_another_kind_is_refused_naming_the_field(tmp_path, model_preset):
    with pytest.raises(ValueError, match=r"kind: expected 'mmg_3dof'"):
        read_mmg(model_preset)
    path = tmp_path / "broken.yaml"
    path.write_text("kind: mmg_3dof\nrigid_body: {length: 7}\n")
    with pytest.raises(ValueError, match=r"rigid_body\.breadth: expected a finite number"):
        read_mmg(path)


def test_sailing_it_in_wind_is_refused_naming_the_condition(truth):
    from ship_env.model.external import ShipMotion
    from ship_env.model.simulator import Conditions

    with pytest.raises(ValueError, match="no wind or wave forces"):
        MmgFitted(truth).reset(ShipMotion(0.0, 0.0, 0.0, 0.0, 1.0), Conditions(wind_speed=5.0), 0)
