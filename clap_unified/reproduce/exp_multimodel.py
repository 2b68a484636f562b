"""Experiment: the n possibilities as answers, several planes on AdelaideRMF.

The paper says correct solutions "form coherent clusters in the solution
space" when "multiple noisy hypotheses arise from ambiguous correspondences,
symmetries, or partial observations"; its CLAP reports one cluster. Here
every cluster that holds a structure is an answer: the 17 AdelaideRMF
homography sequences present (planes in two views; ``label`` scores only),
the misclassification error of each method, the number of planes found by
the method.

Methods, all through :func:`~clap_unified.segment` with the same threshold,
minimum support and finish (each match to its nearest model, each model
refitted on its matches; then the same with spatial coherence, a graph cut
that asks neighbouring matches to share a model: :mod:`clap_unified.coherence`):

* ``clap_paper``: the paper's CLAP read as a multi-model method: uniform
  minimal samples, density clusters of the raw hypotheses (its automatic
  bandwidth), clusters taken by support while each explains new matches;
* ``clap``: the library's multi-model CLAP (local samples, hypotheses refined
  on their inliers, grouped when they end with the same inliers (on planes
  nearly every one stays alone), a label cost that picks the models);
* ``ransac``: sequential RANSAC with the same local samples each round;
* ``multi_ransac``: MultiRANSAC (Zuliani et al., 2005), a set of at most six
  models fused with each batch of the shared hypotheses;
* ``t_linkage``: T-Linkage on the same hypotheses as ``clap``;
* ``magsac``: OpenCV MAGSAC++ in a remove-inliers loop;
* ``randomized_hough``: the accumulator's peaks (in ``bench/bench_adelaidermf.py``
  only, which times every method per sequence: left out of the experiment for
  its time, far behind the others in accuracy).

Each method's best single threshold of the sweep is its number (the protocol
of the published evaluations); Progressive-X's published numbers stand beside.
Where CLAP errs, :func:`~clap_unified.imaging.segment_matches.explain_errors`
splits its error into the floor that the annotated planes themselves leave
after the same finish and the excess, and asks of the excess whether CLAP's
objective prefers its answer to the truth or its search stopped short.
The 19 fundamental-matrix sequences (rigid motions) run the same way, an
extension outside the claim.
"""

from __future__ import annotations

import numpy as np

from ..imaging.segment_matches import (
    evaluate_adelaidermf,
    explain_errors,
    segment_preset,
    summarise,
)
from .claims import deviation
from .registry import experiment

__all__ = ["METHODS", "run_multimodel"]

#: Row label -> (segmenter, options of ``segment_matches``).
METHODS = {
    "clap_paper": ("clap", {"neighbours": 0, "refine_rounds": 0, "bandwidth": "auto",
                            "select": "cover"}),
    "clap": ("clap", {}),
    "ransac": ("ransac", {}),
    "multi_ransac": ("multi_ransac", {}),
    "t_linkage": ("t_linkage", {}),
    "magsac": ("magsac", {}),
    "randomized_hough": ("randomized_hough", {}),
}

#: What each part of the library's CLAP adds: the library's CLAP with one part changed.
ABLATION = {
    "uniform samples": {"neighbours": 0},
    "no hypothesis refinement": {"refine_rounds": 0},
    "density clusters (auto bandwidth)": {"bandwidth": "auto"},
    "cover instead of label cost": {"select": "cover"},
    "no spatial coherence": {"coherence": 0.0},
    "no final refit": {"refine": False},
}


def _evaluate(label, segmenter, options, params, seed, kind="homography"):
    rows = evaluate_adelaidermf(kind, (segmenter,), thresholds=params["thresholds"],
                                seeds=[seed + k for k in range(params["seeds"])],
                                names=params.get("names"), options={segmenter: options})
    for r in rows:
        r["method"] = label
    return rows


def _seed_means(rows, method, threshold) -> list:
    """The mean error (%) over the sequences of each seed, in the order of the seeds: the
    spread over seeds of one method at one threshold (the claims' edge, chapter 7's table)."""
    by = {}
    for r in rows:
        if r["method"] == method and r["threshold"] == threshold:
            by.setdefault(r["seed"], []).append(100 * r["error"])
    return [round(float(np.mean(by[k])), 2) for k in sorted(by)]


def _best(rows):
    """Each method's summary at its best threshold (lowest mean error), with its mean per
    seed (``seed_means``)."""
    table = summarise(rows)
    out = {}
    for method in sorted({m for m, _ in table}):
        key = min((k for k in table if k[0] == method), key=lambda k: table[k]["mean"])
        s = table[key]
        out[method] = {"threshold": key[1], "mean": round(s["mean"], 2),
                       "median": round(s["median"], 2), "models": round(s["models"], 2),
                       "true_models": round(s["true_models"], 2),
                       "seed_means": _seed_means(rows, method, key[1]),
                       "per_sequence": {q: round(v, 2) for q, v in s["per_sequence"].items()}}
    return out


