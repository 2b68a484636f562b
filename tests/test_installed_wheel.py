"""The package works installed, not only from the checkout.

Builds the wheel from a copy of the sources (offline: setuptools' build backend, no build
isolation), installs it into a fresh virtual environment without network (the wheel alone:
its dependencies come from this environment's site-packages through a ``.pth`` file added
after the new environment's own), and runs every command, ``python -m clap_unified`` and the
package data loaders from a temporary folder with no ``PYTHONPATH``: the installed package
must not see the repository. Takes about 30 s.
"""

from __future__ import annotations

import json
import os
import shutil
import site
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.slow


def _sh(*argv, **kwargs):
    proc = subprocess.run([str(a) for a in argv], capture_output=True, text=True, timeout=300,
                          **kwargs)
    assert proc.returncode == 0, (argv, proc.stdout[-2000:], proc.stderr[-2000:])
    return proc


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """The wheel, built from a copy of what a clone holds (the checkout stays untouched)."""
    work = tmp_path_factory.mktemp("build")
    src = work / "src"
    shutil.copytree(ROOT / "clap_unified", src / "clap_unified",
                    ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(ROOT / name, src / name)
    dist = work / "dist"
    _sh(sys.executable, "-c", "import sys; from setuptools import build_meta as b; "
        "print(b.build_wheel(sys.argv[1]))", dist, cwd=src)
    [whl] = dist.glob("clap_unified-*.whl")
    return whl


@pytest.fixture(scope="module")
def venv(wheel, tmp_path_factory) -> Path:
    """A fresh virtual environment holding the wheel; dependencies from this environment."""
    env = tmp_path_factory.mktemp("venv") / "venv"
    _sh(sys.executable, "-m", "venv", "--without-pip", env)
    python = env / "bin" / "python"
    uv = shutil.which("uv", path=str(Path(sys.executable).parent)) or shutil.which("uv")
    if uv:
        _sh(uv, "pip", "install", "--offline", "--no-deps", "--python", python, wheel)
    else:
        _sh(sys.executable, "-m", "pip", "--python", python, "install", "--no-index",
            "--no-deps", wheel)
    [new_site] = _sh(python, "-c", "import site; print(site.getsitepackages()[0])"
                     ).stdout.split()
    # after the new environment's own site-packages: the installed wheel comes first
    deps = [p for p in site.getsitepackages() if Path(p).is_dir()]
    (Path(new_site) / "zz_test_dependencies.pth").write_text("\n".join(deps) + "\n")
    return env


@pytest.fixture(scope="module")
def inputs(tmp_path_factory) -> Path:
    """Small inputs for every command, in a folder outside the repository."""
    import cv2
    from skimage import data

    d = tmp_path_factory.mktemp("inputs")
    rng = np.random.default_rng(0)
    x = rng.uniform(0, 10, 60)
    pts = np.r_[np.c_[x, 0.5 * x + 1 + rng.normal(0, 0.01, 60)], rng.uniform(0, 10, (30, 2))]
    np.savetxt(d / "points.csv", pts, delimiter=",", header="x,y", comments="")
    src = rng.uniform(0, 640, (80, 2))
    dst = src @ np.array([[0.9, 0.1], [-0.1, 0.9]]).T + [30.0, -20.0]
    dst[:20] = rng.uniform(0, 640, (20, 2))
    np.savetxt(d / "matches.csv", np.c_[src, dst], delimiter=",")
    (d / "obs2d.json").write_text(json.dumps([
        {"type": "L", "x": 2.0, "y": 1.5}, {"type": "L", "x": 2.0, "y": -1.5},
        {"type": "T", "x": 3.0, "y": 2.0}, {"type": "goal_post", "x": 3.0, "y": 0.8},
        {"type": "goal_post", "x": 3.0, "y": -0.8}]))
    marks = rng.uniform([-5, -5, 0], [5, 5, 2], (12, 3))
    kinds = ["a", "b", "c", "d"] * 3
    (d / "map.json").write_text(json.dumps(
        [{"type": k, "x": p[0], "y": p[1], "z": p[2]} for k, p in zip(kinds, marks, strict=True)]))
    body = marks[:8] - [0.5, -0.3, 0.0]  # a translated body frame
    (d / "obs3d.json").write_text(json.dumps(
        [{"type": k, "x": p[0], "y": p[1], "z": p[2]} for k, p in zip(kinds, body, strict=False)]))
    img = np.ascontiguousarray(data.astronaut()[::2, ::2, ::-1])  # 256 x 256, BGR
    cv2.imwrite(str(d / "left.png"), img[:, :180])
    cv2.imwrite(str(d / "right.png"), img[:, 60:])
    return d


def _run(venv: Path, cwd: Path, *argv, script: str = "clap-unified"):
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "PYTHONHOME", "CLAP_UNIFIED_DATA", "VIRTUAL_ENV")}
    env.update(OPENBLAS_NUM_THREADS="1", OPEN3D_DISABLE_WEB_VISUALIZER="true",
               OMP_NUM_THREADS="1")
    exe = [venv / "bin" / "python", "-m", "clap_unified"] if script == "-m" else \
        [venv / "bin" / script]
    return subprocess.run([str(a) for a in [*exe, *argv]], capture_output=True, text=True,
                          timeout=300, cwd=cwd, env=env)


