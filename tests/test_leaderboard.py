"""The leaderboard: seeded and deterministic, the classic baselines where they should shine, the shipped policy."""

from __future__ import annotations

import csv
import dataclasses
import math
from pathlib import Path

import pytest
import yaml

from ship_env.cli import main
from ship_env.envs.tracks import THESIS_COURSE_CHANGES_DEG
from ship_env.leaderboard.board import Leaderboard, run_leaderboard, write_leaderboard
from ship_env.leaderboard.suites import (
    COURSE_CHANGE,
    COURSE_CHANGE_DISTURBANCES,
    FIRST_WAYPOINT,
    HALF_SPEED,
    K_TAU_DOUBLE,
    K_TAU_HALF,
    NOMINAL,
    SUITE_SPECS,
    TEST_COURSE_CHANGES_DEG,
    TEST_FIRST_SEED,
    TRACK_FOLLOW,
    SuiteSpec,
)
from ship_env.leaderboard.tables import BETTER, TRAVEL_ALLOWANCE, WORSE, comparisons, learned_verdicts, rank
from ship_env.rl.policy_file import seed_models
from ship_env.rl.shipped import shipped_folder

SHIPPED_PPO = "PPO (shipped)"
#: One course change each way in calm water: the smallest suite that exercises every entrant.
TINY = SuiteSpec(course_changes_deg=(45.0,), tracks=(), conditions=(NOMINAL,), course_change_disturbances=("calm",))


def lines_past_100_columns(out: str, folder: Path) -> list[str]:
    """The printed lines wider than a terminal's 100 columns, but for those naming the output folder (as long as
    its path)."""
    return [line for line in out.splitlines() if len(line) > 100 and str(folder) not in line]


@pytest.mark.slow
def test_the_same_seeds_give_the_same_table_to_the_last_digit():
    first = run_leaderboard(TINY, progress=False)
    second = run_leaderboard(TINY, progress=False)
    assert first.markdown() == second.markdown()
    assert [r.metrics for r in first.results] == [r.metrics for r in second.results]
    assert {r.entrant for r in first.results} >= {"PD, fixed gains", "MRAC", SHIPPED_PPO}


def test_the_dev_suite_is_the_first_repetition_of_the_full_one_and_quick_its_alias():
    dev = {suite.name: suite.episodes for suite in SUITE_SPECS["dev"].suites()}
    full = {suite.name: suite.episodes for suite in SUITE_SPECS["full"].suites()}
    assert set(dev) == set(full)
    for name, episodes in dev.items():
        assert full[name][: len(episodes)] == episodes
    seeds = [episode.seed for episode in full["CourseChange calm | nominal"]]
    assert len(set(seeds)) == len(seeds) == 30
    assert SUITE_SPECS["quick"] == SUITE_SPECS["dev"]


def _sailed(spec_name: str, env_id: str) -> list:
    """Every (suite's environment keywords, episode) of a named suite on ``env_id``."""
    return [
        (suite.env_kwargs, e)
        for suite in SUITE_SPECS[spec_name].suites()
        if suite.env_id == env_id
        for e in suite.episodes
    ]


def test_the_test_suite_shares_no_episode_with_dev_or_full():
    """No course-change magnitude of dev or full (nor of the environments' own draws, the thesis's
    five), no seed of theirs, and no TrackFollow start from the first waypoint where they start."""
    test_changes = _sailed("test", COURSE_CHANGE)
    test_tracks = _sailed("test", TRACK_FOLLOW)
    assert len(test_changes) == 12 * 12 and len(test_tracks) == 4 * 6  # 12 suites x 12 changes; 4 x T1..T6
    magnitudes = {abs(e.options["course_change_deg"]) for _, e in test_changes}
    assert magnitudes == set(TEST_COURSE_CHANGES_DEG) and not magnitudes & set(THESIS_COURSE_CHANGES_DEG)
    test_seeds = {e.seed for _, e in test_changes + test_tracks}
    for screen in ("dev", "full"):
        screened = _sailed(screen, COURSE_CHANGE) + _sailed(screen, TRACK_FOLLOW)
        assert not magnitudes & {
            abs(e.options["course_change_deg"]) for _, e in screened if "course_change_deg" in e.options
        }
        assert not test_seeds & {e.seed for _, e in screened}
        assert {kwargs.get("start", FIRST_WAYPOINT) for kwargs, e in screened if "track" in e.options} == {
            FIRST_WAYPOINT
        }
    assert {kwargs["start"] for kwargs, _ in test_tracks} == {"before_turn"}


