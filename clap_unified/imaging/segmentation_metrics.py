"""How well a multi-model fit labels the data: the misclassification error.

Multi-model fitting (several homographies, several moving objects) assigns
every datum to one structure or to the outliers. Its standard score on
AdelaideRMF (:mod:`clap_unified.imaging.datasets.adelaidermf`), as in the
J-Linkage, T-Linkage, RPA, Multi-X and Progressive-X evaluations, is the
**misclassification error**: the share of data whose label disagrees with
the ground truth once the estimated structures are matched one-to-one to the
true ones in the way that agrees best. The structure indices themselves mean
nothing (structure 2 of the estimate may be structure 1 of the truth); the
outliers are a class of their own.

Two label conventions meet here, and :func:`misclassification_error` takes
each in its own:

* ``predicted``: the library's, ``-1`` for an outlier and ``0, 1, ...`` for
  the structures found;
* ``truth``: the data set's, ``0`` for an outlier and ``1, ..., K`` for the
  structures.
"""

from __future__ import annotations

import numpy as np

__all__ = ["contingency_table", "misclassification_error"]


def _labels(value, name: str, outlier: int) -> np.ndarray:
    a = np.asarray(value)
    if a.ndim != 1:
        raise ValueError(f"{name}: expected a 1-D array of labels, got shape {a.shape}")
    if a.dtype.kind == "f":
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{name}: labels must be finite (got NaN or inf)")
        if np.any(a != np.round(a)):
            raise ValueError(f"{name}: labels must be integers")
    elif a.dtype.kind not in "iu":
        raise ValueError(f"{name}: expected integer labels, got dtype {a.dtype}")
    a = a.astype(np.int64)
    if len(a) and a.min() < outlier:
        raise ValueError(f"{name}: labels must be >= {outlier} ({outlier} = outlier), "
                         f"got {a.min()}")
    return a


def contingency_table(predicted, truth) -> np.ndarray:
    """Counts of data per (predicted class, true class); row and column 0 are the outliers.

    Parameters
    ----------
    predicted : array_like of int, shape (N,)
        ``-1`` = outlier, ``0..M-1`` = the structures found.
    truth : array_like of int, shape (N,)
        ``0`` = outlier, ``1..K`` = the true structures.

    Returns
    -------
    ndarray of int, shape (M + 1, K + 1)
        ``table[i, j]``: data with predicted label ``i - 1`` and true label
        ``j``, so ``table[0, 0]`` counts outliers called outliers.

    Examples
    --------
    >>> contingency_table([-1, 0, 0, 1], [0, 1, 1, 2])
    array([[1, 0, 0],
           [0, 2, 0],
           [0, 0, 1]])
    """
    p = _labels(predicted, "predicted", -1)
    t = _labels(truth, "truth", 0)
    if len(p) != len(t):
        raise ValueError(f"predicted: {len(p)} labels for {len(t)} in truth")
    table = np.zeros((p.max(initial=-1) + 2, t.max(initial=0) + 1), dtype=np.int64)
    np.add.at(table, (p + 1, t), 1)
    return table


def misclassification_error(predicted, truth) -> float:
    """Share of data labelled wrongly under the best one-to-one matching of structures.

    The predicted structures are matched to the true ones one-to-one so that
    the most data agree (``scipy.optimize.linear_sum_assignment`` on the
    :func:`contingency_table`); the outliers are matched only to the
    outliers. A datum is misclassified when its predicted label, so mapped,
    differs from its true label: a predicted structure left unmatched (more
    structures found than exist) and a true structure left unmatched (fewer
    found) count every one of their data as misclassified, as does an
    inlier called an outlier or an outlier put in a structure.

    Parameters
    ----------
    predicted : array_like of int, shape (N,)
        The estimate, the library's convention: ``-1`` = outlier,
        ``0, 1, ...`` = structures (the indices need not be contiguous).
    truth : array_like of int, shape (N,)
        The ground truth, AdelaideRMF's convention: ``0`` = outlier,
        ``1..K`` = structures.

    Returns
    -------
    float
        In ``[0, 1]`` (multiply by 100 for the percentages papers report).

    Raises
    ------
    ValueError
        Empty input, different lengths, not 1-D, NaN or non-integer labels,
        a predicted label below -1 or a true label below 0.

    Notes
    -----
    Published evaluations do not all match labels this way. Progressive-X's
    notebooks, for one, permute every true label, the outlier class
    included, over the label values ``0..K`` (letting outliers match a
    structure, which can only lower the error, while a structure found
    under an index above ``K`` never counts as right). Compare numbers
    computed under one protocol only.

    Examples
    --------
    Structure indices are arbitrary: a permuted labelling is perfect.

    >>> truth = [0, 1, 1, 1, 2, 2, 0]
    >>> misclassification_error([-1, 1, 1, 1, 0, 0, -1], truth)
    0.0

    Calling everything an outlier misclassifies every inlier (5 of 7):

    >>> round(misclassification_error([-1] * 7, truth), 4)
    0.7143

    A spurious third structure costs the data it took (1 of 7):

    >>> round(misclassification_error([-1, 0, 0, 2, 1, 1, -1], truth), 4)
    0.1429
    """
    from scipy.optimize import linear_sum_assignment

    table = contingency_table(predicted, truth)
    n = int(table.sum())
    if n == 0:
        raise ValueError("predicted: no labels (empty input)")
    structures = table[1:, 1:]
    correct = int(table[0, 0])
    if structures.size:
        rows, cols = linear_sum_assignment(structures, maximize=True)
        correct += int(structures[rows, cols].sum())
    return 1.0 - correct / n
