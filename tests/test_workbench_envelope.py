"""The validity envelope: ship presets and effects state the conditions the model is valid for."""

from __future__ import annotations

import math

import pytest
import yaml

from ship_env.model import ShipModel, load_ship
from ship_env.model.declarations import Envelope
from ship_env.paths import config_dir


def test_presets_state_their_envelope_with_sources():
    ship = load_ship("esso_osaka_model")
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
