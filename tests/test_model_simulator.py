"""Simulator behaviour: symmetry, reproducibility, batch = single runs, and errors on bad input."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import CONTAINER, run
from short_run import short_run

from ship_env.model import EFFECTS, Conditions, ShipModel, Simulator, list_ships, load_ship
from ship_env.model import state as S


def _disturbed() -> Conditions:
    return Conditions(
        wind_speed=9.0,
        wind_direction=math.radians(300.0),
        current_speed=1.0,
        current_direction=math.radians(45.0),
        wave_height=2.5,
        wave_period=8.0,
        wave_direction=math.radians(140.0),
    )


def test_mirrored_rudder_gives_the_mirrored_track():
    model = ShipModel(CONTAINER).without_effects("gusts")  # symmetric ship, calm water

    def zigzag(sign):
        return lambda t: sign * math.radians(20.0) * (1.0 if (t // 120.0) % 2 == 0 else -1.0)

    starboard = run(model, zigzag(1.0), duration=900.0)
    port = run(model, zigzag(-1.0), duration=900.0)
    np.testing.assert_allclose(starboard[:, S.NORTH], port[:, S.NORTH], rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(starboard[:, S.EAST], -port[:, S.EAST], rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(starboard[:, S.HEADING], -port[:, S.HEADING], atol=1e-13)
    assert np.max(np.abs(starboard[:, S.EAST])) > 100.0  # it did turn


def test_seeded_runs_repeat_exactly_and_seeds_differ():
    model = ShipModel.full(CONTAINER)
    first = run(model, math.radians(5.0), duration=300.0, conditions=_disturbed(), seed=11)
    again = run(model, math.radians(5.0), duration=300.0, conditions=_disturbed(), seed=11)
    other = run(model, math.radians(5.0), duration=300.0, conditions=_disturbed(), seed=12)
    np.testing.assert_array_equal(first, again)
    assert np.max(np.abs(first[:, S.HEADING] - other[:, S.HEADING])) > 1e-4
    assert np.max(np.abs(first[:, S.WAVE_RATE] - other[:, S.WAVE_RATE])) > 1e-4


def test_batch_equals_single_runs():
    model = ShipModel.full(CONTAINER)
    count, steps = 5, 400
    seeds = [3, 8, 1, 42, 7]
    conditions = [
        Conditions(
            wind_speed=2.0 * i, wind_direction=0.7 * i, current_speed=0.3 * i, wave_height=0.5 * i, wave_direction=i
        )
        for i in range(count)
    ]
    orders = np.radians(np.linspace(-30.0, 30.0, count))
    batch = Simulator(model, num_ships=count, dt=0.5)
    batch.reset(seed=seeds, conditions=conditions, heading=np.linspace(0, 3, count))
    singles = [Simulator(model, dt=0.5) for _ in range(count)]
    for i, single in enumerate(singles):
        single.reset(seed=seeds[i], conditions=conditions[i], heading=np.linspace(0, 3, count)[i])
    for k in range(steps):
        wave = np.sin(0.01 * k) * orders
        batch.step(wave)
        for i, single in enumerate(singles):
            single.step(float(wave[i]))
    for i, single in enumerate(singles):
        np.testing.assert_array_equal(batch.state[i], single.state[0])


def test_integer_seed_gives_ship_i_the_seed_plus_i():
    model = ShipModel(CONTAINER, ["yaw", "kinematics", "wave_filter"])
    batch = Simulator(model, num_ships=3)
    batch.reset(seed=100)
    single = Simulator(model)
    single.reset(seed=102)
    for _ in range(50):
        batch.step(0.0)
        single.step(0.0)
    np.testing.assert_array_equal(batch.state[2], single.state[0])


def test_turning_an_effect_off_only_changes_that_effect():
    model = ShipModel(CONTAINER)
    without = model.without_effects("norrbin")
    assert "norrbin" not in without.effects and "speed_loss" in without.effects
    assert without.record[0]["norrbin_on"] == False  # noqa: E712 (numpy bool)
    assert without.parameter("yaw.gain") == model.parameter("yaw.gain")
    assert set(model.with_effects("wave_filter").effects) == set(model.effects) | {"wave_filter"}


def test_every_preset_loads_and_states_its_sources():
    assert {"container_226m", "esso_osaka_model"} <= set(list_ships())
    for name in list_ships():
        ship = load_ship(name)
        full = ShipModel.full(name)  # every effect has values
        assert full.length > 0
        parameters = [f"principal.{k}" for k in ship.principal] + [
            f"{effect}.{key}" for effect, values in ship.values.items() for key in values
        ]
        assert set(parameters) <= set(ship.sources)
        assert set(ship.values) == set(EFFECTS) - {"kinematics"}


# -- bad input ---------------------------------------------------------------------------------


@pytest.mark.parametrize("order", [math.nan, math.inf, -math.inf])
def test_non_finite_rudder_orders_are_rejected(order):
    sim = Simulator(ShipModel(CONTAINER))
    with pytest.raises(ValueError, match="ordered_rudder"):
        sim.step(order)
    batch = Simulator(ShipModel(CONTAINER), num_ships=3)
    with pytest.raises(ValueError, match=r"ordered_rudder\[1\].*nan|ordered_rudder\[1\].*inf"):
        batch.step(np.array([0.0, order, 0.0]))


def test_wrong_shape_of_orders_is_rejected():
    batch = Simulator(ShipModel(CONTAINER), num_ships=3)
    with pytest.raises(ValueError, match=r"ordered_rudder: expected shape \(3,\)"):
        batch.step(np.zeros(4))


def test_negative_speed_is_rejected():
    with pytest.raises(ValueError, match=r"conditions.service_speed.*-2.0"):
        Conditions(service_speed=-2.0)
    sim = Simulator(ShipModel(CONTAINER))
    with pytest.raises(ValueError, match=r"conditions.wind_speed.*-1"):
        sim.set_conditions("wind_speed", -1.0)
    with pytest.raises(TypeError, match=r"conditions.current_speed.*'fast'"):
        Conditions(current_speed="fast")


def test_a_ship_started_slow_accelerates_as_the_speed_loss_equation_says():
    """On a straight course (2.55) reads tau_u* (L / u) du*/dt = -u*, with u = U0 (1 - u*): the logistic
    u*(t) = 1 / (1 + (1 - u0*) / u0* exp(U0 t / (tau_u* L))); started at half its service speed."""
    model = ShipModel(CONTAINER, ("yaw", "speed_loss", "steering_machine", "kinematics"))
    simulator = Simulator(model, dt=0.5)
    simulator.reset(seed=0, speed=0.5 * model.service_speed)
    assert simulator.speed[0] == pytest.approx(0.5 * model.service_speed, rel=1e-15)
    rate = model.service_speed / (model.parameter("speed_loss.time_constant") * model.length)
    for _ in range(400):
        simulator.step(0.0)
    expected = 1.0 / (1.0 + np.exp(rate * simulator.time[0]))  # u0* = 1/2
    assert 1.0 - simulator.speed[0] / model.service_speed == pytest.approx(expected, rel=1e-8)
    with pytest.raises(ValueError, match=r"speed: expected positive speeds"):
        simulator.reset(speed=0.0)


def test_changed_wind_and_current_carry_their_velocities():
    """A condition set while sailing re-derives the wind's and current's velocity components (2.71, 2.74)."""
    sim = Simulator(ShipModel(CONTAINER), num_ships=2)
    sim.reset(seed=0, conditions=Conditions(current_speed=1.5, current_direction=math.radians(30.0)))
    sim.set_conditions("wind_speed", np.array([10.0, 4.0]))
    sim.set_conditions("wind_direction", math.radians(90.0))  # from the east: the air moves west
    np.testing.assert_allclose(sim.conditions[:, S.WIND_NORTH], 0.0, atol=1e-12)
    np.testing.assert_allclose(sim.conditions[:, S.WIND_EAST], [-10.0, -4.0])
    np.testing.assert_allclose(sim.conditions[:, S.CURRENT_NORTH], 1.5 * math.cos(math.radians(30.0)))
    np.testing.assert_allclose(sim.conditions[:, S.CURRENT_EAST], 0.75)
    sim.set_conditions("current_speed", 0.0)
    assert not np.any(sim.conditions[:, [S.CURRENT_NORTH, S.CURRENT_EAST]])
    with pytest.raises(ValueError, match=r"'wind_north' is derived .*known: service_speed"):
        sim.set_conditions("wind_north", 1.0)


def test_unknown_effect_and_parameter_names_are_rejected():
    with pytest.raises(ValueError, match=r"unknown effect 'wind_momnet'"):
        ShipModel(CONTAINER, ["yaw", "wind_momnet"])
    with pytest.raises(ValueError, match=r"unknown parameter 'yaw.gian'"):
        ShipModel(CONTAINER, parameters={"yaw.gian": 1.0})
    with pytest.raises(ValueError, match=r"'yaw' is required"):
        ShipModel(CONTAINER).without_effects("yaw")
    with pytest.raises(ValueError, match=r"ship: unknown preset 'titanic'"):
        ShipModel("titanic")


def test_parameter_out_of_range_is_rejected():
    with pytest.raises(ValueError, match=r"yaw.time_constant.*-1.0"):
        ShipModel(CONTAINER, parameters={"yaw.time_constant": -1.0})


def _write_variant(tmp_path: Path, edit) -> Path:
    document = yaml.safe_load(load_ship(CONTAINER).path.read_text())
    edit(document)
    path = tmp_path / "variant.yaml"
    path.write_text(yaml.safe_dump(document))
    return path


def test_config_field_of_the_wrong_type_names_the_field_and_value(tmp_path):
    path = _write_variant(tmp_path, lambda d: d["effects"]["yaw"]["gain"].update(value="1.6"))
    with pytest.raises(TypeError, match=r"yaw.gain: expected a number in -, got '1.6'"):
        load_ship(path)
    path = _write_variant(tmp_path, lambda d: d["effects"]["sway"].update(enabled="yes"))
    with pytest.raises(TypeError, match=r"sway.enabled: expected true or false, got 'yes'"):
        load_ship(path)


def test_config_units_convert_and_mismatched_units_are_rejected(tmp_path):
    ship = load_ship(CONTAINER)
    assert ship.principal["rudder_limit"] == pytest.approx(math.radians(35.0))
    path = _write_variant(tmp_path, lambda d: d["principal"]["length"].update(unit="deg"))
    with pytest.raises(ValueError, match=r"principal.length: unit 'deg' cannot be converted to 'm'"):
        load_ship(path)


def test_a_number_in_the_ship_s_own_length_and_speed_converts_by_them(tmp_path):
    """U0, U0/L, L and L/U0: fractions of the ship's own service speed and length, read after them."""
    ship = load_ship(CONTAINER)
    length, speed = ship.principal["length"], ship.principal["service_speed"]

    def relative(document):
        document["envelope"]["minimum_speed"].update(value=0.2, unit="U0")
        document["envelope"]["maximum_rate"].update(value=1.5, unit="U0/L")
        document["effects"]["propeller_slipstream"]["propeller_diameter"].update(value=0.03, unit="L")
        document["effects"]["gusts"]["time_constant"].update(value=0.5, unit="L/U0")
        document["principal"]["minimum_speed"].update(value=0.05, unit="U0")

    read = load_ship(_write_variant(tmp_path, relative))
    assert read.envelope.minimum_speed == pytest.approx(0.2 * speed, rel=1e-15)
    assert read.envelope.maximum_rate == pytest.approx(1.5 * speed / length, rel=1e-15)
    assert read.values["propeller_slipstream"]["propeller_diameter"] == pytest.approx(0.03 * length, rel=1e-15)
    assert read.values["gusts"]["time_constant"] == pytest.approx(0.5 * length / speed, rel=1e-15)
    assert read.principal["minimum_speed"] == pytest.approx(0.05 * speed, rel=1e-15)
    wrong = _write_variant(tmp_path, lambda d: d["envelope"]["minimum_speed"].update(value=1.0, unit="L"))
    with pytest.raises(ValueError, match=r"envelope.minimum_speed: unit 'L' cannot be converted to 'm/s'"):
        load_ship(wrong)
    above = _write_variant(tmp_path, lambda d: d["envelope"]["minimum_speed"].update(value=9.6, unit="m/s"))
    with pytest.raises(ValueError, match=r"envelope.minimum_speed: 9.6 m/s is not below the service speed 9.5 m/s"):
        load_ship(above)
    circular = _write_variant(tmp_path, lambda d: d["principal"]["service_speed"].update(value=1.0, unit="U0"))
    with pytest.raises(ValueError, match=r"principal.service_speed: unit 'U0' cannot be converted .*read first"):
        load_ship(circular)


