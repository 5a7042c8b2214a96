"""A fitted preset for tests, written by hand: a preset with standard errors on its K*, tau*, as a fit writes them."""

from __future__ import annotations

from pathlib import Path

import yaml

from ship_env.paths import config_dir


def fitted_preset(folder: Path, errors: dict[str, float], name: str = "fitted") -> Path:
    """The kvlcc2 preset named ``name`` in ``folder`` with ``errors`` (term -> std_error, SI units) on its terms."""
    document = yaml.safe_load((config_dir() / "ships" / "kvlcc2.yaml").read_text())
    document["name"] = name
    for key, error in errors.items():
        effect, _, term = key.partition(".")
        document["effects"][effect][term]["std_error"] = error
    path = folder / f"{name}.yaml"
    path.write_text(yaml.safe_dump(document, sort_keys=False))
    return path
