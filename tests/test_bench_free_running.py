"""The free-running benchmark's verdict: a fit on four sea-trial zig-zags of a full-scale tanker, with ``improve``'s
defaults, predicts the 35 deg turning circles and the 10/10 zig-zag it never saw within the issue's bounds
(advance and tactical diameter 5 %, steady rate and speed loss 10 %, first overshoot 2 deg).

The truth is kvlcc2's calm model with its values moved (``benchmarks/bench_free_running.py``). Seed 1 is the
sea trial on which the ladder once took the hull's cross-flow drag for Norrbin's cubic and wrote a preset that
stopped dead in the port turn; the slow set judges all five seeds the benchmark judges.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
import yaml

from ship_env.cli import main
from ship_env.model import EFFECTS, ShipModel

BENCH = Path(__file__).parents[1] / "benchmarks" / "bench_free_running.py"


def _judged(load_script, seed: int, folder: Path):
    bench = load_script(BENCH, "bench_free_running")
    return bench.judge(seed, folder)


def test_a_fit_on_sea_trial_zigzags_predicts_the_turning_circle(load_script, tmp_path):
    verdict = _judged(load_script, 1, tmp_path)
    assert verdict.cannot_turn == "" and verdict.failed == 0, verdict.rows


@pytest.mark.slow
@pytest.mark.parametrize("seed", [2, 3, 4, 5])
def test_every_sea_trial_of_the_benchmark_predicts_the_turning_circle(load_script, tmp_path, seed):
    verdict = _judged(load_script, seed, tmp_path)
    assert verdict.cannot_turn == "" and verdict.failed == 0, verdict.rows


def test_a_form_the_runs_cannot_rule_out_is_sailed_beside_the_preset(load_script, tmp_path, capsys):
    """The container ship's seed 2 sea trial: the ladder adds the hull's cross-flow drag (|r*| r*) where the truth's
    yaw damping is Norrbin's cubic, which alone fits the four zig-zags within 5 % in sample. ``improve --preset``
    sails it beside the preset, and the truth's hard-over speed loss and tactical diameter lie between the two,
    where the preset's own figures miss the speed loss by 11 % (its jackknife's +-0.7 points do not reach it)."""
    bench = load_script(BENCH, "bench_free_running")
    verdict = bench.judge(2, tmp_path, bench.make_truth("container_226m"))
    printed = capsys.readouterr().out
    assert "rival 1: norrbin.cubic alone for hull_crossflow" in printed
    table = printed.split("sailed free, mean of the 35 deg turns")[1]
    truth = {row[0]: float(row[1]) for row in verdict.rows}
    found_values = {}
    for figure, row in (("speed loss", "speed loss [%]"), ("tactical diameter", "tactical diameter [L]")):
        found = re.search(rf"^{re.escape(row)}\s+(\S+)\s+(\S+)$", table, flags=re.MULTILINE)
        assert found is not None, table
        found_values[row] = (found[1], found[2])
        preset, rival = float(found[1]), float(found[2])
        assert min(preset, rival) <= truth[figure] <= max(preset, rival), (figure, truth[figure], preset, rival)
    assert any(row[0] == "speed loss" and row[-1] == "FAIL" for row in verdict.rows)  # the preset alone misses it
    # The preset keeps the spread; ship-env manoeuvre prints it; ship-env scale Froude-scales it with the ship.
    recorded = yaml.safe_load((tmp_path / "fitted.yaml").read_text())["fitted"]["rival_forms"]
    (rival,) = recorded["rivals"]
    assert rival["form"] == "norrbin.cubic alone for hull_crossflow"
    assert rival["figures"]["speed loss [%]"]["value"] == float(found_values["speed loss [%]"][1])
    assert main(["manoeuvre", "--ship", str(tmp_path / "fitted.yaml")]) == 0
    assert "  norrbin.cubic alone for hull_crossflow (0.569): advance [L] 2.59" in capsys.readouterr().out
    scaled = tmp_path / "scaled.yaml"
    assert main(["scale", str(tmp_path / "fitted.yaml"), "--factor", "4", "-o", str(scaled)]) == 0
    (rival_scaled,) = yaml.safe_load(scaled.read_text())["fitted"]["rival_forms"]["rivals"]
    rate = "steady rate of turn [deg/s]"
    assert rival_scaled["figures"][rate]["value"] == pytest.approx(rival["figures"][rate]["value"] / 2.0, rel=1e-12)
    assert rival_scaled["figures"]["speed loss [%]"]["value"] == rival["figures"]["speed loss [%]"]["value"]


@pytest.mark.slow
def test_a_fit_on_an_independent_ships_zigzags_is_a_ship_that_sails_the_turning_circle(load_script, tmp_path):
    """shipmmg's MMG KVLCC2 as the truth: on seed 2's sea trial the zig-zags ask for no more than sway, whose fit
    cannot sail a hard-over turn (u* above 1); the ladder adds the best supported candidate with which it sails
    (``improve._first_that_sails``). Its figures are not yet within the
    bounds."""
    pytest.importorskip("shipmmg", reason='shipmmg is not installed (pip install shipmmg or -e ".[bench]")')
    bench = load_script(BENCH, "bench_free_running")
    verdict = bench.judge(2, tmp_path, bench.make_truth(bench.MMG))
    assert verdict.cannot_turn == "", verdict.cannot_turn


@pytest.mark.slow
def test_the_rudder_drag_makes_a_ship_of_a_fit_whose_speed_loss_stops_it_in_a_hard_over_turn(load_script, tmp_path):
    """On seed 3's sea trial of the MMG KVLCC2 the zig-zags' speed loss, all in r*^2, stops the fitted ship in a
    hard-over turn (u* above 1); the ladder adds the rudder's drag, with which the preset sails both turns."""
    pytest.importorskip("shipmmg", reason='shipmmg is not installed (pip install shipmmg or -e ".[bench]")')
    bench = load_script(BENCH, "bench_free_running")
    verdict = bench.judge(3, tmp_path, bench.make_truth(bench.MMG))
    assert verdict.cannot_turn == "", verdict.cannot_turn
    assert ShipModel(tmp_path / "fitted.yaml").has("rudder_drag")