def test_a_preset_scaled_by_hand_keeps_its_assumed_limits_in_proportion(tmp_path):
    """A user who writes a built-in preset at model scale by editing its particulars (length, breadth, draught,
    service speed, rudder rate) gets the envelope, the speed floor and the propeller that ``ship-env scale`` gives:
    the presets write these in the ship's own length and speed. Before, the 7 m KVLCC2 kept the full-scale
    tanker's 2 m/s minimum speed, above its 1.18 m/s service speed, and every run lay outside the envelope."""
    for name in ("kvlcc2", CONTAINER):
        full = ShipModel(name)
        lam = 7.0 / full.length
        scaled = full.scaled(length=7.0)

        def by_hand(document, lam=lam):
            principal = document["principal"]
            for key in ("length", "breadth", "draught"):
                principal[key]["value"] *= lam
            principal["service_speed"]["value"] *= math.sqrt(lam)
            document["effects"]["steering_machine"]["rudder_rate"]["value"] /= math.sqrt(lam)

        document = yaml.safe_load(load_ship(name).path.read_text())
        by_hand(document)
        path = tmp_path / f"{name}_by_hand.yaml"
        path.write_text(yaml.safe_dump(document))
        hand = load_ship(path)
        for limit in ("minimum_speed", "maximum_rate"):
            assert getattr(hand.envelope, limit) == pytest.approx(getattr(scaled.ship.envelope, limit), rel=1e-12)
        assert hand.envelope.minimum_speed < 0.3 * hand.principal["service_speed"]
        assert hand.principal["minimum_speed"] == pytest.approx(scaled.parameter("minimum_speed"), rel=1e-12)
        diameter = hand.values["propeller_slipstream"]["propeller_diameter"]
        assert diameter == pytest.approx(scaled.parameter("propeller_slipstream.propeller_diameter"), rel=1e-12)


