"""Effects with states of their own, written outside ship_env: laid out, started, integrated, fitted, refused."""

from __future__ import annotations

import json

import effect_with_state
import gymnasium as gym
import numpy as np
import pytest
from test_model_registry import NEWER_EFFECTS, REFERENCE, _trajectory, assert_matches_reference

from ship_env.cli import main
from ship_env.model import EFFECTS, REQUIRED_EFFECTS, Conditions, ShipModel, Simulator
from ship_env.model import state as S
from ship_env.model.effect_api import Contribution, Effect, Parameter, State, register_effect
from ship_env.model.registry import register_module
from ship_env.workbench import write_log
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.fitting.terms import DEFAULT_TERMS
from ship_env.workbench.synthetic.synthetic import NO_NOISE, LogSettings, model_test_programme, sail_all

#: The speed loss's terms, fitted wherever the logs measure speed (the speed is an output the model predicts).
SPEED_LOSS_TERMS = DEFAULT_TERMS["speed_loss"]

SHIP = "esso_osaka_model"
NAME = effect_with_state.EFFECT.name
LAG = "lagged_rudder"


@pytest.fixture
def plugin():
    """The test module's effect, registered as an installed module would be, removed afterwards."""
    register_module(effect_with_state, "module effect_with_state")
    yield effect_with_state
    EFFECTS.unregister(NAME)


def _lag_model(time_constant: float = 4.0) -> ShipModel:
    return ShipModel(SHIP, [*REQUIRED_EFFECTS, NAME], {f"{NAME}.time_constant": time_constant})


def test_its_state_follows_the_library_s_and_starts_where_it_declares(plugin):
    model = _lag_model()
    assert model.state_names == (*S.LIBRARY_STATES, LAG)
    sim = Simulator(model, num_ships=3)
    sim.reset(seed=1, rudder=[0.1, -0.2, 0.0])
    np.testing.assert_array_equal(sim.state[:, -1], [0.1, -0.2, 0.0])  # settled: at the actual rudder


def test_it_is_integrated_as_declared_single_and_batched_bit_for_bit(plugin):
    """With no steering machine the rudder jumps to the order: the lag then decays by RK4's exact factor."""
    model = _lag_model(4.0)
    dt, order, start = 0.5, 0.3, 0.1
    single = Simulator(model, dt=dt)
    single.reset(seed=3, rudder=start)
    batch = Simulator(model, num_ships=4, dt=dt)
    batch.reset(seed=3, rudder=start)
    lags = []
    for _ in range(16):
        single.step(order)
        batch.step(np.full(4, order))
        lags.append(single.state[0, -1])
        assert all(np.array_equal(row, single.state[0]) for row in batch.state)
    z = dt / 4.0
    factor = 1.0 - z + z**2 / 2.0 - z**3 / 6.0 + z**4 / 24.0  # RK4 on d l/dt = (delta - l) / T
    expected = order + (start - order) * factor ** np.arange(1, 17)
    np.testing.assert_allclose(lags, expected, rtol=1e-13)
    # The lagged force turns the ship more slowly at first, and as fast once settled.
    without = Simulator(ShipModel(SHIP, REQUIRED_EFFECTS), dt=dt)
    without.reset(seed=3, rudder=start)
    for _ in range(16):
        without.step(order)
    assert single.rate_of_turn[0] < without.rate_of_turn[0]
    for _ in range(600):
        single.step(order)
        without.step(order)
    gain = model.parameter("yaw.gain") * model.service_speed / model.length
    steady = gain * order / model.parameter("yaw.linear")  # r = K delta (2.58), delta_l settled at delta
    assert single.rate_of_turn[0] == pytest.approx(steady, rel=1e-6)
    assert without.rate_of_turn[0] == pytest.approx(steady, rel=1e-6)


def test_registering_it_changes_no_number_of_the_built_ins(plugin):
    """The full library (noise, sea, gusts) with the plugin registered but off: the reference (bit for bit on the
    recording CPU, within its rounding elsewhere: ``test_model_registry.assert_matches_reference``)."""
    ship = "container_226m"
    model = ShipModel.full(ship).without_effects(*NEWER_EFFECTS, NAME)
    assert model.state_size == len(S.LIBRARY_STATES) + 1
    for method, ships in (("rk4", 1), ("euler", 6)):
        trajectory = _trajectory(model, method, ships)
        key = f"{ship}/full/{method}/{ships}"
        assert_matches_reference(trajectory[..., : len(S.LIBRARY_STATES)], np.load(REFERENCE)[key], key)
        assert np.all(trajectory[..., -1] == 0.0)  # off, it stays at its initial value (rudder 0 at reset)