@pytest.mark.slow
def test_named_among_the_candidates_the_drifts_resistance_makes_a_ship_where_the_rudders_drag_may_not(
    load_script, tmp_path
):
    """The same sea trial with every effect but the rudder's drag named as a candidate (the drift's resistance, which
    a ladder tries only where named, among them): the ladder adds the drift's resistance, with which the model sails
    the judged hard-over turns."""
    pytest.importorskip("shipmmg", reason='shipmmg is not installed (pip install shipmmg or -e ".[bench]")')
    bench = load_script(BENCH, "bench_free_running")
    truth = bench.make_truth(bench.MMG)
    bench.write_logs(truth, truth.zigzags, truth.zigzag_lengths, tmp_path / "zigzag", 3)
    candidates = ",".join(name for name in EFFECTS if name != "rudder_drag")
    preset = tmp_path / "fitted.yaml"
    arguments = ["--ship", "kvlcc2", "--candidates", candidates, "--preset", str(preset)]
    assert main(["improve", str(tmp_path / "zigzag"), *arguments]) == 0
    assert ShipModel(preset).has("drift_resistance")
    judged = bench.sail_truth(truth, bench.JUDGED_RUNS, bench.TURNING_LENGTHS, 0, bench.EXACT)
    assert bench.figures(judged, ShipModel(preset))[2] == ""


@pytest.mark.slow
def test_a_ladder_whose_final_model_cannot_sail_says_so_and_why_no_candidate_helps(load_script, tmp_path):
    """The same sea trial with the rudder's drag and the drift's resistance left out of the candidates (with the
    drift's resistance among them the ladder adds it, and the model sails: the test above): the candidates
    with which the model would sail are refused (the lagging drift with the hull's cross-flow drag or Norrbin's terms,
    the cross-flow drag alone: their terms within 2 standard errors of their nulls, rule 3; with a current: one that
    absorbs a mismatch): nothing is added, and the ladder's stop says that the final model cannot sail and why each
    candidate with which it would was refused."""
    pytest.importorskip("shipmmg", reason='shipmmg is not installed (pip install shipmmg or -e ".[bench]")')
    bench = load_script(BENCH, "bench_free_running")
    truth = bench.make_truth(bench.MMG)
    bench.write_logs(truth, truth.zigzags, truth.zigzag_lengths, tmp_path / "zigzag", 3)
    candidates = ",".join(name for name in EFFECTS if name not in ("rudder_drag", "drift_resistance"))
    document = tmp_path / "ladder.json"
    arguments = ["--ship", "kvlcc2", "--candidates", candidates, "--json", str(document)]
    assert main(["improve", str(tmp_path / "zigzag"), *arguments]) == 0
    stop = json.loads(document.read_text())["stopped"]
    refused = stop.partition("of the candidates with which it sails, none is supported by the runs: ")[2]
    assert "the final model cannot sail" in stop and "its terms lie within 2 standard errors" in refused, stop