def test_the_wheel_ships_the_package_data_and_nothing_of_the_repository(wheel):
    names = zipfile.ZipFile(wheel).namelist()
    for needed in ("clap_unified/maps/fields/adult.json", "clap_unified/maps/fields/kid.json",
                   "clap_unified/imaging/datasets/manifests/homography.json",
                   "clap_unified/imaging/datasets/manifests/vpg.json",
                   "clap_unified/imaging/datasets/manifests/stitching_sets.json",
                   "clap_unified/imaging/datasets/manifests/adelaidermf.json",
                   "clap_unified/imaging/datasets/manifests/adelaidermf_published.json",
                   "clap_unified/__main__.py"):
        assert needed in names
    assert not [n for n in names if n.startswith(("tests/", "data/", "book/", "bench/"))]


def test_every_command_runs_from_the_installed_wheel(venv, inputs, tmp_path):
    from clap_unified import __version__

    where = _run(venv, tmp_path, "-c", "import clap_unified; print(clap_unified.__file__)",
                 script="python")
    assert where.returncode == 0, where.stderr
    path = Path(where.stdout.strip()).resolve()
    assert path.is_relative_to(venv.resolve()) and not path.is_relative_to(ROOT)

    for script in ("clap-unified", "-m"):
        p = _run(venv, tmp_path, "--version", script=script)
        assert p.returncode == 0 and p.stdout.strip() == f"clap-unified {__version__}"

    def ok(*argv, status=0, script="clap-unified"):
        p = _run(venv, tmp_path, *argv, script=script)
        assert p.returncode == status, (argv, p.stderr[-1500:])
        return json.loads(p.stdout)

    assert ok("fit", "line", inputs / "points.csv", "--method", "ransac")["inliers"] >= 60
    assert ok("fit", "line", inputs / "points.csv", script="-m")["success"] is True
    h = ok("fit", "homography", inputs / "matches.csv")
    assert h["inliers"] >= 55 and np.allclose(np.array(h["model"]["H"])[:2, 2], [30, -20],
                                              atol=0.5)
    d = ok("segment", "line", inputs / "points.csv")
    assert [m["support"] for m in d["models"]] == [60] and len(d["labels"]) == 90
    d = ok("segment", "homography", inputs / "matches.csv")
    assert [m["support"] for m in d["models"]] == [60] and d["data"] == 80
    for field in ("adult", "kid"):  # the packaged field maps
        d = ok("localize2d", inputs / "obs2d.json", "--field", field)
        assert d["field"] == field and d["candidates"] > 0
    d = ok("localize2d", inputs / "obs2d.json", "--prior", "-1.2,3.4,0.1", status=1)
    assert "prior" in d["reason"]
    d = ok("localize3d", inputs / "obs3d.json", "--map", inputs / "map.json")
    assert np.allclose(d["model"]["translation"], [0.5, -0.3, 0.0], atol=0.05)
    out = tmp_path / "pano.png"
    d = ok("stitch", inputs / "left.png", inputs / "right.png", "-o", out)
    assert out.is_file() and d["size"][0] > 180
    d = ok("reproduce", "--quick", "--only", "localization2d", "--allow-missing", "--out",
           tmp_path / "rep")
    assert d["ran"] == ["localization2d"] and (tmp_path / "rep" / "claims.json").is_file()
    bad = _run(venv, tmp_path, "localize2d", inputs / "nope.json")
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1
    assert not (tmp_path / "data").exists()


def test_package_data_loaders_from_the_installed_wheel(venv, tmp_path):
    code = ("from clap_unified.localization import load_field; "
            "from clap_unified.imaging.datasets import load_manifest, stitching_set_names; "
            "from clap_unified.imaging.datasets.sources import mirror_dir, CHECKOUT; "
            "print(len(load_field('kid').types), len(stitching_set_names()), "
            "len(load_manifest('homography')['files']) > 0, mirror_dir('vpg'), CHECKOUT)")
    p = _run(venv, tmp_path, "-c", code, script="python")
    assert p.returncode == 0, p.stderr
    assert p.stdout.split() == ["31", "11", "True", "None", "None"]
