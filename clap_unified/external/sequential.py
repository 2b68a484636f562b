"""Other libraries' single-model estimators in a remove-inliers loop, as segmenters.

The multi-model baseline a user of OpenCV or PoseLib would write: estimate,
remove the inliers, estimate again
(:func:`~clap_unified.ransac.run_sequential` with the peer as the strategy of
every round). Each is registered under the name of its single-model strategy
(``segment(space, data, "magsac")`` is OpenCV's MAGSAC++ in the loop) and
works in the spaces that strategy works in.
"""

from __future__ import annotations

from ..ransac.sequential import run_sequential
from ..registry import Segmenter, get_strategy, register_segmenter

__all__ = ["SEQUENTIAL_PEERS"]

#: The single-model peers run in a remove-inliers loop.
SEQUENTIAL_PEERS = ("magsac", "cv2_ransac", "poselib", "colmap")


def _segmenter(name):
    def run(space, data, hypotheses=None, *, threshold: float, rng=None,
            n_hypotheses: int = 1000, min_support: int, max_models: int = 20):
        return run_sequential(space, data, None, threshold=threshold, rng=rng,
                              n_hypotheses=n_hypotheses, min_support=min_support,
                              strategy=name, max_models=max_models)

    run.__name__ = run.__qualname__ = f"run_sequential_{name}"
    run.__doc__ = f":func:`~clap_unified.ransac.run_sequential` with ``strategy={name!r}``."
    strategy = get_strategy(name)
    return Segmenter(name, run, uses_hypotheses=False, applies_to=strategy.applies_to,
                     summary=f"{strategy.summary}, in a remove-inliers loop", baseline=True)


for _name in SEQUENTIAL_PEERS:
    register_segmenter(_segmenter(_name))
