"""Effects written outside ship_env: registered, simulated, fitted, and refused with a clear error when wrong."""

from __future__ import annotations

import inspect
import math
import sys
import types

import effect_plugin
import numpy as np
import pytest
import yaml

from ship_env.model import (
    EFFECTS,
    REQUIRED_EFFECTS,
    Conditions,
    Contribution,
    Effect,
    Parameter,
    ShipModel,
    Simulator,
    State,
    register_effect,
)
from ship_env.model import state as S
from ship_env.paths import config_dir
from ship_env.workbench import fit
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.fitting.terms import DEFAULT_TERMS
from ship_env.workbench.synthetic.synthetic import LogSettings, model_test_programme, sail_all

#: The speed loss's terms, fitted wherever the logs measure speed (the speed is an output the model predicts).
SPEED_LOSS_TERMS = DEFAULT_TERMS["speed_loss"]

SHIP = "esso_osaka_model"
NAME = effect_plugin.EFFECT.name


@pytest.fixture
def plugin():
    """The test module's effect, registered as a notebook would, removed afterwards."""
    register_effect(effect_plugin.EFFECT, effect_plugin.CONTRIBUTIONS)
    yield effect_plugin
    EFFECTS.unregister(NAME)


def _turn(model: ShipModel, ships: int) -> np.ndarray:
    sim = Simulator(model, num_ships=ships, dt=0.5)
    sim.reset(seed=3, conditions=Conditions(propeller_rate=10.0))
    for _ in range(600):
        sim.step(math.radians(20.0) if ships == 1 else np.full(ships, math.radians(20.0)))
    return sim.state.copy()


def test_a_registered_effect_sails_single_and_batched_bit_for_bit(plugin):
    model = ShipModel(SHIP, [*REQUIRED_EFFECTS, NAME], {f"{NAME}.loss": 0.8})
    single = _turn(model, 1)
    batch = _turn(model, 4)
    assert all(np.array_equal(row, single[0]) for row in batch)
    # The steady turn of the linear ship (2.58): r = K delta_e with K = K* u / L, delta_e its lift loss.
    delta = math.radians(20.0)
    gain = model.parameter("yaw.gain") * model.service_speed / model.length
    expected = gain * delta * (1.0 - 0.8 * delta) / model.parameter("yaw.linear")
    assert single[0, S.RATE_OF_TURN] == pytest.approx(expected, rel=1e-6)
    without = _turn(ShipModel(SHIP, REQUIRED_EFFECTS), 1)
    assert without[0, S.RATE_OF_TURN] == pytest.approx(expected / (1.0 - 0.8 * delta), rel=1e-6)


def test_a_ship_that_leaves_the_model_names_the_effects_from_outside(plugin):
    sim = Simulator(ShipModel(SHIP, [*REQUIRED_EFFECTS, NAME], {f"{NAME}.loss": 0.8}))
    sim.reset(seed=1)
    sim.state[0, S.RATE_OF_TURN] = math.nan  # as a contribution's NaN would leave it
    with pytest.raises(
        FloatingPointError,
        match=r"rate_of_turn = .*nan.*outside ship_env in the model: rudder_lift_loss \(module test_model_user_",
    ):
        sim.step(0.0)


def test_its_parameters_come_from_the_ship_yaml_or_its_defaults(plugin, tmp_path):
    assert ShipModel(SHIP, [*REQUIRED_EFFECTS, NAME]).parameter(f"{NAME}.loss") == 0.0  # the declared default
    document = yaml.safe_load((config_dir() / "ships" / f"{SHIP}.yaml").read_text())
    document["effects"][NAME] = {"enabled": True, "loss": {"value": 0.4, "unit": "1/rad", "source": "basin test"}}
    path = tmp_path / "with_loss.yaml"
    path.write_text(yaml.safe_dump(document))
    model = ShipModel(path)
    assert model.has(NAME) and model.parameter(f"{NAME}.loss") == 0.4
    assert model.ship.sources[f"{NAME}.loss"] == "basin test"
    with pytest.raises(ValueError, match=r"rudder_lift_loss.loss.*outside"):
        ShipModel(SHIP, [*REQUIRED_EFFECTS, NAME], {f"{NAME}.loss": 3.0})


