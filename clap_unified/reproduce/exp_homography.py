"""Homography experiments: the paper's VPG results and their substitutes.

* ``homography_synthetic``: Sec. "Image Stitching Results", S01-S12. The
  VPG images cannot be had here, so a synthetic VPG-layout set stands in
  (scikit-image photographs and textures, pure-rotation cameras, exact ground
  truth; :func:`~clap_unified.imaging.datasets.load_synthetic_vpg`). SIFT
  matches are the input; the Lie distance to the ground truth scores them.
* ``homography_homogr``: the homogr benchmark (real planar pairs with a
  ground-truth homography; the label-0 rows are the input), an extra real
  data set with ground truth that the paper did not use.
* ``homography_evd``: EVD, extreme views with 2-51 % inliers, for the
  paper's "robustness at high outlier ratios".
* ``stitching_real``: S13-S36. Eleven real panorama sets with parallax and no
  ground truth stand in; scored by the symmetric reprojection error and the
  inlier ratio of each method on the matches the pipeline computes.

CLAP and RANSAC follow the paper's protocol (400 candidates, 5 rounds of
20 % trimming, re-estimation on the inliers; DLT + RANSAC with 1000 fixed
iterations and a refit); OpenCV's MAGSAC++ is shown as a modern reference.
"""

from __future__ import annotations

import base64
import tempfile

import numpy as np

from .progress import progress
from .registry import experiment, finite_or_none

#: label -> (estimator, uses match quality), the format of
#: :data:`~clap_unified.imaging.evaluation.EVALUATED` with shorter labels.
METHODS = {"CLAP": ("clap_paper", False), "RANSAC": ("ransac", False),
           "MAGSAC++": ("magsac", False)}
COLORS = {"CLAP": "C3", "RANSAC": "C0", "MAGSAC++": "C2", "CLAP ordered": "C1"}
#: Inlier threshold, pixels of symmetric reprojection error.
THRESHOLD = 3.0


def _scored_rows(pair_name, scene, rows) -> list[dict]:
    return [{"pair": pair_name, "scene": scene, "method": r["method"],
             "lie": finite_or_none(r["lie"]), "corner_px": finite_or_none(r["corner"]),
             "inliers": int(r["inliers"]), "recall": finite_or_none(r["recall"]),
             "success": bool(r["success"])} for r in rows]


def _thumbnail(left, right, H, width: int = 360) -> str | None:
    """A small feathered mosaic as base64 PNG, or None when it cannot be made."""
    import cv2

    from ..imaging.stitching import StitchError, stitch

    try:
        pano = stitch(left, right, H, blend="feather")
    except (StitchError, ValueError):
        return None
    scale = width / pano.shape[1]
    small = cv2.resize(pano, (width, max(1, round(pano.shape[0] * scale))),
                       interpolation=cv2.INTER_AREA)
    ok, buf = cv2.imencode(".png", small)
    return base64.b64encode(buf.tobytes()).decode() if ok else None


def _decode(b64: str) -> np.ndarray:
    import cv2

    img = cv2.imdecode(np.frombuffer(base64.b64decode(b64), np.uint8), cv2.IMREAD_COLOR)
    return img[:, :, ::-1]


def _medians(rows, key) -> dict:
    out = {}
    for label in dict.fromkeys(r["method"] for r in rows):
        v = [r[key] if r[key] is not None else np.inf for r in rows if r["method"] == label]
        out[label] = float(np.median(v))
    return out


# ------------------------------------------------------------------ S01-S12
def _lie_over_sets(sets, seed: int, desc: str, size=None, seeds: int = 1):
    """Lie distances of every method on every ground-truth pair of ``sets``, and mosaics.

    With ``seeds > 1`` CLAP and RANSAC also run with ``seeds - 1`` more seeds
    per pair (table ``stability``): the spread of their Lie distances over
    seeds measures how stable each estimate is.
    """
    from ..imaging.evaluation import vpg_pair_matches

    pairs = [pm for s in sets for pm in vpg_pair_matches(s) if pm.truth is not None]
    return _lie_over_pairs(pairs, seed, desc, size=size, seeds=seeds)


