"""Figures of the image-stitching chapter: panorama grids, error histograms, CDFs."""

from __future__ import annotations

import numpy as np

__all__ = ["HOMOGRAPHY_STYLE", "plot_cdf", "plot_log_histogram", "show_image_grid"]

#: Colour and marker of every homography method drawn in the book.
HOMOGRAPHY_STYLE = {
    "CLAP": {"color": "#009E73", "marker": "^"},
    "CLAP ordered": {"color": "#56B4E9", "marker": "v"},
    "CLAP ordered, 1000": {"color": "#0072B2", "marker": "D"},
    "RANSAC (library)": {"color": "#D55E00", "marker": "o"},
    "RANSAC + polish": {"color": "#000000", "marker": "x"},
    "CLAP + polish": {"color": "#777777", "marker": "+"},
    "cv2.RANSAC": {"color": "#E69F00", "marker": "s"},
    "cv2.USAC_MAGSAC": {"color": "#CC79A7", "marker": "P"},
    "USAC RANSAC 1000": {"color": "#999999", "marker": "*"},
    # chapter 5's names for the paper's protocol as written ("clap_paper"), told apart from
    # the library's default CLAP: the same colours as above
    "CLAP (paper)": {"color": "#009E73", "marker": "^"},
    "CLAP (paper) ordered": {"color": "#56B4E9", "marker": "v"},
    "CLAP (paper) ordered, 1000": {"color": "#0072B2", "marker": "D"},
    "CLAP (paper), 1000": {"color": "#0072B2", "marker": "D"},
    "CLAP (paper) + polish": {"color": "#777777", "marker": "+"},
    # the performance chapter's methods: the library's default CLAP is "CLAP" above
    "CLAP + quality": {"color": "#56B4E9", "marker": "v"},
    "CLAP (densest-cluster reading)": {"color": "#777777", "marker": "X"},
    "cv2.USAC_ACCURATE": {"color": "#D55E00", "marker": "d"},
    "PoseLib": {"color": "#0072B2", "marker": "p"},
    "COLMAP": {"color": "#000000", "marker": "*"},
}


def show_image_grid(axes, images, titles) -> None:
    """Draw BGR ``uint8`` images (OpenCV order) on a grid of axes, titles above."""
    axes = np.ravel(axes)
    for ax in axes:
        ax.axis("off")
    for ax, img, title in zip(axes, images, titles, strict=False):
        ax.imshow(img[..., ::-1] if img.ndim == 3 else img, cmap="gray")
        ax.set_title(title)  # the book style's axes.titlesize


def plot_cdf(ax, values, label: str, **style) -> None:
    """Empirical CDF of ``values`` (``inf`` counts as never reached)."""
    v = np.sort(np.asarray(values, dtype=float))
    finite = v[np.isfinite(v)]
    y = np.arange(1, len(finite) + 1) / len(v)
    ax.step(np.r_[finite[:1], finite], np.r_[0.0, y], where="post", label=label, **style)


def plot_log_histogram(ax, groups: dict, *, eps: float = 1e-3, bins: int = 20) -> None:
    """Histograms of positive values on log-spaced bins (``value + eps``), one per group.

    ``inf`` (failed estimates) are put in the last bin.
    """
    allv = np.concatenate([np.asarray(v, float) for v in groups.values()])
    finite = allv[np.isfinite(allv)] + eps
    lo, hi = np.log10(finite.min()), np.log10(finite.max())
    edges = np.logspace(lo, hi + 1e-9, bins + 1)
    for label, v in groups.items():
        v = np.asarray(v, float) + eps
        v = np.where(np.isfinite(v), v, edges[-1] * 0.999)
        ax.hist(v, bins=edges, histtype="step", linewidth=1.6, label=label,
                color=HOMOGRAPHY_STYLE.get(label, {}).get("color"))
    ax.set_xscale("log")