def test_config_number_without_a_source_is_rejected(tmp_path):
    path = _write_variant(tmp_path, lambda d: d["effects"]["yaw"]["gain"].pop("source"))
    with pytest.raises(ValueError, match=r"yaw.gain: every number needs a 'source'"):
        load_ship(path)


def test_a_ship_file_edited_in_place_is_read_afresh(tmp_path):
    """A ship file is parsed once per text: an edit of the same length, in the same instant, is read."""
    path = _write_variant(tmp_path, lambda d: d["effects"]["yaw"]["gain"].update(value=1.5))
    first = load_ship(path)
    first.values["yaw"]["gain"] = 9.0  # what one caller does to its ship reaches no other
    path.write_text(path.read_text().replace("value: 1.5", "value: 1.7"))
    assert load_ship(path).values["yaw"]["gain"] == 1.7
    path.write_text(path.read_text().replace("value: 1.7", "value: 1.5"))
    assert load_ship(path).values["yaw"]["gain"] == 1.5


def test_unknown_effect_in_a_config_is_rejected(tmp_path):
    path = _write_variant(tmp_path, lambda d: d["effects"].update(bow_thruster={"enabled": True}))
    with pytest.raises(ValueError, match=r"unknown effect 'bow_thruster'"):
        load_ship(path)


