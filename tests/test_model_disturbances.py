"""Current, wind and waves (thesis 2.5) against closed forms, symmetry and spectra."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CONTAINER, SPEED, run
from scipy import signal

from ship_env.model import Conditions, ShipModel
from ship_env.model import state as S
from ship_env.model.effects import wave_spectrum, wind, wind_drift, wind_moment


def test_current_moves_a_ship_at_rest_by_exactly_uc_t():
    """(2.71, 2.72) with u = 0: the position is U_c t in the direction psi_c."""
    model = ShipModel(CONTAINER, ["yaw", "kinematics", "current"])  # no apparent wind from the drift
    current_speed, current_direction = 1.3, math.radians(225.0)  # setting towards SW
    conditions = Conditions(service_speed=0.0, current_speed=current_speed, current_direction=current_direction)
    history = run(model, 0.0, duration=600.0, dt=1.0, conditions=conditions)
    time = history[:, S.TIME]
    np.testing.assert_allclose(history[:, S.NORTH], current_speed * time * math.cos(current_direction), atol=1e-9)
    np.testing.assert_allclose(history[:, S.EAST], current_speed * time * math.sin(current_direction), atol=1e-9)
    assert np.all(history[:, S.HEADING] == 0.0)


def test_current_adds_to_the_ships_own_velocity():
    model = ShipModel(CONTAINER, ["yaw", "kinematics", "current"])
    heading = math.radians(60.0)
    conditions = Conditions(current_speed=1.0, current_direction=math.radians(300.0))
    history = run(model, 0.0, duration=300.0, dt=1.0, conditions=conditions, heading=heading)
    speed, t = model.service_speed, history[-1, S.TIME]
    assert history[-1, S.NORTH] == pytest.approx(
        t * (speed * math.cos(heading) + math.cos(math.radians(300.0))), abs=1e-8
    )
    assert history[-1, S.EAST] == pytest.approx(
        t * (speed * math.sin(heading) + math.sin(math.radians(300.0))), abs=1e-8
    )


def test_tidal_current_speed_variation_averages_out_over_a_period():
    period = 600.0
    model = ShipModel(CONTAINER, ["yaw", "kinematics", "current"], {"current.variation": 0.5, "current.period": period})
    conditions = Conditions(service_speed=0.0, current_speed=2.0, current_direction=0.0)
    history = run(model, 0.0, duration=period, dt=0.5, conditions=conditions)
    assert history[-1, S.NORTH] == pytest.approx(2.0 * period, rel=1e-9)
    quarter = history[int(period / 4 / 0.5), S.NORTH]
    assert quarter > 2.0 * period / 4 * 1.2  # faster than the mean in the first quarter


def _apparent_wind(heading, north_velocity, east_velocity, wind_speed, wind_direction):
    """(V_wr, gamma_r) from ``wind.relative_wind``'s speed and direction cosines, with the true wind's
    velocity as the conditions row derives it."""
    row = Conditions(wind_speed=wind_speed, wind_direction=wind_direction).row(0.0)
    speed, cos_angle, sin_angle = wind.relative_wind(
        math.cos(heading), math.sin(heading), north_velocity, east_velocity, row[S.WIND_NORTH], row[S.WIND_EAST]
    )
    return speed, math.atan2(sin_angle, cos_angle)


def test_relative_wind_is_true_wind_minus_the_ships_velocity():
    """(2.74): no true wind gives a head wind at the ship's speed; vector sum otherwise."""
    speed, angle = _apparent_wind(0.3, 9.5 * math.cos(0.3), 9.5 * math.sin(0.3), 0.0, 0.0)
    assert speed == pytest.approx(9.5) and angle == pytest.approx(0.0, abs=1e-12)
    # Ship heading north at 10 m/s, true wind 10 m/s from the east: apparent 14.1 m/s from 45 deg to starboard.
    speed, angle = _apparent_wind(0.0, 10.0, 0.0, 10.0, math.radians(90.0))
    assert speed == pytest.approx(10.0 * math.sqrt(2.0)) and angle == pytest.approx(math.radians(45.0))
    # Heading east: the same wind is now dead ahead, 20 m/s.
    speed, angle = _apparent_wind(math.radians(90.0), 0.0, 10.0, 10.0, math.radians(90.0))
    assert speed == pytest.approx(20.0) and angle == pytest.approx(0.0, abs=1e-12)
    # Ship at rest, wind from the port quarter (heading north, wind from 225 deg): gamma_r = -135 deg.
    speed, angle = _apparent_wind(0.0, 0.0, 0.0, 5.0, math.radians(225.0))
    assert speed == pytest.approx(5.0) and angle == pytest.approx(math.radians(-135.0))