def _lie_over_pairs(pairs, seed: int, desc: str, size=None, seeds: int = 1, images=True):
    from ..imaging.estimate import strategy_of
    from ..imaging.evaluation import evaluate_pair
    from ..imaging.features import read_image
    from ..registry import get_strategy

    rows, stability, thumbs = [], [], {}
    # the strategies whose estimate depends on the seed: those drawing hypotheses
    randomized = {k: v for k, v in METHODS.items()
                  if get_strategy(strategy_of(v[0])).uses_hypotheses}
    for k, pm in enumerate(progress(pairs, desc)):
        first = evaluate_pair(pm, size=size, methods=METHODS, seed=seed + k)
        rows += _scored_rows(pm.name, pm.scene, first)
        for j in range(seeds if seeds > 1 else 0):
            again = first if j == 0 else evaluate_pair(
                pm, size=size, methods=randomized, seed=seed + k + 100_003 * j)
            stability += [{"pair": pm.name, "scene": pm.scene, "method": r["method"],
                           "seed_index": j, "lie": finite_or_none(r["lie"])}
                          for r in again if r["method"] in randomized]
        clap_model = next(r["model"] for r in first if r["method"] == "CLAP")
        if images and pm.scene not in thumbs and clap_model is not None:
            thumbs[pm.scene] = _thumbnail(read_image(pm.input.image_a),
                                          read_image(pm.input.image_b), clap_model)
    return rows, stability, thumbs


def _lie_numbers(rows) -> dict:
    return {"median_lie": _medians(rows, "lie")}


def run_homography_synthetic(params: dict, seed: int) -> dict:
    from ..imaging.datasets import load_synthetic_vpg

    with tempfile.TemporaryDirectory() as tmp:
        sets = load_synthetic_vpg(tmp, rng=np.random.default_rng([seed, 0]),
                                  images_per_set=params["images_per_set"])
        rows, stability, thumbs = _lie_over_sets(sets, seed, "homography_synthetic",
                                                 size=(640, 480), seeds=params["seeds"])
    return {"data": "synthetic VPG-layout sets (substitute for VPG S01-S12): scikit-image "
                    "photographs and textures, pure-rotation cameras, exact ground truth, "
                    "SIFT matches as input",
            "tables": {"lie": rows, "stability": stability}, "numbers": _lie_numbers(rows),
            "artifacts": {"mosaics": thumbs}}


def run_homography_vpg(params: dict, seed: int) -> dict:
    from ..imaging.datasets import list_vpg_sets, load_vpg_set, vpg_root

    root = vpg_root(download=False)
    names = [n for n in list_vpg_sets(root) if int(n[1:]) <= 12][: params.get("sets")]
    sets = [load_vpg_set(root / n) for n in names]
    rows, stability, thumbs = _lie_over_sets(sets, seed, "homography_vpg",
                                             seeds=params["seeds"])
    return {"data": "VPG S01-S12: Chen et al. 2020; ground-truth correspondences score, "
                    "SIFT matches are the input",
            "tables": {"lie": rows, "stability": stability}, "numbers": _lie_numbers(rows),
            "artifacts": {"mosaics": thumbs}}


