"""clap-unified reproduce: same claims and numbers with any number of jobs, caching, bad input."""

from __future__ import annotations

import json
import time
from pathlib import Path

import pytest

from clap_unified.cli import main
from clap_unified.reproduce import CLAIMS, EXPERIMENTS, VERDICTS, reproduce, seed_for
from clap_unified.reproduce.claims import _judge_3d, _judge_real
from clap_unified.reproduce.runner import MissingDataError, write_atomic

#: A reduced set that still runs real experiments (a few seconds each).
REDUCED = ["localization2d", "homography_homogr"]


def _results(folder: Path) -> dict:
    """Every file of a run that must not depend on jobs or schedulers (not timings)."""
    files = [folder / "claims.json", folder / "claims.md", *sorted((folder / "tables").glob("*"))]
    return {p.name: p.read_bytes() for p in files}


@pytest.fixture(scope="module")
def serial_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("serial")
    return out, reproduce(out, quick=True, only=REDUCED, progress=False, log=lambda s: None)


def test_reduced_quick_run_writes_claims_tables_and_figures(serial_run):
    out, res = serial_run
    assert sorted(res.ran) == sorted(REDUCED)
    doc = json.loads((out / "claims.json").read_text())
    assert doc["mode"] == "quick"
    assert [c["key"] for c in doc["claims"]] == [c.key for c in CLAIMS]
    for c in doc["claims"]:
        assert c["verdict"] in VERDICTS
        assert c["claim"] and c["section"] and c["rule"]
    tested = {c["key"]: c for c in doc["claims"]}
    # claims of experiments that ran have measured numbers; the others say why not
    assert tested["2d_symmetry"]["verdict"] != "data unavailable"
    assert "%" in tested["2d_outliers"]["measured"]
    assert tested["3d_outliers"]["verdict"] == "data unavailable"
    assert (out / "tables" / "localization2d_errors.csv").read_text().startswith(
        "false_positive_rate,frame,method,e_t_m,e_r_deg")
    for name in ("localization2d_accuracy", "homogr_lie_hist_log", "homogr_lie_per_scene"):
        assert (out / "figures" / f"{name}.png").stat().st_size > 1000
        assert (out / "figures" / f"{name}.svg").stat().st_size > 1000
    assert "| claim (the paper's words) | verdict |" in (out / "claims.md").read_text()
    assert not list(out.rglob("*.part")), "a temporary file was left behind"


def test_two_jobs_and_reversed_order_give_identical_results(serial_run, tmp_path):
    out, _ = serial_run
    res = reproduce(tmp_path, quick=True, only=REDUCED[::-1], jobs=2, progress=False,
                    log=lambda s: None)
    assert sorted(res.ran) == sorted(REDUCED)
    assert _results(tmp_path) == _results(out)


def test_dask_local_cluster_gives_identical_results(serial_run, tmp_path):
    distributed = pytest.importorskip("distributed")
    out, _ = serial_run
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        reproduce(tmp_path, quick=True, only=REDUCED, scheduler=cluster.scheduler_address,
                  progress=False, log=lambda s: None)
    assert _results(tmp_path) == _results(out)


def test_cache_is_reused_unless_forced_and_a_broken_cache_is_recomputed(serial_run, tmp_path):
    out, _ = serial_run
    only = ["homography_homogr"]
    first = reproduce(tmp_path, quick=True, only=only, progress=False, log=lambda s: None)
    again = reproduce(tmp_path, quick=True, only=only, progress=False, log=lambda s: None)
    assert first.ran == only and again.ran == [] and again.reused == only
    forced = reproduce(tmp_path, quick=True, only=only, force=True, progress=False,
                       log=lambda s: None)
    assert forced.ran == only
    cache = tmp_path / "experiments" / "homography_homogr.json"
    cache.write_text(cache.read_text()[:100])  # an interrupted write of an older version
    broken = reproduce(tmp_path, quick=True, only=only, progress=False, log=lambda s: None)
    assert broken.ran == only
    # a full run does not reuse a quick result
    assert json.loads(cache.read_text())["key"]["mode"] == "quick"


def test_a_code_change_invalidates_the_cache(tmp_path, monkeypatch):
    only = ["homography_homogr"]
    quiet = {"progress": False, "log": lambda s: None}
    reproduce(tmp_path, quick=True, only=only, **quiet)
    monkeypatch.setattr("clap_unified.reproduce.runner.code_fingerprint", lambda: "edited")
    assert reproduce(tmp_path, quick=True, only=only, **quiet).ran == only


def test_seed_comes_from_the_name_only():
    assert seed_for("localization2d") == seed_for("localization2d")
    assert len({seed_for(n) for n in EXPERIMENTS}) == len(EXPERIMENTS)


