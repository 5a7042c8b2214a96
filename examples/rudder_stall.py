"""A physical effect the library lacks, written outside ship_env: the rudder stalls at large angles.

The logs of a ship whose rudder stalls (its force stops growing with the angle beyond a dozen
degrees) are fitted with the speed-scheduled Nomoto ship. ``diagnose`` tries every effect of the
library; none explains the residual, and the missing yaw acceleration is found to follow the rudder
angle cubed: "look for a rudder force not proportional to the angle: stall". The effect is then
written in a dozen lines, registered, added with ``fit --add`` (the command line, in this process),
and the held-out error falls to the sensors' noise.

Run:  python examples/rudder_stall.py [--out DIR]
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
from pathlib import Path

from ship_env.model import REQUIRED_EFFECTS, ShipModel
from ship_env.model.effect_api import Contribution, Effect, Parameter, register_effect

# -- the effect, as a naval engineer writes it ------------------------------------------------------
RUDDER_STALL = Effect(
    "rudder_stall",
    "rudder stall (the rudder force stops growing with the angle beyond the stall angle)",
    "delta_e = delta_s tanh(delta / delta_s)",
    Parameter(
        "angle",
        "rad",
        "delta_s, the angle the rudder force levels off at",
        math.radians(5.0),
        math.radians(60.0),
        default=math.radians(60.0),
        source="assumed: a rudder that does not stall in the logs' range",
    ),
)


def stalled_rudder(effective_rudder, angle):
    """The angle that makes the rudder force, rad: the actual one, levelling off at +-angle."""
    return angle * math.tanh(effective_rudder / angle)


register_effect(RUDDER_STALL, [Contribution("effective_rudder", stalled_rudder)])
# ---------------------------------------------------------------------------------------------------

from ship_env.cli import main as ship_env_main  # noqa: E402  (after the effect: the CLI lists it)
from ship_env.model.effects import LIBRARY  # noqa: E402
from ship_env.workbench import FitOptions, cross_validate, diagnose, improve  # noqa: E402
from ship_env.workbench.deciding.diagnose import past_the_library  # noqa: E402
from ship_env.workbench.deciding.signals import plot_signals  # noqa: E402
from ship_env.workbench.fitting.replay import ReplayModel  # noqa: E402
from ship_env.workbench.logs.logs import write_log  # noqa: E402
from ship_env.workbench.reporting.tables import ladder_table  # noqa: E402
from ship_env.workbench.synthetic.synthetic import (  # noqa: E402
    SensorNoise,
    model_test_programme,
    noise_floor,
    noise_scales,
    sail_all,
)

SHIP = "esso_osaka_model"
STALL_ANGLE = math.radians(15.0)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], allow_abbrev=False)
    parser.add_argument("--out", type=Path, default=None, help="folder for the logs and the plot (default: temporary)")
    args = parser.parse_args(argv)
    out = args.out or Path(tempfile.mkdtemp(prefix="rudder_stall_"))
    out.mkdir(parents=True, exist_ok=True)

    truth = ReplayModel(ShipModel(SHIP, [*REQUIRED_EFFECTS, "rudder_stall"], {"rudder_stall.angle": STALL_ANGLE}))
    logs = sail_all(truth, model_test_programme(), seed=11)
    for log in logs:
        write_log(log, out / f"{log.name}.csv")
    scales = noise_scales(SensorNoise())
    options = FitOptions(scales=scales)
    print(f"logs of a ship whose rudder stalls at {math.degrees(STALL_ANGLE):.0f} deg written to {out}/")
    print(f"noise floor (the true model on these logs): held-out score {noise_floor(truth, logs, scales):.2f}\n")

    base = cross_validate(ShipModel(SHIP, REQUIRED_EFFECTS), logs, options=options)
    library = [module.EFFECT.name for module in LIBRARY]
    diagnosis = diagnose(base, logs, options, effects=library, refit=3)
    print(f"base model (yaw, kinematics): held-out score {base.score(scales):.2f}")
    print("the library's candidates with most evidence, added and refitted:")
    for candidate in diagnosis.ranked[:3]:
        if candidate.cross_validation is not None:
            print(f"  + {candidate.effect}: held-out score {candidate.held_out.score(scales):.3g}")
    print(f"\n{past_the_library(diagnosis) or 'an effect of the library explains the residual'}")
    plot = plot_signals(diagnosis.signals, out / "missing_yaw_acceleration.png")
    print(f"plot: {plot}\n")

    ladder = improve(ShipModel(SHIP, REQUIRED_EFFECTS), logs, options, max_steps=2, refit=3, pair_width=0)
    print("error ladder with every registered effect a candidate (improve):")
    print(ladder_table(ladder).text())
    print("\nthe same with the command line: ship-env fit LOGS --model base --add rudder_stall")
    return ship_env_main(["fit", str(out), "--ship", SHIP, "--model", "base", "--add", "rudder_stall"])


if __name__ == "__main__":
    sys.exit(main())
