"""The classic autopilots designed for any ship as for the reference ship, in its own scales.

The baselines' tuning (the PD loop's natural frequency, the identification trial's times, the
position filter's calibration, the course changer's distances and times) was made for the 226 m
container ship; another ship gets the same tuning in units of its length and L / U
(:mod:`ship_env.envs.ship_scales`), and the container ship exactly its own.
"""

from __future__ import annotations

import dataclasses

import gymnasium as gym
import pytest

import ship_env  # noqa: F401  (registers the environments)
from ship_env.baselines.course_changer import CourseChangerSettings
from ship_env.baselines.online_estimators.zigzag_trial import identify_by_zigzag
from ship_env.baselines.position_filter import PositionFilterNoise
from ship_env.baselines.presys import NATURAL_FREQUENCY, pd_controller, preset_parameters
from ship_env.baselines.yaw_filter import YawFilterNoise
from ship_env.envs.ship_scales import ShipScales
from ship_env.model import ShipModel

SHIPS = ("container_226m", "esso_osaka_model", "kvlcc2")


def design_of(ship: str) -> tuple[float, float]:
    """The fixed PD's closed-loop natural frequency (rad/s) and the ship's L / U (s)."""
    env = gym.make("ship_env/CourseChange-v0", ship=ship)
    task = env.unwrapped.task  # type: ignore[attr-defined]
    design = pd_controller(task, "fixed").autopilot.design
    return design.natural_frequency, task.model.length / task.model.service_speed


def test_the_reference_ship_keeps_its_natural_frequency_exactly() -> None:
    natural_frequency, _ = design_of("container_226m")
    assert natural_frequency == NATURAL_FREQUENCY


@pytest.mark.parametrize("ship", SHIPS[1:])
def test_every_ship_is_designed_for_the_reference_loop_per_ship_length(ship: str) -> None:
    """omega_n L / U, the loop's natural frequency per ship length sailed, is the container ship's
    (about 1.4): a 3 m model at 0.3 m/s and a 320 m tanker turn as briskly in ship lengths."""
    reference_frequency, reference_time = design_of("container_226m")
    natural_frequency, time = design_of(ship)
    assert natural_frequency * time == pytest.approx(reference_frequency * reference_time, rel=1e-12)
    assert natural_frequency != pytest.approx(NATURAL_FREQUENCY, rel=0.1)  # not the container's seconds


def test_calibrations_scale_by_their_units() -> None:
    """A ship twice as long sailing half as fast (time x4): lengths x2, speeds x0.5, times x4, each
    spectral density by its units squared over the time; the reference scales change nothing."""
    scales = ShipScales(length=2.0, speed=0.5)
    noise = PositionFilterNoise()
    assert noise.for_ship(ShipScales(length=1.0, speed=1.0)) == noise
    scaled = noise.for_ship(scales)
    assert scaled.position_fix == 2.0 * noise.position_fix
    assert scaled.initial_sway == 2.0 * noise.initial_sway
    assert scaled.log == 0.5 * noise.log
    assert scaled.initial_current == 0.5 * noise.initial_current
    assert scaled.speed_walk == pytest.approx(noise.speed_walk * 0.25 / 4.0)
    assert scaled.current_walk == pytest.approx(noise.current_walk * 0.25 / 4.0)
    assert scaled.sway_walk == pytest.approx(noise.sway_walk * 4.0 / 4.0)
    assert scaled.position_model == pytest.approx(noise.position_model * 4.0 / 4.0)

    settings = CourseChangerSettings(rudder_rate=0.04)
    assert settings.for_ship(ShipScales(length=1.0, speed=1.0)) == settings
    moved = settings.for_ship(scales)
    assert moved.approach_distance == 2.0 * settings.approach_distance
    assert moved.look_ahead == 2.0 * settings.look_ahead
    assert moved.prediction_step == 4.0 * settings.prediction_step
    assert moved.decision_interval == 4.0 * settings.decision_interval
    assert moved.settle_time == 4.0 * settings.settle_time
    unchanged = ("rudder_rate", "largest_correction", "settle_band", "settled_current")
    assert all(getattr(moved, name) == getattr(settings, name) for name in unchanged)
    assert {field.name for field in dataclasses.fields(CourseChangerSettings)} == {
        "rudder_rate",
        "prediction_step",
        "decision_interval",
        "approach_distance",
        "settle_time",
        "look_ahead",
        *unchanged[1:],
    }


def test_the_yaw_filter_calibration_scales_by_its_units() -> None:
    """Time x4: rates / 4, the wave time constant x 4, angles and K*, tau* kept, each spectral density by its units
    squared over the time; the reference scales change nothing."""
    noise = YawFilterNoise()
    assert noise.for_ship(ShipScales(length=1.0, speed=1.0)) == noise
    scaled = noise.for_ship(ShipScales(length=2.0, speed=0.5))
    assert scaled.wave_rate == noise.wave_rate / 4.0 and scaled.gyro == noise.gyro / 4.0
    assert scaled.wave_time_constant == 4.0 * noise.wave_time_constant
    assert scaled.compass == noise.compass and scaled.parameter_uncertainty == noise.parameter_uncertainty
    assert scaled.rate_model == pytest.approx(noise.rate_model / 4.0**2 / 4.0)  # (rad/s)^2 / s
    assert scaled.heading_model == pytest.approx(noise.heading_model / 4.0)  # rad^2 / s
    assert scaled.inverse_time_constant_walk == pytest.approx(noise.inverse_time_constant_walk / 4.0)  # 1 / s
    assert scaled.gain_ratio_walk == pytest.approx(noise.gain_ratio_walk / 4.0)
    assert scaled.offset_walk == pytest.approx(noise.offset_walk / 4.0**4 / 4.0)  # (rad/s^2)^2 / s
    assert scaled.offset_uncertainty == pytest.approx(noise.offset_uncertainty / 4.0**2)  # rad/s^2


def test_a_froude_scaled_ship_is_identified_as_the_original() -> None:
    """The identification zig-zag of the 320 m tanker and of its 7 m model (Froude-scaled: the same manoeuvre in ship
    lengths, the instruments in its scales) gives the same K*, tau* to rounding. Before the yaw filter took its
    calibration and speed floor in the ship's scales, both were filtered with the container ship's calibration in
    seconds, whatever their own L / U: K* 1.750 against 1.779, tau* 2.044 against 2.126."""
    tanker = ShipModel("kvlcc2")
    model = tanker.scaled(length=7.0)
    full = identify_by_zigzag(tanker, preset_parameters(tanker), seed=0).parameters
    small = identify_by_zigzag(model, preset_parameters(model), seed=0).parameters
    assert small.gain == pytest.approx(full.gain, rel=1e-8)
    assert small.time_constant == pytest.approx(full.time_constant, rel=1e-8)