@pytest.mark.slow
def test_a_hidden_instance_is_recovered_by_the_fit(plugin):
    truth = ReplayModel(ShipModel(SHIP, [*REQUIRED_EFFECTS, NAME], {f"{NAME}.loss": 0.6}))
    logs = sail_all(truth, model_test_programme(duration=60.0)[:4], seed=5, settings=LogSettings())
    result = fit(ShipModel(SHIP, [*REQUIRED_EFFECTS, NAME]), logs)
    estimates = {estimate.term.key: estimate.value for estimate in result.estimates}
    assert set(estimates) == {"yaw.gain", "yaw.time_constant", f"{NAME}.loss", *SPEED_LOSS_TERMS}
    assert estimates[f"{NAME}.loss"] == pytest.approx(0.6, abs=0.06)
    assert estimates["yaw.gain"] == pytest.approx(truth.model.parameter("yaw.gain"), rel=0.05)


# -- errors ---------------------------------------------------------------------------------------
def _effect(name: str = "bad_effect", **parameter) -> Effect:
    fields = {"minimum": 0.0, "maximum": 1.0, "default": 0.0, "source": "assumed", **parameter}
    return Effect(name, "a test effect", "none", Parameter("size", fields.pop("unit", "-"), "a size", **fields))


def _adds(effective_rudder, size):
    return effective_rudder + size


def test_an_unregistered_effect_is_refused_by_name():
    with pytest.raises(ValueError, match=r"unknown effect 'shallow_water'; known: yaw"):
        ShipModel(SHIP, [*REQUIRED_EFFECTS, "shallow_water"])


def test_a_clash_with_a_built_in_name_is_refused():
    with pytest.raises(
        ValueError, match=r"effect 'norrbin' from module test_model_user_effects: name: 'norrbin' is already"
    ):
        register_effect(_effect("norrbin"), [Contribution("effective_rudder", _adds)])


def test_parameters_given_as_a_tuple_are_refused_by_the_declaration():
    size = Parameter("size", "-", "a size", 0.0, 1.0)
    with pytest.raises(TypeError, match=r"effect 'bad_effect': parameters: expected Parameter\(\.\.\.\) arguments one"):
        Effect("bad_effect", "a test effect", "none", (size,))  # type: ignore[arg-type]
    assert Effect("bad_effect", "a test effect", "none", size).parameters == (size,)


@pytest.mark.parametrize(
    ("parameter", "message"),
    [
        ({"unit": ""}, r"effect 'bad_effect' from module test_model_user_effects: parameter 'size': unit"),
        ({"minimum": -math.inf}, r"effect 'bad_effect' .*: parameter 'size': range: give a finite minimum and maximum"),
        ({"maximum": math.inf}, r"parameter 'size': range"),
        ({"source": ""}, r"parameter 'size': source: a default needs its source"),
    ],
)
def test_a_parameter_without_unit_range_or_source_is_refused(parameter, message):
    with pytest.raises(ValueError, match=message):
        register_effect(_effect(**parameter), [Contribution("effective_rudder", _adds)])
    assert "bad_effect" not in EFFECTS


def test_a_contribution_to_an_unknown_quantity_or_reading_nothing_is_refused():
    with pytest.raises(ValueError, match=r"effect 'bad_effect' .* contribution quantity 'yaw_moment' is unknown"):
        register_effect(_effect(), [Contribution("yaw_moment", _adds)])

    def reads_depth(water_depth, size):
        return size / water_depth

    with pytest.raises(ValueError, match=r"argument 'water_depth' names nothing the model has"):
        register_effect(_effect(), [Contribution("yaw_acceleration", reads_depth)])


def _module_with_adds(name: str) -> types.ModuleType:
    """A module made from source as ``importlib`` makes one from a file, holding ``_adds``."""
    module = types.ModuleType(name)
    exec(inspect.getsource(_adds), module.__dict__)
    return module


def test_a_function_from_a_module_not_in_sys_modules_is_refused_naming_the_fix():
    """A cached step imports its functions' module by name when it loads; one Python cannot find is refused."""
    module = _module_with_adds("effect_outside_sys_modules")
    with pytest.raises(
        ValueError,
        match=r"contribution to 'effective_rudder': function '_adds' is from module 'effect_outside_sys_modules', "
        r"which is not in sys.modules: .*sys.modules\['effect_outside_sys_modules'\] = module",
    ):
        register_effect(_effect(), [Contribution("effective_rudder", module._adds)])
    assert "bad_effect" not in EFFECTS


