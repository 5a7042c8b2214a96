"""``ship-env train``: train a stable-baselines3 agent with the hyper-parameters of ``configs/agents``.

Declared as :data:`COMMAND`; stable-baselines3 and torch are imported only when the command
runs, so the rest of the command line starts quickly.
"""

from __future__ import annotations

import argparse
import shlex
import time
from pathlib import Path

from ship_env.command_line import Command, add_progress_argument, ship_preset, whole_number
from ship_env.envs.variation import FITTED, FITTED_TERMS, draws_ships
from ship_env.extras import require
from ship_env.model import load_ship
from ship_env.ray_cluster import add_backend_arguments
from ship_env.rl.agents import ALGORITHMS, DEFAULT_TORCH_THREADS
from ship_env.rl.metadata import METADATA_FILE, MODEL_FILE, PolicyMetadata
from ship_env.rl.seeds import BACKENDS, SeedRun

#: The environment ``--env`` defaults to.
DEFAULT_ENV = "ship_env/CourseChange-v0"


def default_out(env_id: str, algo: str) -> Path:
    """``runs/<Env-vN>/<algo>``: the folder of the seeds' folders (``seed<S>``) without ``--out``."""
    return Path("runs") / env_id.rsplit("/", 1)[-1] / algo


def reproducing_command(args: argparse.Namespace, seed: int, out: Path) -> str:
    """The ``ship-env train`` command line that repeats one seed's run, every choice spelled out."""
    words = ["ship-env", "train", "--algo", args.algo, "--env", args.env, "--seed", str(seed)]
    if args.ship is not None:
        words += ["--ship", args.ship]
    if args.ship_variation is not None:
        words += ["--ship-variation", args.ship_variation]
    if args.steps is not None:
        words += ["--steps", str(args.steps)]
    if args.config is not None:
        words += ["--config", str(args.config)]
    if args.trained_agent is not None:
        words += ["--trained-agent", str(trained_agent(args, seed))]
    if args.torch_threads != DEFAULT_TORCH_THREADS:
        words += ["--torch-threads", str(args.torch_threads)]
    words += ["--out", str(out)]
    return shlex.join(words)


def trained_agent(args: argparse.Namespace, seed: int) -> Path | None:
    """The saved agent that seed ``seed``'s run continues: ``--trained-agent`` itself, or with
    ``--seeds`` and a folder of seeds' runs, the run of the same seed in it."""
    if args.trained_agent is None or args.seeds is None or not (args.trained_agent / f"seed{seed}").is_dir():
        return args.trained_agent
    return args.trained_agent / f"seed{seed}"


def seed_runs(args: argparse.Namespace) -> list[SeedRun]:
    """Each seed's run: ``--seed S`` goes to ``--out`` itself (default ``runs/<Env>/<algo>/seed<S>``),
    ``--seeds`` to ``<out>/seed<S>`` each."""
    if args.seeds is None:
        out = args.out if args.out is not None else default_out(args.env, args.algo) / f"seed{args.seed}"
        runs = [(args.seed, out)]
    else:
        parent = args.out if args.out is not None else default_out(args.env, args.algo)
        runs = [(seed, parent / f"seed{seed}") for seed in args.seeds]
    return [SeedRun(seed, out, reproducing_command(args, seed, out), trained_agent(args, seed)) for seed, out in runs]


def run_train(args: argparse.Namespace) -> int:
    """Train each seed, save ``model.zip`` and ``metadata.json`` into its folder, print a summary."""
    require("rl", "training", "torch", "stable_baselines3")
    from ship_env.ray_cluster import check_backend
    from ship_env.rl.agents import load_agent_config
    from ship_env.rl.policy_file import PolicyFileError, read_policy_file
    from ship_env.rl.seeds import train_seeds, trained_already
    from ship_env.rl.training import TENSORBOARD_FOLDER, tensorboard_installed

    check_backend(args.backend, args.ray_address)
    try:
        config = load_agent_config(args.algo, args.env, args.config)
    except ValueError as error:
        args.command_parser.error(f"argument --env/--config: {error}")
    if args.ship is not None:
        config = config.on_ship(args.ship)
    if args.ship_variation is not None:
        ship = str(config.env_kwargs.get("ship", "the environment's own, container_226m"))
        if "ship" not in config.env_kwargs or not draws_ships(load_ship(ship)):
            args.command_parser.error(
                f"argument --ship-variation: {FITTED} draws ships from a fitted preset's uncertainty (its fitted MMG "
                f"model's jackknife, or its effects' standard errors); the ship ({ship}) gives neither (none for "
                f"{', '.join(FITTED_TERMS)}; train --ship FILE written by fit --preset or improve --preset)"
            )
        config = config.with_ship_variation(args.ship_variation)
    runs = seed_runs(args)
    try:
        for run in runs:
            if run.trained_agent is not None:
                read_policy_file(run.trained_agent, trust_policy_code=True)
    except PolicyFileError as error:
        args.command_parser.error(f"argument -i/--trained-agent: {error}")
    existing = trained_already(runs)
    if existing and not args.force:
        args.command_parser.error(
            f"argument --out: already trained, not overwritten without --force: {', '.join(map(str, existing))}"
        )

    def report(run: SeedRun, metadata: PolicyMetadata) -> None:
        print(
            f"{args.algo} on {args.env}, seed {run.seed}: {metadata.timesteps} steps in {metadata.wall_time_s:.1f} s "
            f"({config.n_envs} envs, {args.torch_threads} torch thread(s)) -> {run.out / MODEL_FILE}",
            flush=True,
        )

    start = time.perf_counter()
    try:
        train_seeds(
            config,
            runs,
            steps=args.steps,
            torch_threads=args.torch_threads,
            backend=args.backend,
            ray_address=args.ray_address,
            on_done=report,
            progress_bar=not args.no_progress and len(runs) == 1,
        )
    except PolicyFileError as error:
        args.command_parser.error(f"argument -i/--trained-agent: {error}")
    if len(runs) > 1:
        print(f"{len(runs)} seeds in {time.perf_counter() - start:.1f} s on the {args.backend} backend")
    print(f"metadata (with the command that repeats each run): {METADATA_FILE} beside each model")
    if tensorboard_installed():
        print("tensorboard --logdir " + " --logdir ".join(str(run.out / TENSORBOARD_FOLDER) for run in runs))
    return 0