@pytest.mark.parametrize("angle_deg", [0.0, 90.0, -90.0, 180.0])
def test_wind_moment_vanishes_head_on_beam_on_and_astern(angle_deg):
    """(2.84): C_n = a_n sin(2 gamma_r)."""
    largest = 1e-6 * 15.0**2
    angle = math.radians(angle_deg)
    assert abs(wind_moment.yaw_acceleration(15.0, math.cos(angle), math.sin(angle), 1e-6, 0.0)) < 1e-15 * largest


@pytest.mark.parametrize("angle_deg", [0.0, 180.0])
def test_beam_wind_moment_vanishes_head_on_and_astern_only(angle_deg):
    """C_n = b_n sin(gamma_r): no moment head-on or astern; largest beam-on, into the wind for b_n > 0."""
    angle = math.radians(angle_deg)
    assert abs(wind_moment.yaw_acceleration(15.0, math.cos(angle), math.sin(angle), 0.0, 1e-6)) < 1e-15 * 1e-6 * 15.0**2
    beam = math.radians(90.0)
    assert wind_moment.yaw_acceleration(15.0, math.cos(beam), math.sin(beam), 0.0, 1e-6) == pytest.approx(
        1e-6 * 15.0**2
    )


def test_wind_moment_flips_with_the_side_the_wind_comes_from():
    angle = math.radians(40.0)
    starboard = wind_moment.yaw_acceleration(15.0, math.cos(angle), math.sin(angle), 1e-6, 3e-7)
    port = wind_moment.yaw_acceleration(15.0, math.cos(-angle), math.sin(-angle), 1e-6, 3e-7)
    expected = (1e-6 * math.sin(2 * angle) + 3e-7 * math.sin(angle)) * 15.0**2
    assert starboard == pytest.approx(-port) and starboard == pytest.approx(expected)


def test_still_air_does_not_slow_the_ship():
    """U0 is the still-air speed: the apparent wind of the ship's own motion adds no resistance."""
    model = ShipModel(CONTAINER).without_effects("gusts")
    history = run(model, 0.0, duration=600.0, dt=1.0)
    assert history[-1, SPEED] == pytest.approx(model.service_speed, rel=1e-12)


def test_head_wind_on_a_straight_ship_leaves_it_straight_and_slows_it():
    model = ShipModel(CONTAINER).without_effects("gusts")
    history = run(model, 0.0, duration=600.0, dt=1.0, conditions=Conditions(wind_speed=15.0, wind_direction=0.0))
    assert np.all(history[:, S.RATE_OF_TURN] == 0.0)
    assert np.all(history[:, S.EAST] == 0.0)
    assert history[-1, SPEED] < model.service_speed  # wind resistance (2.86, 2.88)