def test_a_model_driven_past_its_validity_raises_instead_of_returning_nonsense():
    """A huge speed-loss gain drives u* past 1 (going astern): an error names the ship and the cause."""
    model = ShipModel(CONTAINER, ["yaw", "kinematics", "speed_loss"], {"speed_loss.gain": 50.0})
    sim = Simulator(model, num_ships=2, dt=1.0)
    sim.reset(seed=0)
    with pytest.raises(
        FloatingPointError,
        match=r"ship 1 left the model's validity .* speed_loss u\* = .* > 1 .*\(e\.g\. speed_loss\.gain for a turn",
    ):
        for _ in range(2000):
            sim.step(np.radians([0.0, 35.0]))


def test_resetting_some_ships_leaves_the_others_sailing():
    model = ShipModel(CONTAINER).with_effects("wave_filter")
    batch = Simulator(model, num_ships=3)
    batch.reset(seed=10)
    for _ in range(20):
        batch.step(np.radians([5.0, 10.0, 15.0]))
    before = batch.state.copy()
    batch.reset(seed=[77], heading=1.0, ships=[1])
    np.testing.assert_array_equal(batch.state[[0, 2]], before[[0, 2]])
    fresh = Simulator(model)
    fresh.reset(seed=77, heading=1.0)
    np.testing.assert_array_equal(batch.state[1], fresh.state[0])
    for _ in range(20):
        batch.step(np.radians([5.0, 10.0, 15.0]))
        fresh.step(math.radians(10.0))
    np.testing.assert_array_equal(batch.state[1], fresh.state[0])
    with pytest.raises(ValueError, match=r"ships: expected indices in \[0, 3\)"):
        batch.reset(ships=[3])