def figures_lie(output: dict, prefix: str) -> dict:
    """Lie-distance histograms (linear, log) and per-scene bars, as the paper's figures."""
    import matplotlib.pyplot as plt

    rows = output["tables"]["lie"]
    labels = list(dict.fromkeys(r["method"] for r in rows))
    source = output["data"].split(":")[0]
    vals = {m: np.array([r["lie"] if r["lie"] is not None else np.nan
                         for r in rows if r["method"] == m]) for m in labels}
    finite = np.concatenate([v[np.isfinite(v)] for v in vals.values()])
    figs = {}
    for scale in ("linear", "log"):
        fig, ax = plt.subplots(layout="constrained", figsize=(6.0, 3.6))
        if scale == "linear":
            hi = max(float(np.percentile(finite, 90)) if len(finite) else 1.0, 1e-3)
            bins = np.linspace(0, hi, 30)
            data = {m: np.clip(v[np.isfinite(v)], 0, hi) for m, v in vals.items()}
            xlabel = "Lie distance to ground truth (clipped at the 90th percentile)"
        else:
            eps = 1e-4
            top = max(float(finite.max()) if len(finite) else 1.0, 1.0) * 1.5
            bins = np.geomspace(eps, top, 40)
            data = {m: v[np.isfinite(v)] + eps for m, v in vals.items()}
            ax.set_xscale("log")
            xlabel = "Lie distance to ground truth + 1e-4 (log scale)"
        for m in labels:
            failed = int(np.sum(~np.isfinite(vals[m])))
            ax.hist(data[m], bins=bins, histtype="step", lw=1.6, color=COLORS.get(m),
                    label=m + (f" ({failed} failed)" if failed else ""))
        ax.set_xlabel(xlabel)
        ax.set_ylabel("pairs")
        ax.legend(fontsize=8)
        ax.set_title(f"Lie distance, {scale} scale ({source})", fontsize=9)
        figs[f"{prefix}_lie_hist_{scale}"] = fig
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    height = min(9.0, 1.2 + 0.3 * len(scenes) * len(labels) ** 0.5)
    fig, ax = plt.subplots(layout="constrained", figsize=(6.5, height))
    h = 0.8 / len(labels)
    for j, m in enumerate(labels):
        mean = [np.mean([r["lie"] if r["lie"] is not None else np.inf
                         for r in rows if r["scene"] == sc and r["method"] == m])
                for sc in scenes]
        ax.barh(np.arange(len(scenes)) + (j - (len(labels) - 1) / 2) * h,
                np.minimum(mean, 1e6), h, color=COLORS.get(m), label=m)
    ax.set_xscale("log")
    ax.set_yticks(np.arange(len(scenes)), scenes, fontsize=7)
    ax.invert_yaxis()
    ax.set_xlabel("mean Lie distance per scene (log scale)")
    ax.legend(fontsize=8)
    ax.set_title(f"Per-scene Lie distance ({source})", fontsize=9)
    figs[f"{prefix}_lie_per_scene"] = fig
    mosaics = output.get("artifacts", {}).get("mosaics", {})
    if mosaics:
        figs[f"{prefix}_mosaics"] = _mosaic_overview(mosaics, f"CLAP mosaics ({source})")
    return figs


def _mosaic_overview(mosaics: dict, title: str):
    import matplotlib.pyplot as plt

    names = sorted(mosaics)
    cols = 4
    rows = int(np.ceil(len(names) / cols))
    fig, axes = plt.subplots(rows, cols, layout="constrained", figsize=(11, 2.4 * rows),
                             squeeze=False)
    for ax in axes.ravel():
        ax.axis("off")
    for ax, name in zip(axes.ravel(), names, strict=False):
        if mosaics[name] is not None:
            ax.imshow(_decode(mosaics[name]))
        ax.set_title(name, fontsize=8)
    fig.suptitle(title, fontsize=10)
    return fig


experiment("homography_synthetic",
           "Image stitching S01-S12 (substitute): Lie distance to the ground truth",
           quick={"images_per_set": 2, "seeds": 3}, full={"images_per_set": 3, "seeds": 5},
           datasets=(), figures=lambda out: figures_lie(out, "synthetic"),
           expected_seconds=(15.0, 20.0))(run_homography_synthetic)


experiment("homography_vpg", "Image stitching S01-S12 on the real VPG data, when it is here",
           quick={"sets": 4, "seeds": 3}, full={"sets": None, "seeds": 5}, datasets=("vpg",),
           optional=True,
           figures=lambda out: figures_lie(out, "vpg"),
           expected_seconds=(20.0, 60.0))(run_homography_vpg)


