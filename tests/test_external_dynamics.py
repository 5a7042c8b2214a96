"""Ships simulated outside ship_env (ship_env.model.external): the protocol, its reference adapter
(ship_env's own simulator behind it: the same episodes as the native environments), adapters that
fail mid-episode, and shipmmg's MMG KVLCC2 (skipped where shipmmg is absent)."""

from __future__ import annotations

import dataclasses
import math

import gymnasium as gym
import numpy as np
import pytest

import ship_env  # noqa: F401  (registers the environments)
from ship_env.baselines.presys import pd_controller
from ship_env.leaderboard.entrants import CLASSIC_BUILDERS
from ship_env.leaderboard.sailing import sail
from ship_env.leaderboard.suites import COURSE_CHANGE, Episode
from ship_env.model import Conditions, ShipModel
from ship_env.model.external import ExternalDynamicsError, ShipMotion
from ship_env.model.native_dynamics import NativeDynamics

#: float32 observations of the same motion agree to their rounding; the speed passes through
#: u = U0 (1 - u*) and back, a few float64 roundings of a number near 1.
OBSERVATION_TOLERANCE = 1e-6
REWARD_TOLERANCE = 1e-12


def sail_actions(env: gym.Env, seed: int, steps: int, options: dict | None = None) -> list:
    """Reset with ``seed``, then a rudder sweeping both ways; every (observation, reward, info)."""
    observation, info = env.reset(seed=seed, options=options)
    record = [(observation, 0.0, info)]
    for k in range(steps):
        observation, reward, _, _, info = env.step(np.array([math.sin(k / 25.0)], dtype=np.float32))
        record.append((observation, reward, info))
    return record


def assert_same_episode(native: list, external: list) -> None:
    for (obs, reward, info), (obs_x, reward_x, info_x) in zip(native, external, strict=True):
        np.testing.assert_allclose(obs_x, obs, rtol=0.0, atol=OBSERVATION_TOLERANCE)
        assert reward_x == pytest.approx(reward, rel=REWARD_TOLERANCE, abs=REWARD_TOLERANCE)
        for name, value in info["metrics"].items():
            assert info_x["metrics"][name] == pytest.approx(value, rel=1e-12), name


@pytest.mark.parametrize(
    ("env_id", "env_kwargs", "steps"),
    [
        (COURSE_CHANGE, {"disturbance": "calm"}, 200),
        (COURSE_CHANGE, {"disturbance": "wind_current"}, 200),
        ("ship_env/TrackFollow-v0", {"start": "before_turn"}, 200),  # placed on a leg between reset and step
    ],
)
def test_reference_adapter_sails_the_native_episode(env_id, env_kwargs, steps):
    native = gym.make(env_id, **env_kwargs)
    model = native.unwrapped.task.model
    external = gym.make(env_id, **env_kwargs, dynamics=NativeDynamics(model))
    assert_same_episode(sail_actions(native, 7, steps), sail_actions(external, 7, steps))


def test_classic_autopilot_completes_a_course_change_through_the_protocol():
    native = gym.make(COURSE_CHANGE)
    external = gym.make(COURSE_CHANGE, dynamics="ship_env.model.native_dynamics:NativeDynamics")
    episode = Episode(3, {"course_change_deg": 45.0}, "+45 deg")
    metrics, _ = sail(external, pd_controller(external.unwrapped.task, schedule="fixed"), episode)
    expected, _ = sail(native, pd_controller(native.unwrapped.task, schedule="fixed"), episode)
    assert math.isfinite(metrics["settling_time"])
    for name, value in expected.items():
        assert metrics[name] == pytest.approx(value, rel=1e-9), name


def test_vector_env_of_adapters_equals_the_native_vector_env():
    make = {"num_envs": 3, "vectorization_mode": "vector_entry_point", "disturbance": "wind_current"}
    native = gym.make_vec(COURSE_CHANGE, **make)
    external = gym.make_vec(COURSE_CHANGE, **make, dynamics=NativeDynamics)
    observations, _ = native.reset(seed=5)
    observations_x, _ = external.reset(seed=5)
    for k in range(60):
        actions = np.full((3, 1), math.sin(k / 10.0), dtype=np.float32)
        np.testing.assert_allclose(observations_x, observations, atol=OBSERVATION_TOLERANCE)
        observations, rewards, *_ = native.step(actions)
        observations_x, rewards_x, *_ = external.step(actions)
        np.testing.assert_allclose(rewards_x, rewards, rtol=REWARD_TOLERANCE)


