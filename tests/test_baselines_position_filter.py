"""The position filter (thesis 5.4, 6.3.3): current from 50-m fixes, a current switched off, bad fixes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ship_env.baselines.filter_health import FilterDivergenceError
from ship_env.baselines.instruments import InstrumentNoise, SimulatedInstruments
from ship_env.baselines.measurement import Measurement
from ship_env.baselines.nomoto import NomotoParameters
from ship_env.baselines.online_estimators.zigzag_trial import zigzag_rudder
from ship_env.baselines.position_filter import PositionFilter, PositionFilterNoise
from ship_env.baselines.yaw_filter import YawFilter
from ship_env.model import Conditions, ShipModel, Simulator

KNOT = 1852.0 / 3600.0
SAMPLE_TIME = 0.5
CURRENT_SPEED = 3.0 * KNOT  # 6.3.3: 3 kn towards 030
CURRENT_DIRECTION = math.radians(30.0)
SWITCH_OFF = 600.0  # s
FIX_ERROR = 50.0  # m, 6.3.3: "more than ... G.P.S."


@pytest.mark.parametrize("seed", [0, 1])
def test_current_is_estimated_from_50_m_fixes_and_followed_when_switched_off(seed):
    """6.3.3: zig-zag with the full preset and HF waves; 3 kn at 030 switched off after 10 min."""
    model = ShipModel("container_226m").with_effects("wave_filter")
    simulator = Simulator(model, dt=SAMPLE_TIME)
    simulator.reset(seed=seed, conditions=Conditions(current_speed=CURRENT_SPEED, current_direction=CURRENT_DIRECTION))
    instruments = SimulatedInstruments(simulator, InstrumentNoise(position=FIX_ERROR), fix_interval=2.0, seed=seed)
    yaw_filter = YawFilter(model.length, SAMPLE_TIME, NomotoParameters(1.6, 1.7))
    position_filter = PositionFilter(SAMPLE_TIME, noise=PositionFilterNoise(position_fix=FIX_ERROR))
    first = instruments.read()
    yaw_filter.reset(first)
    position_filter.reset(first, yaw_filter.rate_of_turn, yaw_filter.heading)
    rudder = order = math.radians(20.0)
    times, errors = [], []
    while simulator.time[0] < 2.0 * SWITCH_OFF - 1e-9:
        order = zigzag_rudder(order, simulator.heading[0], rudder)
        simulator.step(order)
        if simulator.time[0] >= SWITCH_OFF:
            simulator.set_conditions("current_speed", 0.0)
        reading = instruments.read()
        yaw_filter.step(reading, speed=position_filter.speed)
        position_filter.step(reading, yaw_filter.rate_of_turn, yaw_filter.heading)
        speed = simulator.conditions[0, 2]
        true_current = speed * math.cos(CURRENT_DIRECTION), speed * math.sin(CURRENT_DIRECTION)
        times.append(simulator.time[0])
        errors.append(math.dist(position_filter.current, true_current) / KNOT)
    times, errors = np.asarray(times), np.asarray(errors)
    before = (times >= SWITCH_OFF - 120.0) & (times < SWITCH_OFF)
    after = times >= 2.0 * SWITCH_OFF - 120.0
    assert errors[before].max() < 0.3
    assert errors[after].max() < 0.3
    recovered = times[np.flatnonzero((errors > 0.3) & (times >= SWITCH_OFF))[-1]] - SWITCH_OFF
    print(
        f"seed {seed}: current error (kn) max over 8-10 min {errors[before].max():.3f}, over 18-20 min "
        f"{errors[after].max():.3f}; after the switch-off within 0.3 kn from {recovered:.0f} s; "
        f"gamma {position_filter.sway_constant:.1f} m"
    )


def straight_filter() -> PositionFilter:
    """A filter on 000 at 9.5 m/s, a minute of fixes every 2 s at the true position."""
    position_filter = PositionFilter(1.0, noise=PositionFilterNoise(position_fix=5.0))
    position_filter.reset(Measurement(0.0, 0.0, 0.0, 9.5, 0.0, 0.0, 0.0), 0.0, 0.0)
    for second in range(1, 61):
        fix = second % 2 == 0
        position_filter.step(
            Measurement(
                0.0,
                0.0,
                0.0,
                9.5,
                9.5 * second if fix else math.nan,
                0.0 if fix else math.nan,
                second if fix else math.nan,
            ),
            0.0,
            0.0,
        )
    return position_filter


def test_a_missing_fix_is_skipped_and_a_held_fix_is_used_once():
    held, missing = straight_filter(), straight_filter()
    # An environment holds its last fix (time 60 s) between fixes; NaN means no fix at all.
    held.step(Measurement(0.0, 0.0, 0.0, 9.5, 570.0, 0.0, 60.0), 0.0, 0.0)
    missing.step(Measurement(0.0, 0.0, 0.0, 9.5, math.nan, math.nan), 0.0, 0.0)
    np.testing.assert_array_equal(held.kalman.x, missing.kalman.x)
    assert np.all(np.isfinite(missing.kalman.x)) and missing.position[0] == pytest.approx(9.5 * 61, abs=1.0)


def test_a_wild_fix_is_rejected_and_a_persistent_jump_reports_divergence():
    position_filter = straight_filter()
    second = 60

    def fix(offset: float) -> Measurement:
        return Measurement(0.0, 0.0, 0.0, 9.5, 9.5 * second + offset, 0.0, float(second))

    second += 1
    position_filter.step(fix(5000.0), 0.0, 0.0)
    assert position_filter.gate.outliers == 1
    assert position_filter.position[0] == pytest.approx(9.5 * second, abs=2.0)
    with pytest.raises(FilterDivergenceError, match="position filter"):
        for _ in range(position_filter.gate.patience):
            second += 1
            position_filter.step(fix(5000.0), 0.0, 0.0)