@pytest.mark.slow
def test_a_hidden_instance_is_recovered_by_fit_add(plugin, tmp_path, capsys):
    """Noise-free logs of the lagged ship: ``fit --add`` with the plugin finds every term (from T_l = 2 s)."""
    # The logs measure speed, so the fit predicts it with the speed loss: the truth loses speed in its turns.
    # Runs that start at their service speed: one that accelerates from rest has it estimated (``replay``).
    truth = ReplayModel(_lag_model(6.0).with_effects("speed_loss"))
    exact = LogSettings(noise=NO_NOISE)
    runs = [run for run in model_test_programme(duration=60.0) if run.start_speed == run.final_speed][:4]
    for log in sail_all(truth, runs, seed=5, settings=exact):
        write_log(log, tmp_path / f"{log.name}.csv")
    fit_file = tmp_path / "fit.json"
    assert main(["fit", str(tmp_path), "--ship", SHIP, "--add", NAME, "--json", str(fit_file)]) == 0
    values = json.loads(fit_file.read_text())["values"]
    assert set(values) == {"yaw.gain", "yaw.time_constant", f"{NAME}.time_constant", *SPEED_LOSS_TERMS}
    for key, value in values.items():
        assert value == pytest.approx(truth.model.parameter(key), rel=1e-6), key


def test_the_environments_sail_it(plugin):
    options = {"effects": [*REQUIRED_EFFECTS, NAME], "ship_parameters": {f"{NAME}.time_constant": 5.0}}
    env = gym.make("ship_env/CourseChange-v0", **options)
    env.reset(seed=4)
    envs = gym.make_vec("ship_env/CourseChange-v0", num_envs=2, vectorization_mode="vector_entry_point", **options)
    envs.reset(seed=4)
    for _ in range(30):
        observation, *_ = env.step(np.ones(1, dtype=np.float32))
        observations, *_ = envs.step(np.ones((2, 1), dtype=np.float32))
    assert np.array_equal(observations[0], observation)


# -- errors ---------------------------------------------------------------------------------------
def _effect() -> Effect:
    return Effect(
        "bad_state",
        "a test effect",
        "none",
        Parameter("size", "-", "a size", 0.0, 2.0, default=1.0, source="assumed"),
    )


def _rate(depth, size):
    return size - depth


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("gust", r"state 'gust': name: 'gust' is already a state of effect 'gusts' from ship_env"),
        ("heading", r"state 'heading': name: 'heading' is a state of the ship's motion"),
        ("wind_speed", r"state 'wind_speed': name: 'wind_speed' is already an input, quantity, condition"),
    ],
)
def test_a_state_name_that_is_taken_is_refused(name, message):
    with pytest.raises(ValueError, match=rf"effect 'bad_state' from module test_model_effect_states: {message}"):
        register_effect(_effect(), [Contribution(f"{name}_derivative", _rate)], [State(name, "m", "a depth")])
    assert "bad_state" not in EFFECTS


def test_a_state_without_a_derivative_is_refused():
    with pytest.raises(
        ValueError,
        match=r"effect 'bad_state' from module test_model_effect_states: state 'depth': it has no derivative; "
        r"add Contribution\('depth_derivative', function\)",
    ):
        register_effect(_effect(), [], [State("depth", "m", "a depth")])
    with pytest.raises(ValueError, match=r"state 'depth': unit: every state needs its SI unit"):
        register_effect(_effect(), [Contribution("depth_derivative", _rate)], [State("depth", "", "a depth")])


def test_a_noise_driven_state_of_its_own_leaves_the_built_ins_noise_as_it_was():
    """Its white noise is a third channel, drawn from counters of its own: the wave filter's and the gusts' stay."""

    def intensity(size):
        return size

    def drift_rate(drift, drift_white_noise, size):
        return -drift / 20.0 + size * drift_white_noise

    register_effect(
        _effect(), [Contribution("drift_derivative", drift_rate)], [State("drift", "m", "a drift", 0.0, intensity)]
    )
    try:
        disturbed = ShipModel(SHIP, [*REQUIRED_EFFECTS, "wave_filter", "gusts"])
        histories = []
        for model in (disturbed, disturbed.with_effects("bad_state")):
            sim = Simulator(model)
            sim.reset(seed=2, conditions=Conditions(wind_speed=8.0))
            history = []
            for _ in range(200):
                sim.step(0.1)
                history.append(sim.state[0].copy())
            histories.append(np.array(history))
    finally:
        EFFECTS.unregister("bad_state")
    without, with_drift = histories
    np.testing.assert_array_equal(with_drift[:, :-1], without[:, :-1])  # the drift feeds nothing back
    assert np.std(without[:, S.GUST]) > 0.0 and np.std(without[:, S.WAVE_RATE]) > 0.0
    assert np.all(without[:, -1] == 0.0) and np.std(with_drift[:, -1]) > 0.0
    assert abs(np.corrcoef(np.diff(with_drift[:, -1]), np.diff(with_drift[:, S.GUST]))[0, 1]) < 0.3