def test_the_same_code_from_another_module_is_other_equations(monkeypatch):
    """Its compiled step is cached apart: one cached from a script must not be loaded for the imported file."""
    fingerprints = []
    for name in ("effect_as_a_script", "effect_as_a_module"):
        module = _module_with_adds(name)
        monkeypatch.setitem(sys.modules, name, module)
        register_effect(_effect(), [Contribution("effective_rudder", module._adds)])
        try:
            fingerprints.append(EFFECTS.fingerprint(["bad_effect"]))
        finally:
            EFFECTS.unregister("bad_effect")
    assert fingerprints[0] != fingerprints[1]


def _nan_rudder(effective_rudder, size):
    return effective_rudder + math.log(size - 1.0)


def _nan_depth_rate(depth, size):
    return math.log(depth - size)


@pytest.mark.parametrize(
    ("contribution", "states"),
    [
        (Contribution("effective_rudder", _nan_rudder), ()),
        (Contribution("depth_derivative", _nan_depth_rate), (State("depth", "m", "a depth of its own"),)),
    ],
)
def test_a_contribution_returning_nan_is_named_before_any_simulation(contribution, states):
    """A contribution to a quantity, or to the rate of a state of the effect's own."""
    register_effect(_effect(default=0.5), [contribution], states)
    try:
        with pytest.raises(
            ValueError,
            match=rf"effect 'bad_effect' from module test_model_user_effects: its contribution to "
            rf"'{contribution.quantity}' is nan",
        ):
            ShipModel(SHIP, [*REQUIRED_EFFECTS, "bad_effect"])
    finally:
        EFFECTS.unregister("bad_effect")


def test_an_entry_point_registers_an_installed_effect(tmp_path, monkeypatch):
    """A package that declares ``[project.entry-points."ship_env.effects"]`` (a dist-info on sys.path)
    registers the package's own effect, with the equations that
    ``test_a_registered_effect_sails_single_and_batched_bit_for_bit`` sails."""
    distribution = tmp_path / "ship_effects_example-1.0.dist-info"
    distribution.mkdir()
    (distribution / "METADATA").write_text("Metadata-Version: 2.1\nName: ship-effects-example\nVersion: 1.0\n")
    (distribution / "entry_points.txt").write_text(f"[ship_env.effects]\n{NAME} = effect_plugin\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    EFFECTS.load_entry_points()
    try:
        entry = EFFECTS.entry(NAME)
        assert entry.origin == f"entry point '{NAME}' (effect_plugin)"
        assert entry.effect is effect_plugin.EFFECT
        model = ShipModel(SHIP, [*REQUIRED_EFFECTS, NAME], {f"{NAME}.loss": 0.8})
        assert model.effects[-1] == NAME and model.parameter(f"{NAME}.loss") == 0.8
        installed = EFFECTS.fingerprint([NAME])
    finally:
        EFFECTS.unregister(NAME)
    register_effect(effect_plugin.EFFECT, effect_plugin.CONTRIBUTIONS)
    try:
        assert EFFECTS.fingerprint([NAME]) == installed  # the same equations: the same compiled model
    finally:
        EFFECTS.unregister(NAME)
    (distribution / "entry_points.txt").write_text("[ship_env.effects]\nbroken = no_such_module_for_ship_env\n")
    with pytest.raises(
        ImportError, match=r"effect 'broken' from entry point 'broken' \(no_such_module_for_ship_env\): cannot import"
    ):
        EFFECTS.load_entry_points()


def test_the_environments_sail_a_registered_effect(plugin):
    """The Gymnasium environments take it like a built-in (``effects``, ``ship_parameters``)."""
    import gymnasium as gym

    def headings(loss: float, vector: bool) -> np.ndarray:
        options = {"effects": [*REQUIRED_EFFECTS, NAME], "ship_parameters": {f"{NAME}.loss": loss}}
        if vector:
            envs = gym.make_vec(
                "ship_env/CourseChange-v0", num_envs=3, vectorization_mode="vector_entry_point", **options
            )
            envs.reset(seed=4)
            for _ in range(60):
                observation, *_ = envs.step(np.ones((3, 1), dtype=np.float32))
            return np.asarray(observation)
        env = gym.make("ship_env/CourseChange-v0", **options)
        env.reset(seed=4)
        for _ in range(60):
            observation, *_ = env.step(np.ones(1, dtype=np.float32))
        return np.asarray(observation)[np.newaxis]

    without, with_loss = headings(0.0, False), headings(0.8, False)
    assert not np.array_equal(without, with_loss)  # the lost rudder force changes the course change
    assert np.array_equal(headings(0.8, True)[0], with_loss[0])  # ship 0 of a batch seeded 4 is the single env
