"""The paper's claims, each with the experiment that tests it and a stated verdict rule.

A verdict is one of :data:`VERDICTS`. The rules compare rates and medians
with a stated margin (:data:`MARGIN`), never single draws, so that a verdict
does not flip with the last bits of a float. A claim whose data set is missing
is ``"data unavailable"``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

__all__ = ["CLAIMS", "MARGIN", "VERDICTS", "Claim", "chapter_claims", "evaluate_claims"]

VERDICTS = ("reproduced", "partly reproduced", "not reproduced", "data unavailable")

#: Two success rates differ only when they differ by more than this.
MARGIN = 0.05
#: Two medians are "similar" when their ratio lies within [1 / SIMILAR, SIMILAR].
SIMILAR = 1.25


@dataclass(frozen=True)
class Claim:
    """One claim of the paper.

    Attributes
    ----------
    key : str
    words : str
        The paper's words.
    section : str
    experiments : tuple of str
        Experiments whose outputs the rule reads.
    rule : str
        The verdict rule, for people.
    judge : callable
        ``judge(outputs: dict) -> (verdict, measured: str, numbers: dict)``.
    chapter : str
        The book chapter that shows it.
    """

    key: str
    words: str
    section: str
    experiments: tuple
    rule: str
    judge: Callable
    chapter: str


def _v(x) -> float:
    """A stored median: None (more than half of the runs failed) counts as infinite."""
    return float("inf") if x is None else float(x)


def _rate_table(numbers, methods, keys, prefix=""):
    return {f"{prefix}{m}@{k}": numbers[f"{prefix}{m}@{k}"] for m in methods for k in keys}


def _combine(verdicts) -> str:
    """Reproduced in every setting; not reproduced when it fails in one and holds in none."""
    if all(v == "reproduced" for v in verdicts):
        return "reproduced"
    if "not reproduced" in verdicts and "reproduced" not in verdicts:
        return "not reproduced"
    return "partly reproduced"


_SETTINGS_3D = (("typed", "typed detections"),
                ("correspondences", "putative correspondences"))


def _high_ratios(numbers, prefix):
    return sorted({k.split("@")[1] for k in numbers
                   if k.startswith(prefix) and float(k.split("@")[1]) > 0.5})


def _judge_3d(outputs):
    n = outputs["localization3d"]["numbers"]
    verdicts, parts, table = [], [], {}
    for setting, label in _SETTINGS_3D:
        p = f"{setting}:"
        high = _high_ratios(n, p)
        clap = [n[f"{p}clap@{o}"]["ok"] for o in high]
        ransac = [n[f"{p}ransac@{o}"]["ok"] for o in high]
        better = [c - r > MARGIN for c, r in zip(clap, ransac, strict=True)]
        robust = all(c >= 0.8 for c in clap)
        no_worse = all(c >= r - MARGIN for c, r in zip(clap, ransac, strict=True))
        if all(better) and robust:
            verdicts.append("reproduced")
        elif any(better) or (robust and no_worse):
            verdicts.append("partly reproduced")
        else:
            verdicts.append("not reproduced")
        parts.append(f"{label}: " + ", ".join(
            f"{float(o):.0%} false CLAP {c:.2f} / RANSAC {r:.2f}"
            for o, c, r in zip(high, clap, ransac, strict=True)))
        table.update(_rate_table(n, ("clap", "ransac"), high, p))
    return _combine(verdicts), ("share of frames within 5 cm and 1 deg; " + "; ".join(parts)
                                ), table


def _judge_3d_spurious(outputs):
    n = outputs["localization3d"]["numbers"]
    verdicts, parts, table = [], [], {}
    for setting, label in _SETTINGS_3D:
        p = f"{setting}:"
        high = _high_ratios(n, p)
        c = max(n[f"{p}clap@{o}"]["gross"] for o in high)
        r = max(n[f"{p}ransac@{o}"]["gross"] for o in high)
        verdicts.append("reproduced" if r > c + MARGIN else
                        "partly reproduced" if r > c else "not reproduced")
        parts.append(f"{label}: CLAP {c:.2f}, RANSAC {r:.2f}")
        table.update({f"{p}clap_gross_max": c, f"{p}ransac_gross_max": r})
    return _combine(verdicts), ("largest share of spurious poses (beyond 0.5 m or 5 deg) "
                                "above 50 % false detections; " + "; ".join(parts)), table


def _closer(paired, a="CLAP", b="RANSAC"):
    ma, mb = _v(paired[f"median_{a}"]), _v(paired[f"median_{b}"])
    ratio = ma / mb if 0 < mb < float("inf") else (1.0 if ma == mb else float("inf"))
    return ratio, paired[f"{a}_closer"]


def _judge_closer(outputs):
    parts, verdicts, numbers = [], [], {}
    primary = (("homography_vpg", "VPG S01-S12") if "homography_vpg" in outputs else
               ("homography_synthetic", "synthetic VPG-layout (substitute)"))
    for name, label in (primary, ("homography_homogr", "homogr")):
        if name not in outputs:
            continue
        ratio, share = _closer(outputs[name]["numbers"]["paired"])
        numbers[name] = {"median_ratio_clap_over_ransac": ratio, "share_clap_closer": share}
        if ratio < 1 / 1.1 and share > 0.5:
            verdicts.append("closer")
        elif ratio > 1.1 and share < 0.5:
            verdicts.append("farther")
        else:
            verdicts.append("similar")
        parts.append(f"{label}: median Lie distance CLAP / RANSAC = {ratio:.2f}, "
                     f"CLAP closer on {share:.0%} of pairs")
    if not verdicts:
        return "data unavailable", "", numbers
    if all(v == "closer" for v in verdicts):
        verdict = "reproduced"
    elif "closer" in verdicts or all(v != "farther" for v in verdicts):
        verdict = "partly reproduced"
    else:
        verdict = "not reproduced"
    return verdict, "; ".join(parts), numbers


def _judge_real(outputs):
    n = outputs["stitching_real"]["numbers"]
    c, r = _v(n["median_sre"]["CLAP"]), _v(n["median_sre"]["RANSAC"])
    qc, qr = n["median_inlier_ratio"]["CLAP"], n["median_inlier_ratio"]["RANSAC"]
    ratio = c / r if 0 < r < float("inf") else float("inf")
    similar = 1 / SIMILAR <= ratio <= SIMILAR and abs(qc - qr) <= MARGIN
    verdict = "reproduced" if similar else "not reproduced"
    return verdict, (f"{n['pairs']} real pairs: median RMS SRE CLAP {c:.2f} px, RANSAC "
                     f"{r:.2f} px (ratio {ratio:.2f}); median inlier ratio CLAP {qc:.2f}, "
                     f"RANSAC {qr:.2f}"), {"sre_ratio": ratio, "inlier_ratio_clap": qc,
                                          "inlier_ratio_ransac": qr}


def _judge_evd(outputs):
    n = outputs["homography_evd"]["numbers"]
    rc, rr = _v(n["median_recall"]["CLAP"]), _v(n["median_recall"]["RANSAC"])
    lc, lr = _v(n["median_lie"]["CLAP"]), _v(n["median_lie"]["RANSAC"])
    if rc > rr + MARGIN and lc < lr:
        verdict = "reproduced"
    elif rc > rr + MARGIN or lc < lr:
        verdict = "partly reproduced"
    else:
        verdict = "not reproduced"
    return verdict, (f"EVD (15 pairs, 2-51 % inliers): median labelled inliers kept CLAP "
                     f"{rc:.2f}, RANSAC {rr:.2f}; median Lie distance CLAP {lc:.1f}, RANSAC "
                     f"{lr:.1f}"), {"recall_clap": rc, "recall_ransac": rr, "lie_clap": lc,
                                    "lie_ransac": lr}


def _judge_2d(outputs):
    n = outputs["localization2d"]["numbers"]
    rates = sorted({k.split("@")[1] for k in n if "@" in k})
    high = [r for r in rates if float(r) >= 0.4]
    robust = all(n[f"clap@{r}"]["ok"] >= n["clap@" + rates[0]]["ok"] - MARGIN for r in high)
    no_worse = all(n[f"clap@{r}"]["ok"] >= n[f"ransac@{r}"]["ok"] - MARGIN for r in high)
    if robust and no_worse:
        verdict = "reproduced"
    elif robust or no_worse:
        verdict = "partly reproduced"
    else:
        verdict = "not reproduced"
    measured = "; ".join(f"{float(r):.0%} false: CLAP {n[f'clap@{r}']['ok']:.2f}, RANSAC "
                         f"{n[f'ransac@{r}']['ok']:.2f}, Hough {n[f'hough@{r}']['ok']:.2f}"
                         for r in rates)
    return verdict, "share of frames within 10 cm and 2 deg: " + measured, \
        _rate_table(n, ("clap", "ransac", "hough"), rates)


def _judge_symmetry(outputs):
    s = outputs["localization2d"]["numbers"]["symmetry"]
    share = s["pose_and_mirror_tied"]
    verdict = ("reproduced" if share >= 0.8 else
               "partly reproduced" if share >= 0.5 else "not reproduced")
    return verdict, (f"{share:.0%} of {s['frames']} frames without false detections: the two "
                     f"best clusters are the pose and its 180 deg mirror, with equal support"), s


CLAIMS = [
    Claim("3d_outliers",
          "CLAP significantly outperforms RANSAC, maintaining robustness even when more than "
          "50% of the landmark correspondences are corrupted by outliers.",
          "Experiments and Results, 3D Localization Results (error CDF)",
          ("localization3d",),
          f"in each setting (typed detections, putative correspondences): reproduced when at "
          f"every false-detection ratio above 50 % CLAP's share of correct frames exceeds "
          f"RANSAC's by more than {MARGIN} and is at least 0.8; partly: at some ratio, or CLAP "
          f"robust and no worse; the claim is reproduced when it is in every setting, not "
          f"reproduced when it is not in one setting and reproduced in none, else partly",
          _judge_3d, "04_localization_3d"),
    Claim("3d_spurious",
          "CLAP consistently identifies the correct cluster of poses, whereas RANSAC "
          "occasionally converges to spurious solutions when the correct inlier set is "
          "overwhelmed.",
          "Experiments and Results, 3D Localization Results",
          ("localization3d",),
          f"in each setting: reproduced when RANSAC's largest share of spurious poses above "
          f"50 % outliers exceeds CLAP's by more than {MARGIN}; partly: exceeds it; combined "
          f"over the settings as for the claim above",
          _judge_3d_spurious, "04_localization_3d"),
    Claim("vpg_lie",
          "On S01-S12 ... lower values indicate homographies closer to the reference "
          "homography (CLAP's Lie distance to the ground truth is lower than RANSAC's).",
          "Experiments and Results, Image Stitching Results (Lie-distance histograms, "
          "per-scene bars)",
          ("homography_vpg", "homography_synthetic", "homography_homogr"),
          "on VPG S01-S12 when it is here, else on the synthetic substitute, and on homogr; "
          "per data set, CLAP closer when the median Lie-distance ratio CLAP / RANSAC is below "
          "1/1.1 and CLAP is closer on more than half of the pairs, farther when above 1.1 and "
          "on less than half; reproduced: closer on every data set; partly: closer on one or "
          "never farther; else not reproduced",
          _judge_closer, "05_image_stitching"),
    Claim("vpg_real_sre",
          "For the real-world subset (S13-S36) ... The two methods show similar accuracy "
          "(SRE CDF, inlier ratio).",
          "Experiments and Results, Image Stitching Results (SRE CDF)",
          ("stitching_real",),
          f"reproduced: median RMS SRE ratio CLAP / RANSAC within [1/{SIMILAR}, {SIMILAR}] "
          f"and median inlier ratios within {MARGIN}; else not reproduced",
          _judge_real, "05_image_stitching"),
    Claim("stitching_outliers",
          "Clustering-based consistency checks improve robustness compared to conventional "
          "outlier rejection methods [in image stitching].",
          "Introduction, contributions; Experiments and Results (high outlier ratios)",
          ("homography_evd",),
          f"on EVD, reproduced: CLAP keeps more labelled inliers (median, by more than "
          f"{MARGIN}) and has the lower median Lie distance; partly: one of the two; else "
          f"not reproduced",
          _judge_evd, "05_image_stitching"),
    Claim("2d_outliers",
          "CLAP is particularly recognized for its robustness against outliers, where "
          "clustering is employed to suppress noise and mitigate against erroneous feature "
          "matches.",
          "Abstract (the predecessor's 2D localization)",
          ("localization2d",),
          f"reproduced: at 40 % false detections and more, CLAP's share of correct frames "
          f"stays within {MARGIN} of its share without false detections and is no worse than "
          f"RANSAC's (by {MARGIN}); partly: one of the two; else not reproduced",
          _judge_2d, "03_localization_2d"),
    Claim("2d_symmetry",
          "Clustering to Localize Across n Possibilities: on a symmetric field the "
          "possibilities (the pose and its mirror) appear as separate clusters.",
          "Predecessor paper (title); Generalized CLAP Framework, local vs. global modes",
          ("localization2d",),
          "reproduced: in at least 80 % of frames the two best global clusters are the pose "
          "and its 180 deg mirror with equal support; partly: at least 50 %",
          _judge_symmetry, "03_localization_2d"),
]


def evaluate_claims(outputs: dict, skipped: dict | None = None) -> list[dict]:
    """One dict per claim: the paper's words, section, data, measured numbers and verdict.

    Parameters
    ----------
    outputs : dict
        Experiment name -> output (``run`` result); absent experiments were not run.
    skipped : dict, optional
        Experiment name -> why it was not run (a missing data set).
    """
    skipped = skipped or {}
    out = []
    for c in CLAIMS:
        data = [outputs[e]["data"] for e in c.experiments if e in outputs]
        data += [f"{e} not run: {skipped[e]}" for e in c.experiments if e in skipped]
        entry = {"key": c.key, "claim": c.words, "section": c.section,
                 "experiments": list(c.experiments), "rule": c.rule, "chapter": c.chapter,
                 "data": data}
        if not any(e in outputs for e in c.experiments):
            why = "; ".join(dict.fromkeys(skipped[e] for e in c.experiments if e in skipped))
            why = why or "experiment not run"
            entry.update(verdict="data unavailable", measured=why, numbers={})
        else:
            verdict, measured, numbers = c.judge(outputs)
            entry.update(verdict=verdict, measured=measured, numbers=numbers)
        assert entry["verdict"] in VERDICTS
        out.append(entry)
    return out


def chapter_claims(chapter: str) -> str:
    """Markdown list of the claims a chapter tests, with their rules and experiments.

    The verdicts are on the book's front page and in ``claims.json``; a chapter
    shows this list so that its claims are written once, here.

    Examples
    --------
    >>> print(chapter_claims("03_localization_2d").splitlines()[0][:41])
    * *"CLAP is particularly recognized for i
    """
    items = [f"* *\"{c.words}\"* ({c.section}). Experiment `{', '.join(c.experiments)}`; "
             f"verdict rule: {c.rule}." for c in CLAIMS if c.chapter == chapter]
    if not items:
        raise ValueError(f"chapter: no claim is tested in {chapter!r}")
    return "\n".join(items) + "\n"
