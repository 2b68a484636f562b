"""Progress bars of a reproduction: one overall, one per running experiment (tqdm)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["configure", "progress"]


@dataclass
class _Bar:
    position: int = 0
    enabled: bool = False  # an experiment run outside the runner (a notebook) draws no bar


#: Set by the runner in each worker: the bar line of the running experiment.
_BAR = _Bar()


def configure(position: int, enabled: bool) -> None:
    """Where the running experiment draws its bar (line ``position``), or no bar at all."""
    _BAR.position, _BAR.enabled = position, enabled


def progress(iterable, desc: str, total: int | None = None):
    """``tqdm`` over ``iterable`` for the running experiment (silent when not a terminal).

    Parameters
    ----------
    iterable : iterable or None
        None gives a bar to update by hand (``with progress(None, ..., total=n) as bar``).
    desc : str
        Label, the experiment's name.
    total : int, optional
    """
    from tqdm.auto import tqdm

    return tqdm(iterable, desc=desc, total=total, position=_BAR.position, leave=False,
                disable=None if _BAR.enabled else True, dynamic_ncols=True)