def test_wind_from_either_bow_gives_mirrored_tracks():
    model = ShipModel(CONTAINER).without_effects("gusts")
    starboard = run(
        model, 0.0, duration=600.0, dt=1.0, conditions=Conditions(wind_speed=12.0, wind_direction=math.radians(50.0))
    )
    port = run(
        model, 0.0, duration=600.0, dt=1.0, conditions=Conditions(wind_speed=12.0, wind_direction=math.radians(-50.0))
    )
    np.testing.assert_allclose(starboard[:, S.NORTH], port[:, S.NORTH], rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(starboard[:, S.EAST], -port[:, S.EAST], rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(starboard[:, S.HEADING], -port[:, S.HEADING], rtol=1e-12, atol=1e-12)
    # The container preset's bow falls off the wind (N_w' < 0) and the ship drifts to leeward.
    assert starboard[-1, S.HEADING] < 0.0 and starboard[-1, S.EAST] < 0.0


def test_leeway_balances_the_wind_side_force():
    """Wind drift: (C_L u + C_D |v|) v = -c_y V_wr^2 sin(gamma_r), v moving the track only."""
    model = ShipModel(CONTAINER, ["yaw", "kinematics", "wind_drift"])
    conditions = Conditions(wind_speed=15.0, wind_direction=math.radians(90.0))
    history = run(model, 0.0, duration=100.0, dt=1.0, conditions=conditions)
    assert np.all(history[:, S.HEADING] == 0.0)
    leeway = (history[-1, S.EAST] - history[-2, S.EAST]) / 1.0
    speed = model.service_speed
    apparent_speed, apparent_angle = _apparent_wind(0.0, speed, 0.0, 15.0, math.radians(90.0))
    lift, drag, ratio = (model.parameter(f"wind_drift.{k}") for k in ("lift_slope", "crossflow_drag", "force_ratio"))
    residual = (lift * speed + drag * abs(leeway)) * leeway + ratio * apparent_speed**2 * math.sin(apparent_angle)
    assert leeway < 0.0  # wind from starboard pushes to port
    assert residual == pytest.approx(0.0, abs=1e-12)
    # At rest the cross-flow drag alone resists: v = -sqrt(c_y / C_D) V_wr.
    at_rest = wind_drift.leeway(0.0, 10.0, 1.0, ratio, lift, drag)
    assert at_rest == pytest.approx(-math.sqrt(ratio / drag) * 10.0)


def test_hf_wave_filter_spectrum_peaks_at_its_natural_frequency_and_leaves_the_track():
    """Figs. 2.13, 2.14: the wave rate is band-passed white noise with RMS sigma_r."""
    model = ShipModel(CONTAINER, ["yaw", "kinematics", "wave_filter"])
    dt = 0.2
    history = run(model, 0.0, duration=20000.0, dt=dt, seed=3)
    wave_rate = history[:, S.WAVE_RATE]
    frequency, density = signal.welch(wave_rate, fs=1.0 / dt, nperseg=4096)
    peak = 2.0 * math.pi * frequency[np.argmax(density)]
    natural_frequency = model.parameter("wave_filter.natural_frequency")
    assert peak == pytest.approx(natural_frequency, abs=2.0 * math.pi / (4096 * dt) * 1.5)
    assert np.std(wave_rate) == pytest.approx(model.parameter("wave_filter.rate_rms"), rel=0.1)
    # The waves move the measured heading, not the ship: the track is that of calm water.
    calm = run(ShipModel(CONTAINER, ["yaw", "kinematics"]), 0.0, duration=20000.0, dt=dt, seed=3)
    np.testing.assert_array_equal(history[:, : S.WAVE_HEADING], calm[:, : S.WAVE_HEADING])
    assert np.std(history[:, S.WAVE_HEADING]) > 0.0


def test_gusts_have_the_stated_intensity():
    model = ShipModel(CONTAINER)
    history = run(model, 0.0, duration=20000.0, dt=0.5, conditions=Conditions(wind_speed=10.0), seed=5)
    expected = model.parameter("gusts.intensity") * 10.0
    assert np.std(history[:, S.GUST]) == pytest.approx(expected, rel=0.1)
    assert abs(np.mean(history[:, S.GUST])) < 0.15 * expected


def test_wave_excitation_has_the_encounter_frequency_of_2_90():
    """A ship crossing one regular wave meets it at omega_e = omega_0 - omega_0^2 U cos(gamma_w) / g."""
    frequency, speed, heading = 0.6, 8.0, math.radians(30.0)
    wave_direction = math.radians(180.0)  # waves from the south travel north: gamma_w = heading
    waves = np.array([[frequency], [1.0], [0.0]])
    dt, count = 0.25, 2**14
    times = dt * np.arange(count)
    excitation = np.array(
        [
            wave_spectrum.yaw_acceleration(
                t, speed * t * math.cos(heading), speed * t * math.sin(heading), heading, wave_direction, waves, 1.0
            )
            for t in times
        ]
    )
    spectrum = np.abs(np.fft.rfft(excitation * np.hanning(count)))
    measured = 2.0 * math.pi * np.fft.rfftfreq(count, dt)[np.argmax(spectrum)]
    expected = wave_spectrum.encounter_frequency(frequency, speed, heading)
    assert expected == pytest.approx(frequency - frequency**2 * speed * math.cos(heading) / 9.81)
    assert measured == pytest.approx(abs(expected), abs=2.0 * math.pi / (count * dt))


def test_head_and_beam_seas_give_no_yaw_moment():
    """(2.91): N_g ~ sin(2 gamma_w)."""
    model = ShipModel(CONTAINER, ["yaw", "kinematics", "wave_spectrum"])
    for wave_direction in (0.0, 90.0, 180.0):
        conditions = Conditions(wave_height=3.0, wave_period=9.0, wave_direction=math.radians(wave_direction))
        history = run(model, 0.0, duration=200.0, dt=0.5, conditions=conditions)
        assert np.max(np.abs(history[:, S.RATE_OF_TURN])) < 1e-15
    quartering = Conditions(wave_height=3.0, wave_period=9.0, wave_direction=math.radians(135.0))
    history = run(model, 0.0, duration=200.0, dt=0.5, conditions=quartering)
    assert np.max(np.abs(history[:, S.RATE_OF_TURN])) > 1e-5


def test_pierson_moskowitz_components_carry_the_significant_height():
    """(2.89): H_s = 4 sqrt(m0), m0 the spectrum's area, which the components reproduce."""
    uniforms = np.full((2, 200), 0.5)
    components = wave_spectrum.components(2.5, 9.0, uniforms)
    m0 = np.sum(components[1] ** 2) / 2.0
    # 0.6..3 omega_p holds about 94% of the PM spectrum's energy.
    assert 4.0 * math.sqrt(m0) == pytest.approx(2.5, rel=0.05)
    peak = components[0, np.argmax(components[1])]
    assert peak == pytest.approx(2.0 * math.pi / 9.0, rel=0.05)
