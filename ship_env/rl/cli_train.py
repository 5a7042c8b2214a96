"""``ship-env train``: train a stable-baselines3 agent with the hyper-parameters of ``configs/agents``.

Registered by :func:`add_parser`; stable-baselines3 and torch are imported only when the command
runs, so the rest of the command line starts quickly.
"""

from __future__ import annotations

import argparse
import shlex
from pathlib import Path

from ship_env.rl.agents import ALGORITHMS, DEFAULT_TORCH_THREADS
from ship_env.rl.metadata import METADATA_FILE

#: The environment ``--env`` defaults to.
DEFAULT_ENV = "ship_env/CourseChange-v0"


def _whole_number(minimum: int):
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"expected a whole number >= {minimum}, got {text!r}")
        return value

    return parse


def default_out(env_id: str, algo: str, seed: int) -> Path:
    """``runs/<Env-vN>/<algo>/seed<S>``: where a run goes without ``--out``."""
    return Path("runs") / env_id.rsplit("/", 1)[-1] / algo / f"seed{seed}"


def reproducing_command(args: argparse.Namespace, out: Path) -> str:
    """The ``ship-env train`` command line that repeats this run, every choice spelled out."""
    words = ["ship-env", "train", "--algo", args.algo, "--env", args.env, "--seed", str(args.seed)]
    if args.steps is not None:
        words += ["--steps", str(args.steps)]
    if args.config is not None:
        words += ["--config", str(args.config)]
    if args.torch_threads != DEFAULT_TORCH_THREADS:
        words += ["--torch-threads", str(args.torch_threads)]
    words += ["--out", str(out)]
    return shlex.join(words)


def run_train(args: argparse.Namespace) -> int:
    """Train, save ``model.zip`` and ``metadata.json`` into ``--out``, print a summary."""
    from ship_env.rl.agents import load_agent_config
    from ship_env.rl.training import TENSORBOARD_FOLDER, tensorboard_installed, train

    try:
        config = load_agent_config(args.algo, args.env, args.config)
    except ValueError as error:
        args.command_parser.error(f"argument --env/--config: {error}")
    out = args.out if args.out is not None else default_out(args.env, args.algo, args.seed)
    run = train(
        config,
        out,
        reproducing_command(args, out),
        steps=args.steps,
        seed=args.seed,
        torch_threads=args.torch_threads,
        progress_bar=not args.no_progress,
    )
    metadata = run.metadata
    print(
        f"{args.algo} on {args.env}: {metadata.timesteps} steps in {metadata.wall_time_s:.1f} s "
        f"({config.n_envs} envs, {args.torch_threads} torch thread(s), seed {args.seed})"
    )
    print(f"model    {run.model_path}\nmetadata {out / METADATA_FILE}")
    if tensorboard_installed():
        print(f"tensorboard --logdir {out / TENSORBOARD_FOLDER}")
    return 0


def add_parser(subcommands: argparse._SubParsersAction) -> None:
    """Register ``ship-env train``."""
    parser = subcommands.add_parser(
        "train",
        help="train a PPO or SAC policy on an environment",
        description=(
            "Train a stable-baselines3 agent on the native vector environment with the hyper-parameters\n"
            "of configs/agents/<algo>.yaml (one entry per environment id, as rl-zoo3 keeps them), and\n"
            "save model.zip with metadata.json (environment and its kwargs, config, seed, steps, wall\n"
            "time, package versions, the command that reproduces the run). TensorBoard logs go to\n"
            "<out>/tensorboard when tensorboard is installed."
        ),
        epilog=(
            "examples:\n"
            "  ship-env train --algo ppo --env ship_env/CourseChange-v0\n"
            "  ship-env train --algo sac --env ship_env/CourseChange-v0 --steps 50000 --seed 3 --out runs/sac3"
        ),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--algo", choices=list(ALGORITHMS), required=True, help="the algorithm")
    parser.add_argument(
        "--env", default=DEFAULT_ENV, metavar="ID", help="the Gymnasium environment id (default: %(default)s)"
    )
    parser.add_argument(
        "--steps",
        type=_whole_number(1),
        default=None,
        metavar="N",
        help="environment steps to train (default: the config's n_timesteps)",
    )
    parser.add_argument("--seed", type=_whole_number(0), default=0, metavar="S", help="random seed (default: 0)")
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        metavar="DIR",
        help="folder for model.zip and metadata.json (default: runs/<Env>/<algo>/seed<S>)",
    )
    parser.add_argument(
        "--config",
        type=Path,
        default=None,
        metavar="FILE",
        help="agent config YAML keyed by environment id (default: configs/agents/<algo>.yaml)",
    )
    parser.add_argument(
        "--torch-threads",
        type=_whole_number(1),
        default=DEFAULT_TORCH_THREADS,
        metavar="N",
        help="torch intra-op threads; 1 is fastest on 2 shared cores (default: %(default)s)",
    )
    parser.add_argument("--no-progress", action="store_true", help="do not show the progress bar")
    parser.set_defaults(handler=run_train, command_parser=parser)