# -------------------------------------------------------------- homogr, EVD
def run_homography_homogr(params: dict, seed: int) -> dict:
    from ..imaging.datasets import homogr_names, load_homogr

    pairs = [_Named(load_homogr(n, images=False), n) for n in homogr_names()[: params["pairs"]]]
    rows, stability, _ = _lie_over_pairs(pairs, seed, "homography_homogr",
                                         seeds=params["seeds"], images=False)
    return {"data": "homogr: Lebeda, Matas, Chum; 16 real planar pairs, ground-truth "
                    "homography; the label-0 tentative matches are the input",
            "tables": {"lie": rows, "stability": stability}, "numbers": _lie_numbers(rows)}


class _Named:
    """A loader's pair with the ``name`` / ``scene`` the tables use."""

    def __init__(self, pair, name):
        self.input, self.truth, self.name, self.scene = pair.input, pair.truth, name, name


experiment("homography_homogr", "homogr: Lie distance to the ground truth (real planar pairs)",
           quick={"pairs": None, "seeds": 3}, full={"pairs": None, "seeds": 5},
           datasets=("homography",),
           figures=lambda out: figures_lie(out, "homogr"),
           expected_seconds=(2.0, 2.0))(run_homography_homogr)


def run_homography_evd(params: dict, seed: int) -> dict:
    from ..imaging.datasets import evd_names, load_evd
    from ..imaging.evaluation import evaluate_pair

    methods = dict(METHODS, **{"CLAP ordered": ("clap_paper", True)})
    rows = []
    for k, name in enumerate(progress(evd_names(), "homography_evd")):
        pair = load_evd(name, images=False)
        for r in _scored_rows(name, name, evaluate_pair(pair, methods=methods, seed=seed + k)):
            r["inlier_ratio"] = float(np.mean(pair.truth.inliers))
            rows.append(r)
    return {"data": "EVD: extreme view dataset, 15 pairs, 2-51 % labelled inliers; all "
                    "tentative matches and their SIFT ratios are the input",
            "tables": {"lie": rows},
            "numbers": {"median_lie": _medians(rows, "lie"),
                        "median_recall": _medians(rows, "recall")}}


def figures_evd(output: dict) -> dict:
    import matplotlib.pyplot as plt

    rows = output["tables"]["lie"]
    pairs = sorted(dict.fromkeys(r["pair"] for r in rows),
                   key=lambda p: next(r["inlier_ratio"] for r in rows if r["pair"] == p))
    labels = list(dict.fromkeys(r["method"] for r in rows))
    fig, ax = plt.subplots(layout="constrained", figsize=(10, 3.6))
    w = 0.8 / len(labels)
    for j, m in enumerate(labels):
        v = [next((r["recall"] or 0.0) for r in rows if r["pair"] == p and r["method"] == m)
             for p in pairs]
        ax.bar(np.arange(len(pairs)) + (j - (len(labels) - 1) / 2) * w, v, w,
               color=COLORS.get(m), label=m)
    ratio = [next(r["inlier_ratio"] for r in rows if r["pair"] == p) for p in pairs]
    ax.set_xticks(np.arange(len(pairs)), [f"{p}\n{q:.0%}" for p, q in zip(pairs, ratio,
                                                                          strict=True)],
                  fontsize=7)
    ax.set_ylabel("labelled inliers kept")
    ax.legend(fontsize=8, ncol=4)
    ax.set_title("EVD: labelled inliers within 3 px of each estimate (pairs by inlier ratio)",
                 fontsize=9)
    return {"evd_recall": fig}


experiment("homography_evd", "EVD: extreme views, 2-51 % inliers",
           quick={}, full={}, datasets=("homography",), figures=figures_evd,
           expected_seconds=(2.0, 2.0))(run_homography_evd)