def _diagnose(threshold, params, seed, rows_run):
    """CLAP's error against the annotated planes' own (the oracle), per sequence and seed.

    ``summary``: the oracle's mean error (the floor of the finish) and CLAP's
    mean excess over it, split by cause (``objective``: CLAP's answer has a
    lower label-cost energy than the truth; ``search``: a higher one), in
    points of mean error. CLAP runs again for each sequence and seed; its
    errors must be those of ``rows_run`` (the experiment's own run).
    """
    rows = []
    for k in range(params["seeds"]):
        for r in explain_errors("homography", threshold=threshold, seed=seed + k,
                                names=params.get("names")):
            rows.append({**r, "seed": seed + k, "error": round(100 * r["error"], 2),
                         "oracle_error": round(100 * r["oracle_error"], 2),
                         "energy": round(r["energy"], 1),
                         "oracle_energy": round(r["oracle_energy"], 1)})
    ran = {(r["sequence"], r["seed"]): 100 * r["error"] for r in rows_run
           if r["method"] == "clap" and r["threshold"] == threshold}
    for r in rows:  # the same call, seed and threshold: the same answer, or nothing is explained
        if round(ran[r["sequence"], r["seed"]], 2) != r["error"]:
            raise RuntimeError(f"explain_errors: CLAP on {r['sequence']} (seed {r['seed']}) "
                               f"gave {r['error']} %, the experiment "
                               f"{ran[r['sequence'], r['seed']]:.2f} %")
    n = len(rows)
    excess = {c: round(sum(r["error"] - r["oracle_error"] for r in rows if r["cause"] == c) / n,
                       2) for c in ("objective", "search", "floor")}
    return {"rows": rows, "summary": {
        "threshold": threshold, "error_mean": round(sum(r["error"] for r in rows) / n, 2),
        "oracle_mean": round(sum(r["oracle_error"] for r in rows) / n, 2),
        "excess": excess}}


def _listed(values) -> str:
    """Distinct values in words: ``"4"``, ``"4 and 5"``, ``"unstated"`` for None."""
    words = list(dict.fromkeys("unstated" if v is None else f"{v:g}" for v in values))
    return " and ".join(words) if words else "unstated"


def _published_thresholds(entries: list) -> list:
    """Each published entry's inlier threshold (px) as its protocol states it, or as the
    entry before it of the same method and kind states it when it reads "as above" (the
    same notebook at a later commit); None when neither says.

    Examples
    --------
    >>> _published_thresholds([{"method": "X", "kind": "h", "protocol": "with threshold 4 px"},
    ...                        {"method": "X", "kind": "h", "protocol": "as above but w 2"},
    ...                        {"method": "Y", "kind": "h", "protocol": "no number"}])
    [4.0, 4.0, None]
    """
    import re

    out, last = [], {}
    for p in entries:
        m = re.search(r"\bthreshold (\d+(?:\.\d+)?)", p.get("protocol", ""))
        key = (p.get("method"), p.get("kind"))
        value = (float(m.group(1)) if m else
                 last.get(key) if "as above" in p.get("protocol", "") else None)
        last[key] = value
        out.append(value)
    return out