@pytest.mark.slow
def test_a_track_sailed_from_before_a_turn_has_no_thesis_navigator_rows():
    """The thesis's navigators sailed whole tracks: their rows stand beside whole tracks only."""
    spec = dataclasses.replace(
        SUITE_SPECS["test"], course_changes_deg=(), course_change_disturbances=(), tracks=("T2",), conditions=(NOMINAL,)
    )
    table = run_leaderboard(spec, shipped=False, progress=False).table("TrackFollow | nominal")
    assert [(s.entrant, s.completed) for s in table.standings] == [("predictor course changer", 1)]
    assert table.suite.episodes[0].seed == TEST_FIRST_SEED


@pytest.fixture(scope="module")
def nominal_course_changes():
    """Every entrant on the dev suite's calm and wind-and-current course changes."""
    spec = SuiteSpec(tracks=(), conditions=(NOMINAL,), course_change_disturbances=("calm", "wind_current"))
    return run_leaderboard(spec, progress=False)


@pytest.fixture(scope="module")
def robustness():
    """The classic baselines on CourseChange at half speed and with the ship's K*, tau* halved and doubled."""
    spec = SuiteSpec(
        tracks=(),
        conditions=(HALF_SPEED, K_TAU_HALF, K_TAU_DOUBLE),
        course_change_disturbances=("calm", "wind_current"),
    )
    return run_leaderboard(spec, shipped=False, progress=False)


def _beside_the_fixed_pd(table, name: str):
    """The fixed PD's and ``name``'s standings in ``table``, printed for the test log."""
    fixed, other = table.standing("PD, fixed gains"), table.standing(name)
    print(f"{table.suite.name}: fixed {fixed.values}\n {name} {other.values}")
    return fixed, other


@pytest.mark.slow
@pytest.mark.parametrize("disturbance", ["calm", "wind_current"])
def test_gain_scheduled_pd_beats_the_fixed_pd_at_half_speed(robustness, disturbance):
    """Fixed gains at half speed leave the loop at half its natural frequency and with damping 0.60
    (:mod:`ship_env.baselines.pd_autopilot`); the scheduled PD holds omega_n and zeta in seconds: less
    heading error, no overshoot, settled sooner. The four-fold gains that takes also answer the raw
    gyro's noise four-fold, so its rudder travel is the larger (without noise it is within the travel
    allowance: ``test_baselines_pd``); the adaptive autopilots, scheduled alike but on the yaw
    filter's signals, beat the fixed PD with less rudder travel."""
    table = robustness.table(f"CourseChange {disturbance} | half speed")
    fixed, scheduled = _beside_the_fixed_pd(table, "PD, gain-scheduled")
    assert scheduled.rank < fixed.rank
    assert scheduled.values["integrated_heading_error"] < fixed.values["integrated_heading_error"]
    assert scheduled.values["overshoot"] < fixed.values["overshoot"]
    assert scheduled.values["settling_time"] < fixed.values["settling_time"]
    assert scheduled.completed >= fixed.completed
    for name in ("indirect adaptive PD", "MRAC"):
        adaptive = table.standing(name)
        assert adaptive.values["integrated_heading_error"] < fixed.values["integrated_heading_error"]
        assert adaptive.values["rudder_travel"] < fixed.values["rudder_travel"]


