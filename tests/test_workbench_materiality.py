"""Materiality: each effect's declared smallest physical size, scaled to the ship, judges a fitted effect."""

from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from ship_env.model import EFFECTS, REQUIRED_EFFECTS, ShipModel
from ship_env.model.declarations import Parameter
from ship_env.workbench.fitting.fit import Estimate
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.fitting.terms import _RULES, DEFAULT_TERMS, make_term
from ship_env.workbench.judging.materiality import mismatch

SHIPS = ("esso_osaka_model", "container_226m", "kvlcc2")


def setup(ship: str, *effects: str) -> ReplayModel:
    return ReplayModel(ShipModel(ship, [*REQUIRED_EFFECTS, *effects]))


def estimates(ship: str, effect: str, values: dict[str, float]) -> SimpleNamespace:
    """A fit's estimates (all the fit that ``mismatch`` reads) of ``effect``'s terms at ``values``."""
    model = setup(ship, effect)
    return SimpleNamespace(
        estimates=tuple(Estimate(make_term(key, model), value, 0.0, False) for key, value in values.items())
    )


def test_every_fitted_term_with_a_null_declares_a_material_size():
    fitted_with_null = [key for keys in DEFAULT_TERMS.values() for key in keys if _RULES[key].null is not None]
    for key in fitted_with_null:
        effect = key.partition(".")[0]
        assert make_term(key, setup("esso_osaka_model", effect)).material is not None, key


@pytest.mark.parametrize("ship", SHIPS)
def test_the_material_size_scales_with_the_ship(ship):
    model = ShipModel(ship)
    length, speed = model.length, model.service_speed
    assert make_term("current.north", setup(ship, "current")).material == pytest.approx(0.015 * speed)
    assert make_term("wind_moment.yaw_coefficient", setup(ship, "wind_moment")).material == pytest.approx(
        5e-4 / length**2
    )
    assert make_term("rudder_offset.angle", setup(ship, "rudder_offset")).material == pytest.approx(math.radians(0.3))


def test_an_offset_of_hundredths_of_a_degree_absorbs_a_mismatch():
    fit = estimates("esso_osaka_model", "rudder_offset", {"rudder_offset.angle": math.radians(0.02)})
    assert mismatch(["rudder_offset"], fit) == (
        "rudder_offset absorbs a mismatch of size 0.02 deg (material from 0.3 deg): not a physical effect"
    )
    assert (
        mismatch(["rudder_offset"], estimates("esso_osaka_model", "rudder_offset", {"rudder_offset.angle": -0.01}))
        is None
    )


def test_an_effect_is_material_when_one_of_its_terms_is():
    small = {"norrbin.cubic": 0.05, "norrbin.odd_quadratic": 0.01}
    assert mismatch(["norrbin"], estimates("kvlcc2", "norrbin", small)) == (
        "norrbin absorbs a mismatch of size cubic 0.05, odd_quadratic 0.01 (material from 0.1, 0.05): "
        "not a physical effect"
    )
    assert mismatch(["norrbin"], estimates("kvlcc2", "norrbin", {**small, "norrbin.cubic": 0.2})) is None


def test_a_current_is_judged_against_the_ships_service_speed():
    """0.1 m/s is 29 % of the 3 m model's service speed, 1 % of the container ship's."""
    current = {"current.north": 0.1, "current.east": -0.05}
    assert mismatch(["current"], estimates("esso_osaka_model", "current", current)) is None
    assert mismatch(["current"], estimates("container_226m", "current", current)) == (
        "current absorbs a mismatch of size north 0.1 m/s, east -0.05 m/s (material from 0.14 m/s, 0.14 m/s): "
        "not a physical effect"
    )


def test_an_effect_that_declares_no_material_size_is_never_judged_immaterial():
    fit = estimates("esso_osaka_model", "steering_machine", {"steering_machine.rudder_rate": math.radians(20.0)})
    assert fit.estimates[0].term.material is None
    assert mismatch(["steering_machine"], fit) is None


def test_a_material_size_needs_a_positive_number_and_a_known_reference():
    with pytest.raises(ValueError, match=r"parameter 'size': material must be a positive number, got -1"):
        Parameter("size", "-", "a size", material=-1.0)
    with pytest.raises(ValueError, match=r"parameter 'size': material_per 'beam' is not one of '', 'service_speed'"):
        Parameter("size", "-", "a size", material=1.0, material_per="beam")


def test_the_built_in_declarations_justify_their_material_sizes():
    """Each built-in effect with a material size says why in its module's docstring."""
    import importlib

    for name in EFFECTS:
        effect = EFFECTS[name]
        if any(parameter.material is not None for parameter in effect.parameters):
            module = importlib.import_module(f"ship_env.model.effects.{name}")
            assert "``material``" in (module.__doc__ or ""), name
