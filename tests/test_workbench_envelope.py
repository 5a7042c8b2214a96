"""The validity envelope: ship presets and effects state the conditions the model is valid for."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
import yaml

from ship_env.cli import main
from ship_env.model import REQUIRED_EFFECTS, ShipModel, load_ship
from ship_env.model.declarations import Envelope
from ship_env.paths import config_dir
from ship_env.workbench import FitOptions, Log, ReplayModel, fit, write_log
from ship_env.workbench.fitting.envelope import COURSE_ERROR, check_envelope, drift_angle, inside_logs
from ship_env.workbench.synthetic.synthetic import HIDDEN_VALUES, NO_NOISE, LogSettings, model_test_programme, sail_all

SHIP = "esso_osaka_model"


def test_presets_state_their_envelope_with_sources():
    ship = load_ship(SHIP)
    assert ship.envelope.minimum_speed == pytest.approx(0.1)
    assert ship.envelope.propeller_ahead_only is True
    assert ship.envelope.maximum_drift == pytest.approx(math.radians(40.0))
    assert ship.envelope.maximum_rate == pytest.approx(math.radians(10.0))
    assert "envelope.minimum_speed" in ship.assumed
    assert "envelope.propeller_ahead_only" not in ship.assumed
    assert all(f"envelope.{name}" in ship.sources for name in ("minimum_speed", "propeller_ahead_only"))


def test_an_effect_widens_the_envelope_and_never_narrows_it():
    base = Envelope(minimum_speed=0.1, propeller_ahead_only=True, maximum_drift=0.5)
    widened = base.widened(Envelope(minimum_speed=0.0, propeller_ahead_only=False), Envelope(maximum_drift=0.3))
    assert widened == Envelope(minimum_speed=0.0, propeller_ahead_only=False, maximum_drift=0.5)
    assert Envelope().widened(Envelope(minimum_speed=0.2)) == Envelope()
    assert ShipModel("esso_osaka_model").envelope == load_ship("esso_osaka_model").envelope


@pytest.mark.parametrize(
    ("entry", "message"),
    [
        ({"minimum_speed": {"value": -1.0, "unit": "m/s", "source": "x"}}, "envelope.minimum_speed"),
        ({"propeller_ahead_only": {"value": "yes", "source": "x"}}, "envelope.propeller_ahead_only"),
        ({"maximum_speed": {"value": 1.0, "source": "x"}}, "unknown limit 'maximum_speed'"),
        ({"maximum_drift": {"value": 20, "unit": "deg"}}, "source"),
    ],
)
def test_a_bad_envelope_is_rejected_naming_the_field(tmp_path, entry, message):
    document = yaml.safe_load((config_dir() / "ships" / "esso_osaka_model.yaml").read_text())
    document["envelope"] = entry
    path = tmp_path / "ship.yaml"
    path.write_text(yaml.safe_dump(document))
    with pytest.raises((TypeError, ValueError), match=message):
        load_ship(path)


def harbour_log(name: str = "harbour", astern_share: float = 0.6, samples: int = 600) -> Log:
    """A run at 0.05 m/s astern with the propeller astern, then at 0.3 m/s ahead."""
    time = np.arange(samples) * 0.1
    astern = np.arange(samples) < astern_share * samples
    return Log(
        name=name,
        time=time,
        heading=0.001 * time,
        rudder=np.zeros(samples),
        rate_of_turn=np.full(samples, 0.001),
        north=np.cumsum(np.where(astern, -0.005, 0.03)),
        east=np.zeros(samples),
        speed=np.where(astern, -0.05, 0.3),
        propeller_rate=np.where(astern, -5.0, 10.0),
    )


def test_a_run_at_0_05_m_s_astern_is_flagged_with_the_share_and_the_reason():
    model = ShipModel(SHIP)
    check = check_envelope(harbour_log(), model.envelope, model.length)
    assert check.share == pytest.approx(0.6)
    assert check.describe() == "60 % outside: 60 % below 0.1 m/s; propeller astern 60 % of the time"
    wholly = check_envelope(harbour_log(astern_share=1.0), model.envelope, model.length)
    assert wholly.describe() == (
        "wholly outside the model's envelope: 100 % below 0.1 m/s; propeller astern 100 % of the time"
    )
    # An effect that models the astern propeller widens the envelope: that reason goes.
    wider = model.envelope.widened(Envelope(propeller_ahead_only=False))
    assert check_envelope(harbour_log(), wider, model.length).reasons() == "60 % below 0.1 m/s"


def circling_log(
    drift_deg: float,
    speed: float,
    fix_noise: float,
    dt: float = 1.0,
    fix_interval: float | None = None,
    duration: float = 1200.0,
) -> Log:
    """A steady turn to starboard in closed form, apart from any simulator: the track a circle of radius
    R = U / r, the course r t, the heading the course plus the drift; the fixes with white noise of
    ``fix_noise`` m, each held until the next where ``fix_interval`` is given."""
    radius = 1000.0
    time = np.arange(0.0, duration, dt)
    course = speed / radius * time
    fixes = np.floor(time / fix_interval) * fix_interval if fix_interval else time
    noise = np.random.default_rng(0).normal(0.0, fix_noise, size=(2, len(np.unique(fixes))))
    index = np.unique(fixes, return_inverse=True)[1]
    fix_course = speed / radius * fixes
    return Log(
        name="turn",
        time=time,
        heading=course + math.radians(drift_deg),
        rudder=np.full(len(time), math.radians(35.0)),
        north=radius * np.sin(fix_course) + noise[0, index],
        east=radius * (1.0 - np.cos(fix_course)) + noise[1, index],
        speed=np.full(len(time), speed),
    )


def test_the_drift_angle_holds_under_sea_trial_fixes_and_is_exact_without_noise():
    # A 320 m tanker's hard-over turn at 3 m/s with a drift of 12 deg, GPS fixes of 3 m at 1 Hz. The course was the
    # slope of a track smoothed over 1 s: its noise alone (3 m over 1 s against 3 m/s) put half of these samples
    # beyond 30 deg. The window chosen from the fixes' own noise holds the course to COURSE_ERROR (1 deg): the
    # error's RMS within that (and 10 % for the noise's estimate and the sample's spread), no sample beyond 5 of it.
    length = 320.0
    noisy = circling_log(12.0, 3.0, 3.0)
    error = drift_angle(noisy, length) - math.radians(12.0)
    assert np.sqrt(np.mean(error**2)) <= 1.1 * COURSE_ERROR
    assert np.max(np.abs(error)) <= 5.0 * COURSE_ERROR
    envelope = Envelope(maximum_drift=math.radians(30.0))
    assert check_envelope(noisy, envelope, length).share == 0.0
    # Exact fixes: a quadratic's slope at the centre of a symmetric window on a circle is the tangent's (the two
    # samples at either end, from one-sided fits, to 1e-6 rad).
    exact = drift_angle(circling_log(12.0, 3.0, 0.0), length)
    np.testing.assert_allclose(exact[2:-2], math.radians(12.0), atol=1e-9)
    np.testing.assert_allclose(exact, math.radians(12.0), atol=1e-6)
    # A logger at 10 Hz that holds each 1 Hz fix: the course is read at the fixes, as sure as above.
    held = drift_angle(circling_log(12.0, 3.0, 3.0, dt=0.1, fix_interval=1.0), length) - math.radians(12.0)
    assert np.sqrt(np.nanmean(held**2)) <= 1.1 * COURSE_ERROR
    assert np.count_nonzero(np.isnan(held)) <= 10  # only after the last fix


def test_a_ship_too_slow_for_its_fixes_has_an_unknown_drift_angle_not_a_wild_one():
    # Two minutes of 3 m fixes at 1 Hz on a ship at 0.05 m/s: even the whole run as the window leaves the course's
    # error at 9 deg (sigma sqrt(12 / (w^3 dt^2)) / U), three times MAX_COURSE_ERROR, so the drift is NaN and no
    # sample is outside the envelope for it.
    slow = circling_log(12.0, 0.05, 3.0, duration=120.0)
    assert np.all(np.isnan(drift_angle(slow, 320.0)))
    assert check_envelope(slow, Envelope(maximum_drift=math.radians(30.0)), 320.0).share == 0.0


def test_a_run_wholly_outside_gets_a_message_not_an_error(tmp_path, capsys):
    folder = tmp_path / "logs"
    folder.mkdir()
    write_log(harbour_log("alongside", astern_share=1.0), folder / "alongside.csv")
    write_log(harbour_log("approach", astern_share=0.5), folder / "approach.csv")
    assert main(["compare", str(folder), "--ship", SHIP]) == 0
    out = capsys.readouterr().out
    assert "alongside lies wholly outside the model's envelope (100 % below 0.1 m/s; propeller astern 100 %" in out
    rows = [line for line in out.splitlines() if line.startswith("alongside ") and "lies wholly" not in line]
    assert len(rows) == 1 and "100" in rows[0]  # in the envelope table only: never scored
    assert "over the samples inside the envelope" in out and "over the samples outside the envelope" in out


def corrupted(logs: list[Log], start: float, stop: float, heading_error: float) -> list[Log]:
    """The logs with the propeller astern and a wrong heading between ``start`` and ``stop`` (shares of each run)."""
    result = []
    for log in logs:
        stretch = (np.arange(log.samples) >= start * log.samples) & (np.arange(log.samples) < stop * log.samples)
        result.append(
            replace(
                log,
                heading=np.where(stretch, log.heading + heading_error, log.heading),
                propeller_rate=np.where(stretch, -8.0, log.propeller_rate),
            )
        )
    return result


def test_fitting_on_valid_segments_ignores_the_rest():
    truth = ReplayModel(ShipModel(SHIP, [*REQUIRED_EFFECTS, "speed_loss"], HIDDEN_VALUES))
    clean = sail_all(truth, model_test_programme(duration=40.0)[::2], seed=2, settings=LogSettings(noise=NO_NOISE))
    start = truth.model.with_parameters({"yaw.gain": 1.0, "yaw.time_constant": 1.0})
    options = FitOptions(initial_window=0.0)
    fits = []
    for heading_error in (0.5, -1.0):
        logs = corrupted(clean, 0.3, 0.5, heading_error)
        segments, groups = inside_logs(logs, truth.model.envelope, truth.model.length)
        assert len(segments) >= len(logs) and set(groups) == {log.name for log in logs}
        assert all(np.all(segment.propeller_rate >= 0.0) for segment in segments)
        fits.append(fit(start, segments, options=options))
        whole = fit(start, logs, options=options)
        assert abs(whole.values()["yaw.gain"] / truth.model.parameter("yaw.gain") - 1.0) > 0.05
    # The samples outside the envelope do not reach the fit: two different corruptions, one fit.
    assert fits[0].values() == fits[1].values()
    for key, value in fits[0].values().items():
        assert value == pytest.approx(truth.model.parameter(key), rel=1e-4)


@pytest.mark.parametrize("speed", [0.15, 0.3, 0.6])
def test_norrbins_odd_quadratic_is_the_cross_flow_drag_at_any_speed(speed):
    """Norrbin's alpha2' |r*| r* adds -(alpha2' / tau*) |r| r to dr/dt: the speeds cancel (2.54, 2.40).

    That is the hull's cross-flow yaw drag of strip theory, -c |r| r, so the library has one effect for
    it (a second one with the same regressor would leave the workbench unable to tell them apart).
    """
    from ship_env.model import state as S
    from ship_env.model.dynamics import derivatives

    without = ShipModel(SHIP, REQUIRED_EFFECTS)
    with_it = without.with_effects("norrbin").with_parameters({"norrbin.cubic": 0.0, "norrbin.odd_quadratic": 0.4})
    state = np.zeros(without.state_size)
    state[S.RATE_OF_TURN] = -math.radians(2.0)
    conditions = np.zeros(S.CONDITION_SIZE)
    conditions[S.SERVICE_SPEED] = speed
    slopes = []
    for model in (without, with_it):
        out = np.zeros(without.state_size)
        derivatives(state, 0.1, conditions, np.zeros(without.state_size), np.zeros(0), 0.0, model.record[0], out)
        slopes.append(out[S.RATE_OF_TURN])
    rate = state[S.RATE_OF_TURN]
    expected = -0.4 / with_it.parameter("yaw.time_constant") * abs(rate) * rate
    assert slopes[1] - slopes[0] == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("propeller_rate", [-12.0, 12.0])
def test_a_propeller_astern_takes_the_rudder_inflow_and_walks_the_stern(propeller_rate):
    """The astern effect's closed form: for n < 0 the rudder inflow falls by c_a (n D)^2 (not below 0)
    and the side moment grows by c_w (n D)^2; for n > 0 nothing changes, and no slipstream astern."""
    from ship_env.model import state as S
    from ship_env.model.dynamics import derivatives

    values = {
        "propeller_slipstream.coefficient": 0.1,
        "propeller_astern.rudder_inflow": 0.05,
        "propeller_astern.walk": 0.02,
    }
    base = ShipModel(SHIP, [*REQUIRED_EFFECTS, "propeller_slipstream", "propeller_astern"], values)
    without = base.without_effects("propeller_astern")
    state = np.zeros(without.state_size)
    rudder = math.radians(10.0)
    conditions = np.zeros(S.CONDITION_SIZE)
    conditions[S.SERVICE_SPEED] = 0.3
    conditions[S.PROPELLER_RATE] = propeller_rate
    slopes = []
    for model in (without, base):
        out = np.zeros(without.state_size)
        derivatives(state, rudder, conditions, np.zeros(without.state_size), np.zeros(0), 0.0, model.record[0], out)
        slopes.append(out[S.RATE_OF_TURN])
    gain, time_constant = base.parameter("yaw.gain"), base.parameter("yaw.time_constant")
    induced = (propeller_rate * base.parameter("propeller_slipstream.propeller_diameter")) ** 2
    scale = time_constant * base.length**2
    if propeller_rate > 0:
        assert slopes[1] == slopes[0]
        assert slopes[0] == pytest.approx((0.3**2 + 0.1 * induced) * gain * rudder / scale, rel=1e-12)
    else:
        assert slopes[0] == pytest.approx(0.3**2 * gain * rudder / scale, rel=1e-12)  # no slipstream astern
        inflow = max(0.3**2 - 0.05 * induced, 0.0)
        assert slopes[1] == pytest.approx((inflow * gain * rudder - 0.02 * induced) / scale, rel=1e-12)
    assert base.envelope.propeller_ahead_only is False and without.envelope.propeller_ahead_only is True