@pytest.mark.slow
@pytest.mark.parametrize("disturbance", ["calm", "wind_current"])
def test_mrac_beats_the_fixed_pd_when_the_ships_k_and_tau_are_halved(robustness, disturbance):
    table = robustness.table(f"CourseChange {disturbance} | K*, tau* x0.5")
    fixed, mrac = _beside_the_fixed_pd(table, "MRAC")
    assert mrac.rank < fixed.rank
    assert mrac.values["integrated_heading_error"] < fixed.values["integrated_heading_error"]
    assert mrac.values["rudder_travel"] < fixed.values["rudder_travel"]


@pytest.mark.slow
@pytest.mark.parametrize("disturbance", ["calm", "wind_current"])
def test_mrac_keeps_the_design_loop_when_the_ships_k_and_tau_are_doubled(
    robustness, nominal_course_changes, disturbance
):
    """K*, tau* doubled keep K*/tau*, so the fixed gains keep omega_n; their damping falls from 1 to
    0.90 and the ship turns half as fast again at full helm: the fixed PD's turns get quicker. MRAC
    makes the ship answer like its reference model, the design ship, and keeps the designed turn,
    so its heading error changes less from the nominal ship's than the fixed PD's does; it is the
    larger of the two (a PD designed with the true K*, tau* loses to the detuned one as well:
    ``test_baselines_pd``), with less overshoot and a third of the rudder travel."""
    table = robustness.table(f"CourseChange {disturbance} | K*, tau* x2")
    nominal = nominal_course_changes.table(f"CourseChange {disturbance} | nominal")
    fixed, mrac = _beside_the_fixed_pd(table, "MRAC")
    error = "integrated_heading_error"
    mrac_shift = abs(mrac.values[error] - nominal.standing("MRAC").values[error])
    fixed_shift = abs(fixed.values[error] - nominal.standing("PD, fixed gains").values[error])
    assert mrac_shift < fixed_shift
    assert fixed.values[error] < mrac.values[error]
    assert mrac.values["overshoot"] < fixed.values["overshoot"]
    assert mrac.values["rudder_travel"] < fixed.values["rudder_travel"]


@pytest.mark.slow
@pytest.mark.parametrize("disturbance", ["calm", "wind_current"])
def test_shipped_ppo_beats_the_best_classic_baseline(nominal_course_changes, disturbance):
    """Five training seeds x ten course changes: the probability of improvement's interval lies above parity."""
    assert len(seed_models(shipped_folder("ship_env/CourseChange-v0", "ppo"))) == 5
    table = nominal_course_changes.table(f"CourseChange {disturbance} | nominal")
    (comparison,) = [c for c in comparisons(table) if c.learned == SHIPPED_PPO]
    print(comparison)
    assert table.standing(SHIPPED_PPO).sample == "5 seeds x 10 episodes"
    assert comparison.improvement.low > 0.5
    assert comparison.score_ratio < 1.0
    assert comparison.travel_ratio <= TRAVEL_ALLOWANCE
    assert comparison.verdict == BETTER
    assert table.standing(SHIPPED_PPO).rank == 1