def test_large_batches_step_on_all_cores_with_the_same_numbers():
    from ship_env.model.simulator import PARALLEL_SHIPS

    model = ShipModel.full(CONTAINER)
    conditions = Conditions(wind_speed=8.0, wave_height=2.0)
    big = Simulator(model, num_ships=PARALLEL_SHIPS)
    big.reset(seed=0, conditions=conditions)
    small = Simulator(model, num_ships=2)
    small.reset(seed=[0, PARALLEL_SHIPS - 1], conditions=conditions)
    orders = np.radians(np.linspace(-20.0, 20.0, PARALLEL_SHIPS))
    for _ in range(30):
        big.step(orders)
        small.step(orders[[0, -1]])
    np.testing.assert_array_equal(big.state[[0, -1]], small.state)


def test_the_model_runs_as_pure_python_with_the_compiled_numbers():
    """``NUMBA_DISABLE_JIT=1`` runs the same code uncompiled (for a debugger). Both do the same IEEE
    operations without fast-math; only a math library may round a last bit differently, which ten
    steps do not grow to 1e-9."""
    environment = {**os.environ, "NUMBA_DISABLE_JIT": "1"}
    script = Path(__file__).with_name("short_run.py")
    result = subprocess.run([sys.executable, str(script)], env=environment, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    pure_python = json.loads(result.stdout)
    for name, compiled in short_run().items():
        np.testing.assert_allclose(pure_python[name], compiled, rtol=1e-9, atol=1e-12, err_msg=name)


#: Steps ships and environments on all cores and in one thread, and replays a run, then prints the
#: types each loop's kernel was compiled for with its first argument, the index.
_LOOPS = """
import gymnasium as gym
import numpy as np
from ship_env.envs import course_change_task
from ship_env.model import ShipModel, Simulator, integrators
from ship_env.model.simulator import PARALLEL_SHIPS
from ship_env.workbench import ReplayModel, simulate
from ship_env.workbench.fitting.replay import _replay_task
from ship_env.workbench.synthetic.synthetic import model_test_programme, sail_all

sim = Simulator(ShipModel("container_226m"), num_ships=PARALLEL_SHIPS)
sim.reset(seed=0)
envs = gym.make_vec("ship_env/CourseChange-v0", num_envs=PARALLEL_SHIPS, vectorization_mode="vector_entry_point")
envs.reset(seed=0)
for _ in range(3):  # on all cores first, then in one thread (simulator.Cores)
    sim.step(np.zeros(PARALLEL_SHIPS))
    envs.step(np.zeros((PARALLEL_SHIPS, 1), dtype=np.float32))
truth = ReplayModel(ShipModel("container_226m"))
simulate(truth, sail_all(truth, model_test_programme(duration=30.0)[:1], seed=1))
for kernel in (integrators._step_range, integrators._step_rows, course_change_task.update_ship, _replay_task):
    print(kernel.__name__, sorted({str(signature[0]) for signature in kernel.signatures}))
"""


@pytest.mark.slow  # an empty cache: every kernel compiled (about 40 s)
def test_a_kernel_a_loop_calls_is_compiled_for_a_signed_index_only(tmp_path):
    """The serial and the parallel loops over ships (and the replay's over tasks) call one compiled
    kernel: the parallel loop's unsigned index and a start of 0 are passed as int64."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), "NUMBA_NUM_THREADS": "2"}
    result = subprocess.run([sys.executable, "-c", _LOOPS], env=env, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr
    printed = result.stdout.splitlines()
    assert printed == [f"{name} ['int64']" for name in ("_step_range", "_step_rows", "update_ship", "_replay_task")]