def _seed_list(text: str) -> tuple[int, ...]:
    from ship_env.rl.seeds import parse_seeds

    try:
        return parse_seeds(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``ship-env train``."""
    parser.add_argument("--algo", choices=list(ALGORITHMS), required=True, help="the algorithm")
    parser.add_argument(
        "--env", default=DEFAULT_ENV, metavar="ID", help="the Gymnasium environment id (default: %(default)s)"
    )
    parser.add_argument(
        "--ship",
        type=ship_preset,
        default=None,
        metavar="FILE",
        help="the ship trained on: a preset name or a ship YAML (say one written by ship-env fit ... --preset), "
        "in place of the config's env_kwargs ship (default: the config's, else container_226m)",
    )
    parser.add_argument(
        "--ship-variation",
        choices=[FITTED],
        default=None,
        help="in place of the config's env_kwargs ship_variation: fitted draws each episode's ship from the --ship "
        "preset's uncertainty: K*, tau* from its standard errors, or, where a fitted MMG model sails it, the model "
        "from its jackknife (a preset written by ship-env fit/improve/fit-mmg --preset)",
    )
    parser.add_argument(
        "--steps",
        type=whole_number(1),
        default=None,
        metavar="N",
        help="environment steps to train (default: the config's n_timesteps)",
    )
    seeds = parser.add_mutually_exclusive_group()
    seeds.add_argument("--seed", type=whole_number(0), default=0, metavar="S", help="random seed (default: 0)")
    seeds.add_argument(
        "--seeds",
        type=_seed_list,
        default=None,
        metavar="LIST",
        help="train several seeds, one folder <out>/seed<S> each: a range 0-4, a list 0,2,5, or both 0-2,7",
    )
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        metavar="DIR",
        help="folder for model.zip and metadata.json (default: runs/<Env>/<algo>/seed<S>); "
        "with --seeds, the folder of the seeds' folders (default: runs/<Env>/<algo>)",
    )
    parser.add_argument(
        "-i",
        "--trained-agent",
        type=Path,
        default=None,
        metavar="PATH",
        help="continue training a saved agent (rl-zoo3's option): its model.zip or its run's folder, "
        "or with --seeds a folder of seeds' runs (each seed continues its own); its weights go into "
        "the config's policy (class and policy_kwargs: another class takes them where they fit exactly), "
        "with the config's other hyper-parameters; read as stable-baselines3 loads it, which runs any code "
        "the zip's pickles carry: continue only agents you trust",
    )
    parser.add_argument("--force", action="store_true", help="overwrite runs already trained in those folders")
    add_backend_arguments(
        parser,
        BACKENDS,
        "local: the seeds one after another in this process; ray: one Ray task per seed, the same weights bit for bit",
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
        type=whole_number(1),
        default=DEFAULT_TORCH_THREADS,
        metavar="N",
        help="torch intra-op threads; 1 is fastest on 2 shared cores (default: %(default)s)",
    )
    add_progress_argument(parser)


COMMAND = Command(
    "train",
    description=(
        "Train a stable-baselines3 agent (or sb3-contrib's RecurrentPPO: --algo ppo_lstm) on the native\n"
        "vector environment with the hyper-parameters of configs/agents/<algo>.yaml (one entry per\n"
        "environment id, as rl-zoo3 keeps them), and\n"
        "save model.zip with metadata.json (environment and its kwargs, config, seed, steps, wall\n"
        "time, package versions, the command that reproduces the run). --seeds trains several seeds,\n"
        "one after another or as Ray tasks (--backend ray), each the same run as its own --seed command.\n"
        "--ship trains on another ship (a fitted preset's YAML), recorded as the env kwargs' ship;\n"
        "--ship-variation fitted on ships drawn from its standard errors.\n"
        "--trained-agent continues a saved agent instead of new weights (fine-tuning it on other\n"
        "environment options), recorded in the metadata with the file's SHA-256.\n"
        "A folder that already holds a run is not overwritten without --force. TensorBoard logs go to\n"
        "<out>/tensorboard when tensorboard is installed.\n"
        'Needs the rl extra: pip install "ship-env[rl]".'
    ),
    examples=(
        "ship-env train --algo ppo --env ship_env/CourseChange-v0",
        "ship-env train --algo ppo --env ship_env/CourseChange-v0 --seeds 0-4 --backend ray",
        "ship-env train --algo sac --env ship_env/CourseChange-v0 --steps 50000 --seed 3 --out runs/sac3",
        "ship-env train --algo ppo --env ship_env/CourseChange-v0 --ship fitted.yaml --seeds 0-4 --out runs/fitted",
        "ship-env train --algo ppo --ship fitted.yaml --ship-variation fitted --seeds 0-4 --out runs/fitted_draws",
        "ship-env train --algo ppo --env ship_env/TrackFollow-v0 --seeds 0-4 --config tuned.yaml "
        "--trained-agent ship_env/policies/TrackFollow-v0/ppo",
    ),
    handler=run_train,
    arguments=add_arguments,
)