@pytest.mark.slow
def test_a_basins_zigzags_of_the_model_fit_a_ship_that_sails_at_their_propeller_rate(load_script, tmp_path):
    """The MMG KVLCC2 as the 7 m model, thirteen basin zig-zags at the constant propeller rate of its self-propulsion
    point: the preset fitted from ``ship-env scale kvlcc2 --length 7`` with ``improve``'s defaults sails at that rate
    (its service condition), with its fold fits recorded for the figures' errors; the runs reach the hard-over rudder,
    and the MMG forces fitted by inverse dynamics, which sail them held out better than the effects, sail the preset:
    its hard-over turns and 10/10 zig-zag are within every bound of the truth's (the effects' turn was a third too
    wide; docs/results/free_running.md)."""
    pytest.importorskip("shipmmg", reason='shipmmg is not installed (pip install shipmmg or -e ".[bench]")')
    bench = load_script(BENCH, "bench_free_running")
    truth = bench.make_truth(bench.MMG_BASIN, tmp_path)
    verdict = bench.judge(1, tmp_path, truth)
    assert verdict.cannot_turn == "", verdict.cannot_turn
    preset = ShipModel(tmp_path / "fitted.yaml")
    assert preset.length == 7.0
    assert preset.ship.service_conditions["propeller_rate"] == pytest.approx(truth.propeller_rate, rel=1e-9)
    assert len(preset.ship.fitted["jackknife"]["values"]) == len(bench.BASIN_ZIGZAGS)
    assert preset.ship.dynamics is not None and preset.ship.fitted["dynamics"]["sailed_by"] == "mmg_3dof"
    assert all(row[-1] == "PASS" for row in verdict.rows), verdict.rows


@pytest.mark.slow
def test_a_ship_of_the_workbenchs_own_form_on_the_basins_programme_keeps_its_effects(load_script, tmp_path):
    """The kvlcc2 truth (the workbench's own form, values moved) on the basin's thirteen zig-zags to the hard-over
    rudder: the MMG forces are fitted too but sail the runs held out worse, so the preset keeps its effects, and its
    turns and 10/10 zig-zag are within every bound."""
    bench = load_script(BENCH, "bench_free_running")
    verdict = bench.judge(1, tmp_path, bench.make_truth(bench.NATIVE_BASIN, tmp_path))
    assert verdict.cannot_turn == "", verdict.cannot_turn
    preset = ShipModel(tmp_path / "fitted.yaml")
    assert preset.ship.dynamics is None and preset.ship.fitted["dynamics"]["sailed_by"] == "effects"
    assert all(row[-1] == "PASS" for row in verdict.rows), verdict.rows


@pytest.mark.slow
def test_the_mmg_forces_fitted_to_a_basins_zigzags_predict_the_turn_the_ladder_misses(load_script, tmp_path):
    """shipmmg's MMG KVLCC2 as the 7 m model, its thirteen basin zig-zags (seed 3): ``ship-env fit-mmg`` (inverse
    dynamics) predicts the 35 deg turns within every bound (advance and tactical diameter 5 %, where the error
    ladder's preset is a third too wide; the steady rate and speed loss 10 %; the 10/10 overshoot 2 deg;
    docs/results/free_running.md)."""
    pytest.importorskip("shipmmg", reason='shipmmg is not installed (pip install shipmmg or -e ".[bench]")')
    bench = load_script(BENCH, "bench_free_running")
    verdict = bench.judge(3, tmp_path, bench.make_truth(bench.MMG_BASIN, tmp_path), fit=bench.FIT_MMG)
    assert verdict.cannot_turn == "", verdict.cannot_turn
    assert all(row[-1] == "PASS" for row in verdict.rows), verdict.rows
