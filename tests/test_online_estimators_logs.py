"""The estimators' input: bad logs give errors naming the field and the value; the workbench's logs convert."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ship_env.baselines.online_estimators.criteria import (
    parameter_criterion,
    relative_errors,
    settling_times,
)
from ship_env.baselines.online_estimators.excitation import (
    Intermittent,
    ModelChange,
    PseudoRandomBinary,
    SpeedChange,
    Turning,
    WhiteNoise,
    ZigZag,
    sail,
)
from ship_env.baselines.online_estimators.history import NOMOTO, ParameterHistory
from ship_env.baselines.online_estimators.least_squares import NguyenRLS
from ship_env.baselines.online_estimators.log import (
    ExcitationLog,
    ExcitationLogError,
    from_workbench_log,
)
from ship_env.baselines.online_estimators.scenarios import GUESS
from ship_env.model import ShipModel
from ship_env.workbench.logs.logs import Log


def good_arrays(samples: int = 200) -> dict[str, np.ndarray]:
    time = np.arange(samples) * 0.5
    rate = 0.01 * np.sin(time / 20.0)
    heading = np.concatenate([[0.0], np.cumsum(0.5 * 0.5 * (rate[1:] + rate[:-1]))])
    return {
        "time": time,
        "rudder": math.radians(10.0) * np.sign(np.sin(time / 30.0)),
        "heading": heading,
        "rate_of_turn": rate,
        "speed": np.full(samples, 9.5),
    }


def test_a_good_log_is_accepted_and_read_only():
    log = ExcitationLog(**good_arrays())
    assert log.samples == 200 and log.sample_time() == 0.5
    with pytest.raises(ValueError):
        log.rudder[0] = 1.0


@pytest.mark.parametrize(
    ("field", "index", "value", "expected"),
    [
        ("rudder", 17, math.nan, r"rudder\[17\] = nan is not a finite number"),
        ("speed", 3, math.inf, r"speed\[3\] = inf is not a finite number"),
        ("time", 50, 24.0, r"time must increase, but time\[50\] = 24 s follows time\[49\] = 24.5 s"),
        ("rudder", 5, 35.0, r"rudder\[5\] = 35 rad is beyond 1.57 rad; degrees"),
        ("rate_of_turn", 9, 2.0, r"rate_of_turn\[9\] = 2 rad/s is beyond 1 rad/s; degrees"),
        ("speed", 0, -1.0, r"speed\[0\] = -1 m/s is negative"),
    ],
)
def test_bad_samples_are_named_with_their_value(field, index, value, expected):
    arrays = good_arrays()
    arrays[field] = arrays[field].copy()
    arrays[field][index] = value
    with pytest.raises(ExcitationLogError, match=expected):
        ExcitationLog(**arrays)


def test_heading_in_degrees_and_rate_in_degrees_per_second_are_caught():
    arrays = good_arrays()
    with pytest.raises(
        ExcitationLogError, match="heading changes 57.3 times faster than rate_of_turn.*heading in degrees"
    ):
        ExcitationLog(**{**arrays, "heading": np.degrees(arrays["heading"])})
    with pytest.raises(ExcitationLogError, match="rate_of_turn in deg/s"):
        ExcitationLog(**{**arrays, "rate_of_turn": np.degrees(arrays["rate_of_turn"])})


def test_shapes_missing_speed_and_uneven_sampling_are_named():
    arrays = good_arrays()
    with pytest.raises(ExcitationLogError, match=r"heading has shape \(199,\); expected 200 samples"):
        ExcitationLog(**{**arrays, "heading": arrays["heading"][:-1]})
    log = ExcitationLog(**{**arrays, "speed": None})
    with pytest.raises(ExcitationLogError, match="speed is absent, and Nguyen RLS .* needs it"):
        NguyenRLS(100.0, GUESS).run(log)
    uneven = arrays["time"].copy()
    uneven[100:] += 0.2
    with pytest.raises(ExcitationLogError, match=r"not uniformly sampled \(step 0.7 s at time\[100\]"):
        ExcitationLog(**{**arrays, "time": uneven}).sample_time()


def test_workbench_log_converts_and_an_ordered_rudder_is_refused():
    arrays = good_arrays()
    workbench = Log(
        name="run 1", time=arrays["time"], heading=arrays["heading"], rudder=arrays["rudder"], service_speed=4.0
    )
    log = from_workbench_log(workbench)
    assert log.name == "run 1" and np.all(log.speed == 4.0)
    np.testing.assert_allclose(log.rate_of_turn[5:-5], arrays["rate_of_turn"][5:-5], atol=2e-4)
    ordered = Log(
        name="run 2", time=arrays["time"], heading=arrays["heading"], rudder=arrays["rudder"], rudder_kind="ordered"
    )
    with pytest.raises(ExcitationLogError, match="rudder is the ordered rudder"):
        from_workbench_log(ordered)


def test_programmes_and_changes_on_the_simulator():
    """The programmes steer as described; a speed ramp and a model change reach the log and the truth."""
    model = ShipModel.minimal("container_226m")
    zigzag = sail(model, ZigZag(math.radians(20.0), math.radians(20.0)), 300.0)
    assert np.max(np.abs(zigzag.log.rudder)) == pytest.approx(math.radians(20.0))
    assert math.radians(20.0) < np.max(zigzag.log.heading) < math.radians(45.0)
    prbs = PseudoRandomBinary(math.radians(10.0), 10.0).controller()
    orders = {prbs(t, 0.0) for t in np.arange(0.0, 600.0, 10.0)}
    assert orders == {math.radians(10.0), -math.radians(10.0)}
    noise = WhiteNoise(math.radians(10.0), 5.0, math.radians(15.0)).controller()
    assert len({noise(t, 0.0) for t in np.arange(0.0, 100.0, 0.5)}) == 20
    quiet = Intermittent(Turning(0.1), 10.0, 20.0).controller()
    assert [quiet(t, 0.0) for t in (5.0, 15.0, 35.0)] == [0.1, 0.0, 0.1]
    loaded = model.with_parameters({"yaw.gain": 1.2, "yaw.time_constant": 2.4})
    changed = sail(
        model,
        ZigZag(math.radians(20.0), math.radians(20.0)),
        600.0,
        changes=[SpeedChange(100.0, 5.0, 50.0), ModelChange(300.0, loaded)],
    )
    assert changed.log.speed[-1] == pytest.approx(5.0, abs=0.2)
    assert tuple(changed.truth.values[0]) == (1.6, 1.7) and tuple(changed.truth.values[-1]) == (1.2, 2.4)
    assert changed.change_times == (100.0, 300.0)


def test_criteria_on_a_known_history():
    """J_p (6.1) integrates the squared relative errors; an invalid estimate counts as 100 %."""
    time = np.arange(11.0)
    truth = ParameterHistory.constant(NOMOTO, time, (2.0, 1.0))
    values = np.tile([2.2, 1.0], (11, 1))
    values[:5] = [1.0, 0.5]
    valid = np.ones(11, dtype=bool)
    valid[0] = False
    estimate = ParameterHistory(NOMOTO, time, values, valid)
    assert relative_errors(estimate, truth)[0].tolist() == [1.0, 1.0]
    assert settling_times(estimate, truth, 0.15) == {"K*": 5.0, "tau*": 5.0}
    assert settling_times(estimate, truth, 0.05) == {"K*": None, "tau*": 5.0}
    assert parameter_criterion(estimate, truth) == pytest.approx(2.0 + 4 * 0.5 + 5 * 0.01)
    assert parameter_criterion(estimate, truth, start=5.0) == pytest.approx(5 * 0.01)