def test_bad_input_is_refused_quickly(tmp_path):
    quiet = {"progress": False, "log": lambda s: None}
    with pytest.raises(ValueError, match="--jobs"):
        reproduce(tmp_path, jobs=0, **quiet)
    with pytest.raises(ValueError, match="--only"):
        reproduce(tmp_path, only=["nope"], **quiet)
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(OSError, match="--out"):
        reproduce(blocker / "sub", only=REDUCED, **quiet)
    t0 = time.perf_counter()
    with pytest.raises(OSError, match="--scheduler"):
        reproduce(tmp_path / "d", only=REDUCED, scheduler="tcp://127.0.0.1:9", **quiet)
    assert time.perf_counter() - t0 < 30


def test_missing_data_stops_or_marks_claims_unavailable(tmp_path, monkeypatch):
    monkeypatch.setenv("CLAP_UNIFIED_DATA", str(tmp_path / "no_mirror"))
    monkeypatch.setenv("CLAP_UNIFIED_CACHE", str(tmp_path / "no_cache"))
    monkeypatch.setattr("clap_unified.imaging.datasets.sources.TIMEOUT", 2.0)
    quiet = {"progress": False, "log": lambda s: None}
    with pytest.raises(MissingDataError, match="Put the file at"):
        reproduce(tmp_path / "a", quick=True, only=["homography_evd"], **quiet)
    assert not (tmp_path / "a" / "claims.json").exists()
    res = reproduce(tmp_path / "b", quick=True, only=["homography_evd"], allow_missing=True,
                    **quiet)
    verdicts = {c["key"]: c for c in res.claims}
    assert verdicts["stitching_outliers"]["verdict"] == "data unavailable"
    assert "data set homography not available" in verdicts["stitching_outliers"]["measured"]
    assert "no_mirror" in res.skipped["homography_evd"]  # the full message says where
    assert res.ran == []


def test_real_vpg_is_used_when_present_and_optional_otherwise(tmp_path, monkeypatch):
    from clap_unified.imaging.datasets import make_synthetic_vpg

    quiet = {"progress": False, "log": lambda s: None}
    monkeypatch.setenv("CLAP_UNIFIED_VPG", str(tmp_path / "none"))
    absent = reproduce(tmp_path / "a", quick=True, only=["homography_vpg"], **quiet)
    assert "homography_vpg" in absent.skipped  # no error without --allow-missing
    # a folder in the VPG layout (Sxx/NN.jpg, mNN-MM.txt, ...) is read as the real data set
    make_synthetic_vpg(tmp_path / "vpg", scenes=["brick"], images_per_set=2, rng=0)
    monkeypatch.setenv("CLAP_UNIFIED_VPG", str(tmp_path / "vpg"))
    present = reproduce(tmp_path / "b", quick=True, only=["homography_vpg"], **quiet)
    assert present.ran == ["homography_vpg"]
    claim = next(c for c in present.claims if c["key"] == "vpg_lie")
    assert claim["verdict"] != "data unavailable"
    assert claim["measured"].startswith("VPG S01-S12")
    assert (tmp_path / "b" / "figures" / "vpg_lie_hist_log.png").is_file()


def test_write_atomic_leaves_the_old_file_when_interrupted(tmp_path, monkeypatch):
    target = tmp_path / "claims.json"
    write_atomic(target, "old")

    def interrupted(src, dst):
        raise KeyboardInterrupt

    monkeypatch.setattr("clap_unified.reproduce.runner.os.replace", interrupted)
    with pytest.raises(KeyboardInterrupt):
        write_atomic(target, "new")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["claims.json"]


def _numbers_3d(clap_ok, ransac_ok):
    n = {}
    for setting in ("typed", "correspondences"):
        for o in ("0.00", "0.60", "0.80"):
            n[f"{setting}:clap@{o}"] = {"ok": clap_ok, "gross": 0.0, "n": 20, "median_cm": 2.0}
            n[f"{setting}:ransac@{o}"] = {"ok": ransac_ok, "gross": 0.0, "n": 20,
                                          "median_cm": 2.0}
    return {"localization3d": {"numbers": n, "data": "x"}}


@pytest.mark.parametrize(("clap_ok", "ransac_ok", "verdict"), [
    (0.95, 0.60, "reproduced"),
    (0.95, 0.93, "partly reproduced"),   # robust, but within the margin of RANSAC
    (0.50, 0.90, "not reproduced"),
])
def test_3d_rule(clap_ok, ransac_ok, verdict):
    assert _judge_3d(_numbers_3d(clap_ok, ransac_ok))[0] == verdict


@pytest.mark.parametrize(("sre", "verdict"), [(1.1, "reproduced"), (2.0, "not reproduced")])
def test_similar_accuracy_rule(sre, verdict):
    n = {"median_sre": {"CLAP": sre, "RANSAC": 1.0},
         "median_inlier_ratio": {"CLAP": 0.8, "RANSAC": 0.8}, "pairs": 11}
    assert _judge_real({"stitching_real": {"numbers": n}})[0] == verdict


def test_cli_refuses_zero_jobs_and_an_unwritable_out(tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["reproduce", "--jobs", "0"])
    assert exc.value.code == 2
    blocker = tmp_path / "file"
    blocker.write_text("x")
    assert main(["reproduce", "--out", str(blocker / "x"), "--only", "localization2d"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) >= 1 and "--out" in err[-1]