@pytest.mark.slow
def test_outputs_are_tables_csv_and_plots(tmp_path):
    spec = SuiteSpec(
        course_changes_deg=(30.0,), tracks=("T2",), conditions=(NOMINAL,), course_change_disturbances=("calm",)
    )
    board = run_leaderboard(spec, progress=False)
    written = write_leaderboard(board, tmp_path)
    assert {path.name for path in written} == {
        "leaderboard.md",
        "leaderboard.csv",
        "episodes.csv",
        "scores.png",
        "headline.png",
        "course_change_sample.png",
        "track_follow_sample.png",
    }
    for path in written:
        assert path.stat().st_size > 0
    with (tmp_path / "leaderboard.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    track = [row for row in rows if row["task"] == "TrackFollow"]
    assert [row["controller"] for row in track if row["kind"] == "human"] == [
        "navigators, track predictor (thesis)",
        "navigators, ground-speed vector (thesis)",
        "navigators, parallel indexing (thesis)",
    ]
    predictor = next(row for row in track if row["controller"] == "predictor course changer")
    assert float(predictor["rms_cross_track_error"]) < 33.0 and predictor["rank"] == "1"
    learned = next(row for row in track if row["controller"] == SHIPPED_PPO)
    assert learned["kind"] == "learned" and learned["episodes"] == "1"
    assert learned["seeds"] == "5" and int(learned["completed"]) <= 5  # completed: all seeds together
    assert learned["iqm_low"] != ""  # five seeds of one episode: an interval over the seeds
    assert float(learned["improvement"]) == 0.0  # the predictor course changer is far better on T2
    ranks = [int(row["rank"]) for row in rows if row["suite"] == "CourseChange calm | nominal"]
    assert ranks == list(range(1, len(ranks) + 1))
    with (tmp_path / "episodes.csv").open() as handle:
        assert len(list(csv.DictReader(handle))) == len(board.results)


@pytest.mark.slow
def test_leaderboard_command_prints_ranked_tables_and_writes_files(tmp_path, capsys):
    status = main(
        [
            "leaderboard",
            "--course-changes",
            "15",
            "--disturbances",
            "wind_current",
            "--no-tracks",
            "--conditions",
            "nominal",
            "half-speed",
            "--out",
            str(tmp_path),
            "--no-plots",
        ]
    )
    assert status == 0
    out, err = capsys.readouterr()
    assert "CourseChange, nominal ship, all seas together (container_226m): normalised score" in out
    assert f"{SHIPPED_PPO} on ship_env/CourseChange-v0: better on " in out and " of 2" in out
    assert "TrackFollow" not in out and "###" not in out  # the tables are in the file
    assert lines_past_100_columns(out, tmp_path) == []
    assert "on the local backend" in out
    assert f"every suite's ranked table: {tmp_path / 'leaderboard.md'}" in out
    assert "leaderboard" in err  # the progress bar over episodes, on stderr
    written = (tmp_path / "leaderboard.md").read_text()
    assert written.startswith("### Headline: CourseChange, nominal ship, all seas together")
    assert (
        "### CourseChange wind_current | nominal" in written and "### CourseChange wind_current | half speed" in written
    )
    assert f"| {SHIPPED_PPO} | learned |" in written and "[95 % CI]" in written


#: :data:`TINY` on the command line, without the shipped policy or drawings.
TINY_COMMAND = [
    "leaderboard",
    "--course-changes",
    "45",
    "--disturbances",
    "calm",
    "--no-tracks",
    "--conditions",
    "nominal",
]
TINY_COMMAND += ["--no-shipped", "--no-plots", "--no-progress"]


def test_each_run_writes_a_folder_named_after_its_suite_and_ship_and_prints_within_100_columns(
    tmp_path, monkeypatch, capsys
):
    monkeypatch.chdir(tmp_path)
    assert main([*TINY_COMMAND, "--suite", "test"]) == 0
    assert main([*TINY_COMMAND, "--ship", "esso_osaka_model"]) == 0
    written = sorted(path.relative_to(tmp_path).as_posix() for path in tmp_path.rglob("leaderboard.md"))
    assert written == ["out/leaderboard/dev-esso_osaka_model/leaderboard.md", "out/leaderboard/test/leaderboard.md"]
    out = capsys.readouterr().out
    assert "every suite's ranked table: out/leaderboard/test/leaderboard.md" in out
    assert "PD, fixed gains" in out and "###" not in out
    assert lines_past_100_columns(out, tmp_path) == []


def test_a_run_leaves_no_drawing_of_an_earlier_run_in_its_folder(tmp_path):
    board = run_leaderboard(TINY, shipped=False, progress=False)
    for name in ("track_follow_sample.png", "scores.png"):
        (tmp_path / name).write_bytes(b"an earlier run's")
    (tmp_path / "notes.txt").write_text("the user's own")
    written = write_leaderboard(board, tmp_path, plots=False)
    assert sorted(path.name for path in tmp_path.iterdir()) == sorted([*(path.name for path in written), "notes.txt"])


def test_settling_time_averages_the_settled_episodes_only():
    """One of an entrant's two episodes made unsettled (an infinite settling time): its settling time
    is the other episode's, and it completes one episode of two; every other entrant keeps its mean."""
    board = run_leaderboard(TINY, shipped=False, progress=False)
    (suite,) = board.suites
    for standing in board.table(suite.name).standings:
        assert standing.completed == standing.episodes == 2
        assert math.isfinite(standing.values["settling_time"])
    unsettled, settled = (r for r in board.results if r.entrant == board.results[0].entrant)
    never = dataclasses.replace(unsettled, metrics=unsettled.metrics | {"settling_time": math.inf})
    standing = rank(suite, [never if r is unsettled else r for r in board.results]).standing(unsettled.entrant)
    assert standing.values["settling_time"] == settled.metrics["settling_time"]
    assert (standing.completed, standing.missed) == (1, frozenset({(never.episode, never.seed)}))


@pytest.mark.slow
def test_ray_backend_gives_the_local_table():
    """One Ray task per controller, training seed and suite; the same table and intervals to the last digit."""
    ray = pytest.importorskip("ray", reason="Ray (the dev extra) is not installed")
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        on_ray = run_leaderboard(TINY, backend="ray", progress=False)
    finally:
        ray.shutdown()
    local = run_leaderboard(TINY, progress=False)
    assert on_ray.markdown() == local.markdown()
    assert "5 seeds x 2 episodes" in local.markdown()


def test_a_ray_address_that_does_not_answer_is_named(tmp_path, capsys):
    pytest.importorskip("ray", reason="Ray (the dev extra) is not installed")
    with pytest.raises(SystemExit) as raised:
        main(["leaderboard", "--backend", "ray", "--ray-address", "127.0.0.1:1", "--out", str(tmp_path)])
    assert raised.value.code == 2
    assert "argument --ray-address: Ray address '127.0.0.1:1': no Ray cluster answers there" in capsys.readouterr().err


@pytest.mark.slow
def test_a_folder_of_seeds_is_one_entrant_sailed_with_each_seed(tmp_path, capsys):
    """``ship-env train --seeds 0-1`` writes seed0/ and seed1/; ``--policies`` that folder ranks one entrant."""
    config = tmp_path / "ppo.yaml"
    entry = {"n_envs": 2, "n_steps": 64, "batch_size": 64, "n_epochs": 1, "policy_kwargs": "dict(net_arch=[8])"}
    config.write_text(yaml.safe_dump({"ship_env/CourseChange-v0": entry}))
    runs = tmp_path / "runs"
    train = ["train", "--algo", "ppo", "--seeds", "3,5", "--steps", "128", "--config", str(config), "--out", str(runs)]
    assert main([*train, "--no-progress"]) == 0
    board = run_leaderboard(TINY, policies=[runs], shipped=False, progress=False)
    standing = board.table("CourseChange calm | nominal").standing(f"PPO ({runs})")
    assert (standing.seeds, standing.episodes, standing.sample) == (2, 2, "2 seeds x 2 episodes")
    assert {r.training_seed for r in board.results if r.entrant == standing.entrant} == {3, 5}


@pytest.mark.slow
@pytest.mark.parametrize("disturbance", ["calm", "wind_current"])
def test_shipped_ppo_beats_the_best_classic_baseline_on_the_full_suite(disturbance):
    """Three times the dev suite's course changes, two of them with seeds the policy was never chosen on."""
    spec = SuiteSpec(repetitions=3, tracks=(), conditions=(NOMINAL,), course_change_disturbances=(disturbance,))
    table = run_leaderboard(spec, progress=False).table(f"CourseChange {disturbance} | nominal")
    (comparison,) = [c for c in comparisons(table) if c.learned == SHIPPED_PPO]
    print(comparison)
    assert comparison.verdict == BETTER


@pytest.fixture(scope="module")
def shipped_track_follow():
    """Every entrant on T1..T6 in the four conditions: the nominal ship, K*, tau* halved and doubled, half speed."""
    assert len(seed_models(shipped_folder("ship_env/TrackFollow-v0", "ppo"))) == 5
    spec = SuiteSpec(course_changes_deg=(), course_change_disturbances=())
    return run_leaderboard(spec, progress=False)


def check_shipped_course_change_ppo_on_the_test_suite(board: Leaderboard) -> None:
    """The shipped CourseChange PPO's verdicts on the test suite's 12 CourseChange suites (``board``)."""
    verdicts = learned_verdicts(board.tables, SHIPPED_PPO)
    print("\n".join(f"{name}: {c.verdict} {c}" for name, c in verdicts.items()))
    better = {name for name, c in verdicts.items() if c.verdict == BETTER}
    not_worse = {name for name, c in verdicts.items() if c.verdict != WORSE}
    assert len(verdicts) == 12
    assert better >= {f"CourseChange {d} | nominal" for d in COURSE_CHANGE_DISTURBANCES}
    assert f"CourseChange calm | {K_TAU_HALF.name}" in better
    assert not_worse >= {f"CourseChange {d} | {K_TAU_HALF.name}" for d in COURSE_CHANGE_DISTURBANCES}
    assert len(not_worse) >= 8
    assert board.headline_verdicts()[SHIPPED_PPO].verdict == BETTER


@pytest.mark.slow
def test_shipped_course_change_ppo_on_the_held_out_test_suite():
    """Five training seeds x the test suite's 12 CourseChange suites (calm, wind and current, waves; the
    nominal ship, K*, tau* halved and doubled, half speed), each 12 course changes of 10 to 120 deg that
    no screen sailed, with seeds no screen used; verdicts from the 95 % intervals of the probability of
    improvement over the best classic autopilot. Measured: better on every sea of the nominal ship,
    on all of them together (the headline) and with K*, tau* halved in calm water; tied in wind and
    current and in waves with them halved, and in calm water and in wind and current with them doubled;
    worse in waves with them doubled and at half speed in every sea: better on 4, tied on 4, worse on 4."""
    assert len(seed_models(shipped_folder("ship_env/CourseChange-v0", "ppo"))) == 5
    check_shipped_course_change_ppo_on_the_test_suite(
        run_leaderboard(dataclasses.replace(SUITE_SPECS["test"], tracks=()), progress=False)
    )


@pytest.mark.slow
def test_shipped_track_follow_ppo_sails_t1_to_t6_nearer_than_the_thesis_navigators(shipped_track_follow):
    """Five training seeds x T1..T6 on the nominal ship: every run reaches its track's end, and the
    IQM of the RMS cross-track error, its whole 95 % interval, lies below the track-predictor
    navigators' 33 m (Table 6.4), the best of the thesis's simulator experiment."""
    standing = shipped_track_follow.table("TrackFollow | nominal").standing(SHIPPED_PPO)
    print(standing)
    assert standing.sample == "5 seeds x 6 episodes" and standing.completed == 30
    assert standing.score.high is not None and standing.score.high < 33.0


@pytest.mark.slow
@pytest.mark.parametrize(
    "condition",
    [K_TAU_HALF, K_TAU_DOUBLE, HALF_SPEED],
    ids=lambda c: c.slug,
)
def test_shipped_track_follow_ppo_holds_within_twice_the_course_changer_off_the_nominal_ship(
    shipped_track_follow, condition
):
    """Off the ship the predictor course changer is designed for, the learned policy's IQM RMS
    cross-track error (five seeds x T1..T6) is at most twice the course changer's (the policy trained
    on the nominal ship only: 365 m against 143 with K*, tau* halved; fine-tuned on the halved ship
    it keeps the other conditions within the mark)."""
    table = shipped_track_follow.table(f"TrackFollow | {condition.name}")
    standing, course_changer = table.standing(SHIPPED_PPO), table.standing("predictor course changer")
    print(standing, course_changer, sep="\n")
    assert standing.score.value <= 2.0 * course_changer.score.value