# -- adapters that fail -----------------------------------------------------------------------------
class FailingShip(NativeDynamics):
    """The reference ship that fails once, at its ``fail_at``-th step, in the way ``how`` says."""

    def __init__(self, how: str, fail_at: int = 5) -> None:
        super().__init__()
        self.how, self.fail_at, self.steps = how, fail_at, 0

    def step(self, rudder_order, propeller_rate, dt):
        motion = super().step(rudder_order, propeller_rate, dt)
        self.steps += 1
        if self.steps != self.fail_at:
            return motion
        if self.how == "nan":
            return [math.nan, *motion.values()[1:]]
        if self.how == "shape":
            return motion.values()[:5]
        raise ConnectionError("co-simulation peer closed the socket")


@pytest.mark.parametrize(
    ("how", "says"),
    [
        ("nan", "non-finite heading = nan"),
        ("shape", "shape (5,), expected a ShipMotion or 7 numbers"),
        ("raise", "step raised ConnectionError: co-simulation peer closed the socket"),
    ],
)
def test_a_failing_adapter_ends_the_episode_with_a_clear_error_and_the_env_sails_on(how, says):
    env = gym.make(COURSE_CHANGE, dynamics=FailingShip(how))
    env.reset(seed=1)
    for _ in range(4):
        env.step(np.array([0.5], dtype=np.float32))
    with pytest.raises(ExternalDynamicsError, match=r"FailingShip, ship 0, step 5 \(t = 4\.0 s\)") as raised:
        env.step(np.array([0.5], dtype=np.float32))
    assert says in str(raised.value) and "the episode ended" in str(raised.value)
    with pytest.raises(ExternalDynamicsError, match="episode ended"):  # ended: no step before a reset
        env.step(np.array([0.5], dtype=np.float32))
    # Nothing else lost: the next episode is the reference ship's, step for step.
    again = sail_actions(env, 2, 30)
    assert_same_episode(sail_actions(gym.make(COURSE_CHANGE), 2, 30), again)


def test_a_failing_adapter_truncates_its_ship_alone_in_a_vector_env():
    ships = iter([NativeDynamics(), FailingShip("nan", fail_at=3), NativeDynamics()])
    make = {"num_envs": 3, "vectorization_mode": "vector_entry_point"}
    failing = gym.make_vec(COURSE_CHANGE, **make, dynamics=lambda: next(ships))
    reference = gym.make_vec(COURSE_CHANGE, **make, dynamics=NativeDynamics)
    failing.reset(seed=4)
    reference.reset(seed=4)
    actions = np.full((3, 1), 0.3, dtype=np.float32)
    for _ in range(3):
        observations, _, _, truncated, info = failing.step(actions)
        expected, *_ = reference.step(actions)
    assert truncated.tolist() == [False, True, False]
    assert info["diverged"].tolist() == [False, True, False]
    np.testing.assert_array_equal(observations[[0, 2]], expected[[0, 2]])
    observations, rewards, *_ = failing.step(actions)  # the failed ship restarts, the others sail on
    assert np.isfinite(observations).all() and rewards[1] == 0.0


def test_dynamics_keyword_errors_name_the_problem():
    with pytest.raises(ValueError, match="sails one ship; give its class"):
        gym.make_vec(COURSE_CHANGE, num_envs=2, vectorization_mode="vector_entry_point", dynamics=NativeDynamics())
    with pytest.raises(ValueError, match="cannot import 'ship_env.model:NoSuchShip'"):
        gym.make(COURSE_CHANGE, dynamics="ship_env.model:NoSuchShip")
    with pytest.raises(ValueError, match="expected 'module:attribute'"):
        gym.make(COURSE_CHANGE, dynamics="NativeDynamics")
    with pytest.raises(TypeError, match="no reset\\(\\) and step\\(\\)"):
        gym.make(COURSE_CHANGE, dynamics=lambda: object())
    env = gym.make(COURSE_CHANGE, dynamics=NativeDynamics, ship_variation={"yaw_gain": (2.0, 2.0)})
    with pytest.raises(ValueError, match="K\\* and tau\\* factors scale ship_env's own model"):
        env.reset(seed=0)


