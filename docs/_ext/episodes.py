"""The ``env-episode`` directive: an environment's episode, drawn by its ``rgb_array`` renderer at build
time and shown as an animated GIF, above the table of its spaces (Gymnasium's environment pages' header).

It writes reStructuredText, so a Markdown page calls it inside ``eval-rst``::

    ```{eval-rst}
    .. env-episode:: ship_env/CourseChange-v0
       :controller: pd
       :options: {"disturbance": "wind_current"}
       :seed: 0
       :frames: 40
    ```

``controller``: the classic autopilot that sails it, ``pd`` (the PD autopilot, gains scheduled on the speed)
or ``track`` (PRESYS's track follower: identification trial, MRAC, position filter, course changer);
``options``: the environment's keywords (JSON); ``frames``: how many frames the GIF shows, evenly over the
episode or its first ``steps`` steps. The GIF is redrawn when the code changes (:mod:`generated`).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
from docutils import nodes
from docutils.parsers.rst import directives
from generated import GENERATED, is_current, mark_current
from PIL import Image
from sphinx.application import Sphinx
from sphinx.util.docutils import SphinxDirective

FOLDER = GENERATED / "episodes"
#: Width of the GIF's frames, pixels (the renderer draws 600).
FRAME_WIDTH = 480
#: Milliseconds each frame shows; the last frame holds for HOLD_MS.
FRAME_MS = 120
HOLD_MS = 2000
CONTROLLERS = {
    "pd": "the PD autopilot (gains scheduled on the speed)",
    "track": "PRESYS's track follower (identification trial, MRAC, position filter, course changer)",
}


def _controller(name: str, env: Any) -> Any:
    from ship_env.baselines import presys

    task = env.unwrapped.task
    return presys.track_follow_controller(task) if name == "track" else presys.pd_controller(task)


def sail_frames(
    env_id: str, controller: str, options: dict[str, Any], seed: int, frames: int, steps: int | None = None
) -> list[np.ndarray]:
    """Sail one episode of ``env_id`` with ``controller`` for ``steps`` (default: the whole episode) and return
    ``frames`` of it, evenly spaced, the first and last included."""
    import gymnasium as gym

    import ship_env  # noqa: F401  (registers the environments)

    env = gym.make(env_id, render_mode="rgb_array", **options)
    sailor = _controller(controller, env)
    observation, info = env.reset(seed=seed)
    # The autopilots steer to info["new_heading"]; on CourseKeeping that is the episode's course.
    ordered = {"new_heading": getattr(info["scenario"], "course", None)}
    sailor.reset(observation, info)
    drawn = [env.render()]
    if steps is None:
        steps = env.spec.max_episode_steps if env.spec and env.spec.max_episode_steps else 600
    stride = max(1, steps // max(1, frames - 1))
    for step in range(1, steps + 1):
        observation, _, terminated, truncated, info = env.step(sailor.act(observation, {**ordered, **info}))
        done = terminated or truncated
        if step % stride == 0 or done or step == steps:
            drawn.append(env.render())
        if done:
            break
    env.close()
    return drawn


def write_gif(frames: list[np.ndarray], path: Path) -> None:
    """The frames as a looping GIF, each scaled to FRAME_WIDTH, the last one held."""
    images = []
    for frame in frames:
        image = Image.fromarray(frame)
        height = round(image.height * FRAME_WIDTH / image.width)
        images.append(image.resize((FRAME_WIDTH, height), Image.LANCZOS).quantize(colors=64))
    durations = [FRAME_MS] * (len(images) - 1) + [HOLD_MS]
    images[0].save(path, save_all=True, append_images=images[1:], duration=durations, loop=0, optimize=True)


def spaces_table(env_id: str, options: dict[str, Any]) -> str:
    """reStructuredText: the environment's action and observation spaces, how to make it, its length."""
    import gymnasium as gym

    import ship_env  # noqa: F401

    env = gym.make(env_id, **options)
    steps = env.spec.max_episode_steps if env.spec else None
    rows = [
        ("Action Space", f"``{env.action_space}``"),
        ("Observation Space", f"``{env.observation_space}``"),
        ("Episode length", f"{steps} steps (truncated)" if steps else "unbounded"),
        ("Import", f'``gymnasium.make("{env_id}")``'),
        ("Vectorised", f'``gymnasium.make_vec("{env_id}", num_envs=N, vectorization_mode="vector_entry_point")``'),
    ]
    env.close()
    lines = [".. list-table::", "   :widths: 25 75", ""]
    for name, value in rows:
        lines += [f"   * - {name}", f"     - {value}"]
    return "\n".join(lines) + "\n"


class EnvEpisode(SphinxDirective):
    """``.. env-episode:: ENV_ID``: the episode's GIF, its caption and the spaces table."""

    required_arguments = 1
    option_spec = {
        "controller": lambda value: directives.choice(value, tuple(CONTROLLERS)),
        "options": directives.unchanged,
        "seed": directives.nonnegative_int,
        "frames": directives.positive_int,
        "steps": directives.positive_int,
    }

    def run(self) -> list[nodes.Node]:
        env_id = self.arguments[0]
        controller = self.options.get("controller", "pd")
        options = json.loads(self.options.get("options", "{}"))
        seed = self.options.get("seed", 0)
        frames = self.options.get("frames", 40)
        steps = self.options.get("steps")
        request = {"env": env_id, "controller": controller, "options": options, "seed": seed, "frames": frames}
        if steps is not None:
            request["steps"] = steps
        name = env_id.split("/")[-1]
        folder = FOLDER / name
        gif = folder / "episode.gif"
        if not (gif.exists() and is_current(folder, request)):
            folder.mkdir(parents=True, exist_ok=True)
            write_gif(sail_frames(env_id, controller, options, seed, frames, steps), gif)
            mark_current(folder, request)
        keywords = ", ".join(f"{key}={value!r}" for key, value in options.items()) or "its defaults"
        caption = (
            f'An episode drawn by ``render_mode="rgb_array"`` at this page\'s build: ``{env_id}`` with {keywords}, '
            f"seed {seed}, sailed by {CONTROLLERS[controller]}" + (f", its first {steps} steps." if steps else ".")
        )
        uri = "/" + gif.relative_to(self.env.srcdir).as_posix()
        text = f".. figure:: {uri}\n   :alt: an episode of {env_id}\n\n   {caption}\n\n{spaces_table(env_id, options)}"
        return self.parse_text_to_nodes(text)


def setup(app: Sphinx) -> dict[str, object]:
    app.add_directive("env-episode", EnvEpisode)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