# ------------------------------------------------------------------ S13-S36
def run_stitching_real(params: dict, seed: int) -> dict:
    import cv2

    from ..imaging.datasets.stitching_sets import load_stitching_set, stitching_set_names
    from ..imaging.estimate import estimate_homography
    from ..imaging.features import read_image, sift_matches
    from ..imaging.metrics import symmetric_reprojection_error

    def small(img):
        s = params["max_side"] / max(img.shape[:2])
        if s >= 1:
            return img
        return cv2.resize(img, (round(img.shape[1] * s), round(img.shape[0] * s)),
                          interpolation=cv2.INTER_AREA)

    sets = {name: load_stitching_set(name).input for name in stitching_set_names()}
    jobs = [(name, i, j) for name, inp in sets.items() for i, j in
            inp.pairs[: params["pairs_per_set"]]]
    rows, thumbs = [], {}
    for k, (name, i, j) in enumerate(progress(jobs, "stitching_real")):
        a, b = small(read_image(sets[name].images[i])), small(read_image(sets[name].images[j]))
        m, _ = sift_matches(a, b)
        errors = {}
        for label, (method, _) in METHODS.items():
            res = estimate_homography(m, method, rng=seed + k) if len(m) >= 8 else None
            errors[label] = (symmetric_reprojection_error(res.model, m)
                             if res is not None and res.success else None)
            if label == "CLAP" and name not in thumbs and errors[label] is not None:
                thumbs[name] = _thumbnail(a, b, res.model)
        # the matches every successful method takes as inliers: one yardstick for all
        found = [e for e in errors.values() if e is not None]
        common = np.logical_and.reduce([e < THRESHOLD for e in found]) if found else None
        for label, e in errors.items():
            row = {"set": name, "pair": f"{name} {i + 1}-{j + 1}", "method": label,
                   "matches": len(m), "success": e is not None, "sre_px": None,
                   "sre_common_px": None, "common": 0, "inlier_ratio": 0.0}
            if e is not None:
                inl = e < THRESHOLD
                row.update(inlier_ratio=float(inl.mean()), common=int(common.sum()),
                           sre_px=_rms(e[inl]), sre_common_px=_rms(e[common]))
            rows.append(row)
    numbers = {"median_sre_common": _medians(rows, "sre_common_px"),
               "median_inlier_ratio": _medians(rows, "inlier_ratio"),
               "pairs": len(jobs)}
    return {"data": "eleven real panorama sets (substitute for VPG S13-S36): parallax, no "
                    "ground truth (stitching_sets); SIFT matches as input",
            "tables": {"sre": rows}, "numbers": numbers, "artifacts": {"mosaics": thumbs}}


def _rms(e) -> float | None:
    return float(np.sqrt(np.mean(np.square(e)))) if len(e) else None


def figures_stitching_real(output: dict) -> dict:
    import matplotlib.pyplot as plt

    rows = output["tables"]["sre"]
    labels = list(dict.fromkeys(r["method"] for r in rows))
    source = output["data"].split(":")[0]
    fig, (a, b) = plt.subplots(1, 2, layout="constrained", figsize=(10, 3.6))
    for m in labels:
        v = np.sort([r["sre_common_px"] if r["sre_common_px"] is not None else np.inf
                     for r in rows if r["method"] == m])
        a.step(v, np.arange(1, len(v) + 1) / len(v), where="post", color=COLORS.get(m),
               label=m)
        q = np.sort([r["inlier_ratio"] for r in rows if r["method"] == m])
        b.step(q, np.arange(1, len(q) + 1) / len(q), where="post", color=COLORS.get(m),
               label=m)
    a.set_xlabel("RMS symmetric reprojection error [px], on the matches\n"
                 "every method takes as inliers")
    a.set_ylabel("fraction of pairs")
    b.set_xlabel("inlier ratio (3 px)")
    a.legend(fontsize=8)
    a.set_title(f"SRE CDF ({source})", fontsize=9)
    b.set_title(f"Inlier ratio CDF ({source})", fontsize=9)
    figs = {"real_sre_cdf": fig}
    mosaics = output.get("artifacts", {}).get("mosaics", {})
    if mosaics:
        figs["real_mosaics"] = _mosaic_overview(mosaics, f"CLAP mosaics ({source})")
    return figs


experiment("stitching_real", "Image stitching S13-S36 (substitute): SRE and inlier ratio",
           quick={"max_side": 800, "pairs_per_set": 1},
           full={"max_side": 1200, "pairs_per_set": 5}, datasets=("stitching_sets",),
           figures=figures_stitching_real, expected_seconds=(20.0, 25.0))(run_stitching_real)