# -- shipmmg's MMG KVLCC2 -------------------------------------------------------------------------------
def mmg_kvlcc2():
    pytest.importorskip(
        "shipmmg", reason='shipmmg is not installed (pip install shipmmg, or pip install -e ".[bench]")'
    )
    from ship_env.model import mmg_kvlcc2

    return mmg_kvlcc2


def test_mmg_kvlcc2_holds_its_speed_and_the_current_carries_it():
    mmg = mmg_kvlcc2()
    ship = mmg.MmgKvlcc2()
    current = Conditions(service_speed=mmg.SERVICE_SPEED, current_speed=1.0, current_direction=math.radians(90.0))
    ship.reset(ShipMotion(0.0, 0.0, 0.0, 0.0, mmg.SERVICE_SPEED), current, 0)
    for _ in range(60):
        motion = ship.step(0.0, None, 1.0)
    # The equilibrium propeller rate holds U0 on a straight course; the current sets the ship east.
    assert motion.speed == pytest.approx(mmg.SERVICE_SPEED, rel=1e-6)
    assert motion.north == pytest.approx(60.0 * mmg.SERVICE_SPEED, rel=1e-6)
    assert motion.east == pytest.approx(60.0, rel=1e-6)
    assert motion.heading == 0.0 and motion.rate_of_turn == 0.0


def test_mmg_kvlcc2_at_model_scale_sails_the_full_scale_turn_froude_scaled():
    """The MMG equations have no Reynolds-dependent term: the 7 m model sails the 320 m ship's hard-over turn with
    lengths / lambda and times / sqrt(lambda), its steering machine's rate included (SIMMAN's 2.32 deg/s at full
    scale is 15.7 deg/s on the model)."""
    mmg = mmg_kvlcc2()
    full, model = mmg.MmgKvlcc2(), mmg.MmgKvlcc2(scale=1.0)
    time_scale = math.sqrt(mmg.SCALE)
    assert math.degrees(model.rudder_rate) == pytest.approx(15.69, abs=0.01)
    motions = []
    for ship, dt in ((full, 1.0), (model, 1.0 / time_scale)):
        speed = ship.service_speed
        ship.reset(ShipMotion(0.0, 0.0, 0.0, 0.0, speed), Conditions(service_speed=speed), 0)
        motions.append([ship.step(math.radians(35.0), None, dt) for _ in range(120)])
    for at_full, at_model in zip(*motions, strict=True):
        assert at_model.heading == pytest.approx(at_full.heading, rel=1e-4, abs=1e-6)
        assert at_model.rudder == pytest.approx(at_full.rudder, rel=1e-9)
        assert at_model.rate_of_turn == pytest.approx(at_full.rate_of_turn * time_scale, rel=1e-4, abs=1e-8)
        assert at_model.north * mmg.SCALE == pytest.approx(at_full.north, rel=1e-4, abs=1e-3)
        assert at_model.east * mmg.SCALE == pytest.approx(at_full.east, rel=1e-4, abs=1e-3)
        assert at_model.speed * time_scale == pytest.approx(at_full.speed, rel=1e-4)


def test_mmg_kvlcc2_refuses_waves():
    mmg = mmg_kvlcc2()
    with pytest.raises(ValueError, match="no wave forces"):
        mmg.MmgKvlcc2().reset(ShipMotion(0.0, 0.0, 0.0, 0.0, 8.0), Conditions(service_speed=8.0, wave_height=2.0), 0)