def run_multimodel(params: dict, seed: int) -> dict:
    """The sweep of every method, the ablation of CLAP, Progressive-X's published numbers."""
    from ..imaging.datasets.adelaidermf import adelaidermf_names, published_results

    rows = []
    for label in params["methods"]:
        segmenter, options = METHODS[label]
        rows += _evaluate(label, segmenter, options, params, seed)
    best = _best(rows)
    ablation_rows = []
    for label, change in ABLATION.items():
        ablation_rows += _evaluate(label, "clap", change, {**params, "thresholds":
                                                          [best["clap"]["threshold"]]}, seed)
    ablation = _best(ablation_rows)
    diagnosis = _diagnose(best["clap"]["threshold"], params, seed, rows)
    fundamental = []
    for label in params.get("fundamental_methods", ()):
        segmenter, options = METHODS[label]
        fundamental += _evaluate(label, segmenter, options,
                                 {**params, "thresholds": params["fundamental_thresholds"],
                                  "names": None}, seed, "fundamental")
    best_f = _best(fundamental) if fundamental else {}
    published = published_results("homography")
    for p, t in zip(published, _published_thresholds(published), strict=True):
        p["threshold"] = t
    published = [p for p in published if p.get("mean") is not None]
    published_f = [p for p in published_results("fundamental") if p.get("mean") is not None]
    seconds = {m: float(np.median([r["seconds"] for r in rows if r["method"] == m]))
               for m in params["methods"]}
    tables = {"multimodel": [{k: v for k, v in r.items() if k != "seconds"} for r in rows],
              "multimodel_ablation": [{k: v for k, v in r.items() if k != "seconds"}
                                      for r in ablation_rows],
              "multimodel_fundamental": [{k: v for k, v in r.items() if k != "seconds"}
                                         for r in fundamental]}
    numbers = {"methods": {m: {k: v for k, v in b.items() if k != "per_sequence"}
                           for m, b in best.items()},
               "published": {f"{p['method']} ({p.get('source', '')[-60:]})":
                             {"mean": p["mean"], "median": p.get("median"),
                              "threshold": p["threshold"], "sequences": p.get("n_sequences")}
                             for p in published},
               "sequences": len(adelaidermf_names("homography") if params.get("names") is None
                                else params["names"]),
               "thresholds": list(params["thresholds"]),
               "seeds": params["seeds"],
               "diagnosis": diagnosis["summary"],
               "fundamental": {
                   "methods": {m: {k: v for k, v in b.items() if k != "per_sequence"}
                               for m, b in best_f.items()},
                   "published": {f"{p['method']} ({p.get('source', '')[-60:]})":
                                 {"mean": p["mean"], "median": p.get("median"),
                                  "sequences": p.get("n_sequences")} for p in published_f},
                   "sequences": len({r["sequence"] for r in fundamental})}}
    variants = {"library_clap": {
        "label": "CLAP (the library's) for several structures (local samples, refined "
                 "hypotheses grouped by "
                 "their inliers, a label cost that picks the models) as CLAP", "kind": "extension",
        "numbers": {**numbers, "methods": {**numbers["methods"],
                                           "clap_paper": numbers["methods"]["clap"]}}}}
    for label, summary in ablation.items():
        variants[f"ablation: {label}"] = {
            "label": f"the library's CLAP with {label}", "kind": "extension",
            "numbers": {**numbers, "methods": {**numbers["methods"], "clap_paper": {
                k: v for k, v in summary.items() if k != "per_sequence"}}}}
    return {
        "data": f"AdelaideRMF: {numbers['sequences']} homography sequences (johnsona and "
                f"johnsonb missing), {params['seeds']} seed{'s' * (params['seeds'] != 1)} per "
                f"sequence; its {numbers['fundamental']['sequences']} fundamental-matrix "
                f"sequences (motions) run too, an extension the rule does not read",
        "protocol": "every method through segment() with the same threshold sweep, minimum "
                    "support (10 matches and 2 %) and finish (nearest model, refit, then "
                    "spatial coherence by a graph cut); each method's best single "
                    "threshold; the paper's CLAP read as clusters of raw hypotheses",
        "deviations": [
            deviation("correct solutions form coherent clusters (one cluster reported)",
                      "every cluster that explains enough matches is a model; the number of "
                      "models is found by the method",
                      "a choice: the paper reports one cluster and never several"),
            deviation("no finish: one cluster is the answer",
                      "every method's models get the same finish: each match to its nearest "
                      "model, each model refitted, then the labels chosen again with spatial "
                      "coherence (neighbouring matches pay for different models)",
                      "a choice: the same for every method (PEARL's and Progressive-X's "
                      "labelling); the ablation measures it"),
            deviation("no multi-structure data", "AdelaideRMF, 17 of its 19 homography "
                      "sequences", "data unavailable: johnsona and johnsonb are in no public "
                      "mirror found"),
            deviation("no comparison with published numbers",
                      "each method measured here at its best single threshold of the sweep ("
                      + ", ".join(f"{t:g}" for t in params["thresholds"]) + " px), chosen on "
                      "the same sequences it is scored on; the published Progressive-X means "
                      "beside them are its authors' runs at one fixed threshold ("
                      + _listed(p["threshold"] for p in published) + " px), on "
                      + _listed(p.get("n_sequences") for p in published) + " sequences, with "
                      "their own error count: an indicative reference, which a threshold "
                      "chosen on the test sequences favours the methods measured here against",
                      "a choice: each method measured here at its best threshold, as the "
                      "field's evaluations report them; Progressive-X's published numbers, "
                      "the only ones checked here, come with their own fixed threshold")],
        "tables": tables,
        "numbers": numbers,
        "artifacts": {"per_sequence": {m: b["per_sequence"] for m, b in best.items()},
                      "per_sequence_fundamental": {m: b["per_sequence"]
                                                   for m, b in best_f.items()},
                      "seconds_fundamental": {
                          m: float(np.median([r["seconds"] for r in fundamental
                                              if r["method"] == m]))
                          for m in params.get("fundamental_methods", ())},
                      "ablation": {m: {k: v for k, v in b.items() if k != "per_sequence"}
                                   for m, b in ablation.items()},
                      "seconds": seconds,
                      "diagnosis": diagnosis["rows"]},
        "variants": variants,
    }


experiment("multimodel_adelaidermf",
           "Several planes: multi-model fitting on AdelaideRMF",
           quick={"methods": ["clap_paper", "clap", "ransac", "multi_ransac", "t_linkage",
                              "magsac"],
                  # quick: each kind's default threshold only (its segmentation preset)
                  "thresholds": [segment_preset("homography").fit["threshold"]], "seeds": 1,
                  "fundamental_methods": ["clap", "magsac"],
                  "fundamental_thresholds": [segment_preset("fundamental").fit["threshold"]]},
           full={"methods": [m for m in METHODS if m != "randomized_hough"],
                 "thresholds": [4.0, 5.0, 7.0, 10.0], "seeds": 5,
                 "fundamental_methods": ["clap", "ransac", "t_linkage", "magsac"],
                 "fundamental_thresholds": [1.0, 2.0, 4.0]},
           datasets=("adelaidermf",), expected_seconds=(20.0, 300.0), version=3)(run_multimodel)
