"""The baselines ready to sail an environment: PRESYS's configurations (thesis ch. 5, 6) as controllers.

Each builder takes the environment's task (``env.unwrapped.task``: its ship model, step and
rudder limit) and returns a controller for the leaderboard's loop::

    env = gym.make("ship_env/CourseChange-v0")
    controller = mrac_controller(env.unwrapped.task)

Prior knowledge: the course-change builders start from the ship preset's K*, tau* (for the
container ship the thesis's identified values, 6.4.4.1); the track follower identifies the ship
first with a zig-zag on its model, as the thesis did before its experiment
(:mod:`ship_env.baselines.online_estimators.zigzag_trial`). The actions are continuous (``action_type="continuous"``).
"""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING

from ship_env.baselines.adaptive_autopilot import IndirectAdaptiveAutopilot
from ship_env.baselines.controller import AutopilotController
from ship_env.baselines.course_changer import CourseChangerSettings, PredictiveCourseChanger, TrackFollowController
from ship_env.baselines.mrac import ModelReferenceAutopilot
from ship_env.baselines.nomoto import NomotoParameters
from ship_env.baselines.online_estimators.zigzag_trial import identify_by_zigzag
from ship_env.baselines.pd_autopilot import PDAutopilot, PDDesign, Schedule
from ship_env.baselines.position_filter import PositionFilter, PositionFilterNoise
from ship_env.baselines.yaw_filter import ship_yaw_filter
from ship_env.envs.ship_scales import ship_scales
from ship_env.model import ShipModel

if TYPE_CHECKING:
    from ship_env.envs.task import ShipTask
    from ship_env.envs.track_follow_task import TrackFollowTask

#: The PD tuning of the baselines: closed-loop natural frequency on the reference ship (rad/s; at
#: the service speed for the distance schedule) and damping. About omega_n* = omega_n L/u = 1.4 per
#: ship length at the service speed: the turn ends briskly, without overshoot. Every ship is designed
#: for that omega_n*: omega_n is this over its time scale (:mod:`ship_env.envs.ship_scales`), so a
#: 3 m model's loop is as brisk in ship lengths as the container ship's.
NATURAL_FREQUENCY = 0.06
DAMPING = 1.0
#: K_R of the MRAC autopilot on course changes: the reference model follows the filter over about
#: T_s / K_R = 500 s at the 1-s step.
REFERENCE_GAIN = 0.002
#: Heading error beyond which the MRAC adapts a_s, b_s (6.3.2: only during course changes).
ADAPTATION_BAND = math.radians(5.0)
#: The track follower's autopilot limits its rudder this much inside the environment's limit, so
#: the compensation (5.90) has rudder left at full helm: in the thesis's experiment the 10 deg was
#: the autopilot's setting, the ship's hard-over angle larger.
COMPENSATION_HEADROOM = math.radians(1.0)


def preset_parameters(model: ShipModel) -> NomotoParameters:
    """K*, tau* of the model's preset (``yaw.gain``, ``yaw.time_constant``)."""
    return NomotoParameters(model.parameter("yaw.gain"), model.parameter("yaw.time_constant"))


def _design(model: ShipModel, rudder_limit: float, schedule: Schedule = "time") -> PDDesign:
    natural_frequency = NATURAL_FREQUENCY / ship_scales(model).time
    return PDDesign(natural_frequency, DAMPING, rudder_limit, model.service_speed, schedule)


def pd_controller(task: ShipTask, schedule: Schedule = "time") -> AutopilotController:
    """The PD autopilot on the raw instruments, gains from the preset's K*, tau* (5.79, 5.80).

    ``schedule``: how the gains follow the speed (:class:`~ship_env.baselines.pd_autopilot.PDDesign`);
    ``"fixed"`` is the fixed-gain variant (gains at the service speed).
    """
    model = task.model
    autopilot = PDAutopilot(_design(model, task.rudder_limit, schedule), preset_parameters(model), model.length)
    return AutopilotController(autopilot, task.rudder_limit)


def indirect_adaptive_controller(task: ShipTask) -> AutopilotController:
    """The indirect adaptive autopilot (5.5.2), its yaw filter starting at the preset's K*, tau*."""
    model = task.model
    yaw_filter = ship_yaw_filter(model, task.dt, preset_parameters(model))
    return AutopilotController(
        IndirectAdaptiveAutopilot(_design(model, task.rudder_limit), yaw_filter), task.rudder_limit
    )


def mrac_controller(task: ShipTask, reference_gain: float = REFERENCE_GAIN) -> AutopilotController:
    """The MRAC autopilot (5.5.3), filter and reference model starting at the preset's K*, tau*."""
    model = task.model
    parameters = preset_parameters(model)
    yaw_filter = ship_yaw_filter(model, task.dt, parameters)
    autopilot = ModelReferenceAutopilot(
        _design(model, task.rudder_limit), yaw_filter, parameters, reference_gain, adaptation_band=ADAPTATION_BAND
    )
    return AutopilotController(autopilot, task.rudder_limit)


def track_follow_controller(task: TrackFollowTask, seed: int = 0) -> TrackFollowController:
    """PRESYS on TrackFollow-v0: identification trial, MRAC with the identified reference model held
    (6.4.4.1: adaptation of the reference switched off), position filter, predictor-based course changer.
    The autopilot's gains are scheduled in the distance domain (3.52), as the track predictor assumes.

    ``seed``: the identification trial's (its sea and instrument noise).
    """
    model = task.model
    identified = identify_by_zigzag(model, preset_parameters(model), seed=seed)
    yaw_filter = ship_yaw_filter(model, task.dt, identified.parameters)
    autopilot = ModelReferenceAutopilot(
        _design(model, task.rudder_limit - COMPENSATION_HEADROOM, "distance"),
        yaw_filter,
        identified.parameters,
        reference_gain=0.0,
        adaptation_band=ADAPTATION_BAND,
    )
    noise = PositionFilterNoise(initial_sway=10.0).for_ship(task.scales)
    position_filter = PositionFilter(
        task.dt,
        sway_constant=identified.sway_constant,
        noise=dataclasses.replace(noise, position_fix=float(task.sensors[0]["position_noise"])),
    )
    settings = CourseChangerSettings(rudder_rate=model.parameter("steering_machine.rudder_rate")).for_ship(task.scales)
    course_changer = PredictiveCourseChanger(autopilot, position_filter, settings, task.dt)
    return TrackFollowController(course_changer, task.tracks, task.rudder_limit)