@pytest.mark.slow
@pytest.mark.parametrize("disturbance", ["calm", "wind_current"])
def test_classic_autopilots_complete_the_course_changes_on_the_mmg_ship(disturbance):
    mmg_kvlcc2()
    env = gym.make(
        COURSE_CHANGE, ship="kvlcc2", dynamics="ship_env.model.mmg_kvlcc2:MmgKvlcc2", disturbance=disturbance
    )
    for name, build in CLASSIC_BUILDERS[COURSE_CHANGE].items():
        for change in (15.0, -45.0, 105.0):
            metrics, _ = sail(env, build(env.unwrapped.task), Episode(0, {"course_change_deg": change}, ""))
            assert math.isfinite(metrics["settling_time"]), f"{name} did not settle after {change:+g} deg"


def test_unseen_suite_sails_the_quick_episodes_on_the_mmg_ship_with_tracks_scaled_to_it():
    mmg_kvlcc2()
    from ship_env.leaderboard.suites import SUITE_SPECS, TRACK_FOLLOW

    quick = {suite.task: suite.episodes for suite in SUITE_SPECS["quick"].suites()}
    unseen = SUITE_SPECS["unseen"].suites()
    assert [suite.name for suite in unseen] == [
        "CourseChange calm | MMG KVLCC2 (unseen physics)",
        "CourseChange wind_current | MMG KVLCC2 (unseen physics)",
        "TrackFollow | MMG KVLCC2 (unseen physics)",
    ]
    for suite in unseen:
        assert suite.episodes == quick[suite.task]
        env = gym.make(suite.env_id, **suite.env_kwargs)
        assert type(env.unwrapped.batch.simulator.adapters[0]).__name__ == "MmgKvlcc2"
        assert env.unwrapped.task.model.length == 320.0  # the kvlcc2 preset: what the bridge knows
    native = gym.make(TRACK_FOLLOW).unwrapped.task
    scale = env.unwrapped.task.model.length / native.model.length  # 320 m / 225.87 m (ship_env.envs.ship_scales)
    np.testing.assert_allclose(env.unwrapped.task.tracks["T3"].leg_lengths, native.tracks["T3"].leg_lengths * scale)
    with pytest.raises(ValueError, match="no wave forces"):
        SUITE_SPECS["unseen"].__class__(course_change_disturbances=("wind_current_waves",)).suites()


def test_synthetic_logs_sailed_through_the_reference_adapter_equal_the_native_ones():
    """A zig-zag and a turn, accelerating from below their service speed, sailed by the true model and by the
    same model behind the protocol: the same log sample for sample (the speed through u = U0 (1 - u*) and
    back), and an external truth in wind refused with the field named."""
    from ship_env.workbench.fitting.replay import ReplayModel
    from ship_env.workbench.synthetic.synthetic import SEA_TRIAL_NOISE, LogSettings, Manoeuvre, sail_all

    model = ShipModel("kvlcc2", ("yaw", "norrbin", "speed_loss", "sway", "steering_machine", "kinematics"))
    speed = model.service_speed
    runs = [
        Manoeuvre("zigzag_20", "zigzag", math.radians(20.0), 600.0, approach=40.0, start_speed=0.8 * speed,
                  final_speed=speed, propeller_rate=1.2, wind_speed=0.0),
        Manoeuvre("turn_m35", "turn", math.radians(-35.0), 500.0, approach=40.0, start_speed=speed,
                  final_speed=speed, propeller_rate=1.2, wind_speed=0.0),
    ]  # fmt: skip
    settings = LogSettings(dt=1.0, noise=SEA_TRIAL_NOISE)
    native = sail_all(ReplayModel(model), runs, seed=3, settings=settings)
    external = sail_all(ReplayModel(model), runs, seed=3, settings=settings, dynamics=lambda: NativeDynamics(model))
    for log, log_x in zip(native, external, strict=True):
        assert np.ptp(log.heading) > math.radians(30.0)  # it turned
        for channel in ("heading", "rate_of_turn", "north", "east", "rudder", "speed"):
            np.testing.assert_allclose(getattr(log_x, channel), getattr(log, channel), rtol=0.0, atol=1e-9)
    windy = dataclasses.replace(runs[0], wind_speed=5.0)
    with pytest.raises(ValueError, match=r"wind_speed 5\.0 m/s"):
        sail_all(ReplayModel(model), [windy], dynamics=lambda: NativeDynamics(model))
