"""Geometry fast paths checked against plain, obviously-correct reference implementations.

Each test names the fast path and the reference in its docstring. Inputs are
random (hypothesis draws a seed or a few floats), derandomised so CI is
deterministic. Tolerances are for float64 and stated with their reason.
"""

import warnings
from itertools import product
from unittest import mock

import numpy as np
import pytest
import scipy.linalg
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import clap_unified.geometry.base as geometry_base
from clap_unified.geometry import (
    SE2,
    SE3,
    Homography,
    Line2D,
    logm,
    so3_exp,
    so3_left_jacobian,
    so3_left_jacobian_inverse,
    so3_log,
)
from clap_unified.geometry.homography_frame import HomographyInFrame

REFERENCE = settings(derandomize=True, max_examples=20, deadline=None,
                     suppress_health_check=[HealthCheck.too_slow])
seeds = st.integers(0, 2**32 - 1)


# ------------------------------------------------------------------ references
def ref_hat_se2(v):
    rx, ry, th = v
    return np.array([[0.0, -th, rx], [th, 0.0, ry], [0.0, 0.0, 0.0]])


def ref_hat_so3(w):
    x, y, z = w
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def ref_hat_se3(v):
    out = np.zeros((4, 4))
    out[:3, :3] = ref_hat_so3(v[3:])
    out[:3, 3] = v[:3]
    return out


def ref_vee_so3(K):
    return np.array([K[2, 1], K[0, 2], K[1, 0]])


def scipy_logm(A):
    """``scipy.linalg.logm`` without its accuracy warning (its estimate is ~1e-12 here)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return scipy.linalg.logm(A)


def real_logm(A):
    """scipy's principal logarithm of one matrix, real part (inputs have a real log)."""
    L = scipy_logm(A)
    assert np.linalg.norm(np.imag(L)) <= 1e-8 * max(1.0, np.linalg.norm(L))
    return np.real(L)


def rotation_vectors(seed, n, max_angle):
    """Random axes times angles in [0, max_angle], with a few tiny angles (Taylor branch)."""
    rng = np.random.default_rng(seed)
    axis = rng.standard_normal((n, 3))
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    angle = rng.uniform(0.0, max_angle, n)
    angle[:3] = [0.0, 1e-9, 3e-7]  # below and at the series switch (1e-6)
    return axis * angle[:, None]


# ------------------------------------------------------------------ SO(3)
@REFERENCE
@given(seed=seeds)
def test_so3_exp_matches_expm_of_hat(seed):
    """Fast path: ``so3_exp`` (batched Rodrigues, Taylor near 0).
    Reference: ``scipy.linalg.expm`` of the hat matrix, one vector at a time.
    Tolerance atol 1e-13: both are accurate to a few ulps of entries of size <= 1."""
    phi = rotation_vectors(seed, 12, 2 * np.pi)
    fast = so3_exp(phi)
    for k in range(len(phi)):
        np.testing.assert_allclose(fast[k], scipy.linalg.expm(ref_hat_so3(phi[k])),
                                   rtol=0, atol=1e-13)


@REFERENCE
@given(seed=seeds)
def test_so3_log_matches_logm(seed):
    """Fast path: ``so3_log`` (atan2 angle, series near 0, symmetric part near pi).
    Reference: vee of ``scipy.linalg.logm(R)`` for angles up to 3.0 rad; near pi
    (where logm's branch choice is arbitrary) ``so3_exp(so3_log(R)) == R`` and the
    angle. Tolerance 1e-10: logm's inverse scaling and squaring is accurate to
    ~1e-12 on orthogonal matrices; near pi the axis read from the symmetric part
    loses a few digits."""
    phi = rotation_vectors(seed, 10, 3.0)
    R = so3_exp(phi)
    fast = so3_log(R)
    for k in range(len(phi)):
        np.testing.assert_allclose(fast[k], ref_vee_so3(real_logm(R[k])), rtol=0, atol=1e-10)
    rng = np.random.default_rng(seed)
    axis = rng.standard_normal((6, 3))
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    angle = np.pi - rng.uniform(0, 2e-3, 6)  # straddles the near-pi switch at pi - 1e-3
    Rp = np.array([scipy.linalg.expm(ref_hat_so3(a * t)) for a, t in zip(axis, angle, strict=True)])
    back = so3_log(Rp)
    np.testing.assert_allclose(np.linalg.norm(back, axis=1), angle, rtol=0, atol=1e-10)
    np.testing.assert_allclose(so3_exp(back), Rp, rtol=0, atol=1e-10)


@REFERENCE
@given(seed=seeds)
def test_so3_left_jacobian_matches_series_block_expm(seed):
    """Fast path: ``so3_left_jacobian`` and ``so3_left_jacobian_inverse`` (closed forms).
    Reference: ``V = sum_k K^k / (k + 1)!``, the top-right block of
    ``expm([[K, I], [0, 0]])``; its inverse by ``np.linalg.inv``.
    Tolerance atol 1e-12: entries are O(1), the inverse is well conditioned below pi."""
    phi = rotation_vectors(seed, 10, 3.0)
    V = so3_left_jacobian(phi)
    Vinv = so3_left_jacobian_inverse(phi)
    for k in range(len(phi)):
        block = np.zeros((6, 6))
        block[:3, :3] = ref_hat_so3(phi[k])
        block[:3, 3:] = np.eye(3)
        ref = scipy.linalg.expm(block)[:3, 3:]
        np.testing.assert_allclose(V[k], ref, rtol=0, atol=1e-12)
        np.testing.assert_allclose(Vinv[k], np.linalg.inv(ref), rtol=0, atol=1e-11)


# ------------------------------------------------------------------ SE(2), SE(3)
@REFERENCE
@given(seed=seeds)
def test_se2_exp_and_log_match_matrix_exp_log(seed):
    """Fast paths: ``SE2.expmap`` (closed form), ``SE2.log`` (entries of both poses,
    no product formed) and ``SE2.logmap``.
    Reference: ``scipy.linalg.expm`` of the 3 x 3 hat matrix; vee of
    ``scipy.linalg.logm(inv(A) @ B)``. Heading kept below 3.0 rad so the principal
    real logarithm is unique. Tolerance atol 1e-10 (logm accuracy, O(10) entries)."""
    rng = np.random.default_rng(seed)
    g = SE2(angle_weight=rng.uniform(0.3, 3.0))
    v = np.c_[rng.uniform(-5, 5, (8, 2)), rng.uniform(-3.0, 3.0, 8)]
    v[0, 2], v[1, 2] = 0.0, 1e-12
    T = g.expmap(v)
    for k in range(len(v)):
        np.testing.assert_allclose(T[k], scipy.linalg.expm(ref_hat_se2(v[k])), rtol=0, atol=1e-12)
    a = g.expmap(np.c_[rng.uniform(-5, 5, (8, 2)), rng.uniform(-1.4, 1.4, 8)])
    b = g.expmap(np.c_[rng.uniform(-5, 5, (8, 2)), rng.uniform(-1.4, 1.4, 8)])
    fast = g.log(b, a)
    fast_d = g.distance(a, b)
    for k in range(len(a)):
        L = real_logm(np.linalg.inv(a[k]) @ b[k])
        ref = np.array([L[0, 2], L[1, 2], L[1, 0]])
        np.testing.assert_allclose(fast[k], ref, rtol=0, atol=1e-10)
        np.testing.assert_allclose(g.logmap(b[k]), ref_vee_se2(real_logm(b[k])), rtol=0, atol=1e-10)
        ref_d = np.sqrt(ref[0] ** 2 + ref[1] ** 2 + (g.angle_weight * ref[2]) ** 2)
        np.testing.assert_allclose(fast_d[k], ref_d, rtol=1e-10, atol=1e-12)


def ref_vee_se2(L):
    return np.array([L[0, 2], L[1, 2], L[1, 0]])


@REFERENCE
@given(seed=seeds)
def test_se3_exp_and_log_match_matrix_exp_log(seed):
    """Fast paths: ``SE3.expmap`` / ``SE3.logmap`` (Rodrigues with the left Jacobian).
    Reference: ``scipy.linalg.expm`` / ``logm`` of the 4 x 4 hat matrix, rotation
    angle below 3.0 rad. Tolerance atol 1e-10 (logm accuracy, O(10) entries)."""
    rng = np.random.default_rng(seed)
    g = SE3()
    v = np.c_[rng.uniform(-5, 5, (8, 3)), rotation_vectors(seed, 8, 3.0)]
    T = g.expmap(v)
    back = g.logmap(T)
    for k in range(len(v)):
        ref = scipy.linalg.expm(ref_hat_se3(v[k]))
        np.testing.assert_allclose(T[k], ref, rtol=0, atol=1e-11)
        L = real_logm(ref)
        np.testing.assert_allclose(back[k], np.r_[L[:3, 3], ref_vee_so3(L[:3, :3])],
                                   rtol=0, atol=1e-10)


# ------------------------------------------------------------------ logm tiers
def random_matrices(seed, n):
    """3 x 3 test matrices for the logarithm: near identity, graded (pixel-like),
    rotations with shear, Jordan blocks (defective) and pure translations."""
    rng = np.random.default_rng(seed)
    out = []
    for k in range(n):
        kind = k % 5
        if kind == 0:
            A = np.eye(3) + 10.0 ** rng.uniform(-8, -0.5) * rng.standard_normal((3, 3))
        elif kind == 1:  # graded like a pixel homography relative matrix
            D = np.diag([1.0, 1.0, 10.0 ** rng.uniform(-4, -1)])
            A = np.linalg.inv(D) @ (np.eye(3) + 0.3 * rng.standard_normal((3, 3))) @ D
        elif kind == 2:
            th = rng.uniform(-2.5, 2.5)
            A = np.array([[np.cos(th), -np.sin(th), 0], [np.sin(th), np.cos(th), 0], [0, 0, 1]])
            A = A @ (np.eye(3) + 0.2 * np.triu(rng.standard_normal((3, 3))))
        elif kind == 3:
            lam = rng.uniform(0.5, 2.0)
            A = np.array([[lam, rng.uniform(-2, 2), 0.0], [0.0, lam, rng.uniform(-2, 2)],
                          [0.0, 0.0, lam]])
        else:
            A = np.eye(3)
            A[:2, 2] = rng.uniform(-100, 100, 2)
        if np.all(np.real(np.linalg.eigvals(A))[np.abs(np.imag(np.linalg.eigvals(A))) < 1e-9]
                  > 0):
            out.append(A)
    return np.array(out)


@REFERENCE
@given(seed=seeds)
def test_logm_tiers_match_scipy_logm(seed):
    """Fast path: ``geometry.logm`` (closed-form spectral tier for 3 x 3, batched
    eigendecomposition tier, scipy fallback).
    Reference: ``scipy.linalg.logm`` one matrix at a time.
    Tolerance: 1e-8 relative to ``max(1, ||L||)``; the fast tiers pass a matrix on
    when rounding may be amplified beyond 1e5 eps (~2e-11), logm itself is ~1e-12."""
    A = random_matrices(seed, 15)
    fast = logm(A)
    for k in range(len(A)):
        ref = real_logm(A[k])
        scale = max(1.0, np.linalg.norm(ref))
        assert np.linalg.norm(fast[k] - ref) <= 1e-8 * scale, (A[k], fast[k], ref)


@REFERENCE
@given(seed=seeds)
def test_logm_negative_eigenvalues_frobenius_matches_scipy(seed):
    """Fast path: ``geometry.logm`` on matrices with a negative real eigenvalue pair
    (complex principal log). Reference: ``scipy.linalg.logm``; compared by the
    full complex matrix. Tolerance 1e-8 relative (as above)."""
    rng = np.random.default_rng(seed)
    A = []
    for _ in range(6):
        P = np.eye(3) + 0.3 * rng.standard_normal((3, 3))
        A.append(P @ np.diag([-rng.uniform(0.5, 2), -rng.uniform(0.5, 2), rng.uniform(0.5, 2)])
                 @ np.linalg.inv(P))
    A = np.array(A)
    fast = logm(A)
    for k in range(len(A)):
        ref = scipy_logm(A[k])
        scale = max(1.0, np.linalg.norm(ref))
        assert np.linalg.norm(np.abs(fast[k])) == pytest.approx(np.linalg.norm(np.abs(ref)),
                                                                rel=1e-8)
        assert np.linalg.norm(fast[k] - ref) <= 1e-8 * scale


# ------------------------------------------------------------------ pairwise
def loop_pairwise(manifold, a, b):
    """Reference: ``distance`` called on one pair at a time."""
    return np.array([[float(manifold.distance(x, y)) for y in b] for x in a])


def sample_points(name, manifold, n, rng):
    if name.startswith("line"):
        return np.c_[rng.uniform(0, np.pi, n), rng.uniform(-5, 5, n)]
    if name.startswith("H") or name.startswith("frame"):
        H = np.eye(3) + 0.1 * rng.standard_normal((n, 3, 3))
        H[:, :2, 2] *= 100.0  # pixel-like translations
        H[:, 2, :2] *= 1e-3
        H[:n // 4] = H[0] + 1e-4 * rng.standard_normal((n // 4, 3, 3))  # a tight cluster
        return H / H[:, 2:, 2:]
    pts = manifold.random(n, rng=rng, scale=1.0)
    pts[: n // 4] = manifold.exp(0.01 * rng.standard_normal((n // 4, manifold.dim)), pts[0])
    return pts


_T1 = np.array([[1 / 320, 0, -1.0], [0, 1 / 240, -1.0], [0, 0, 1]])
_T2 = np.array([[1 / 300, 0, -0.9], [0, 1 / 260, -1.1], [0, 0, 1]])
MANIFOLDS = {
    "line": Line2D(length_scale=2.0, origin=(1.0, -0.5)),
    "SE2": SE2(angle_weight=2.0),
    "SE3-lie": SE3(angle_weight=1.5),
    "SE3-relative": SE3(angle_weight=1.5, metric="relative"),
    "SE3-point_set": SE3(metric="point_set", reference_points=np.random.default_rng(0).normal(
        size=(5, 3))),
    "H-h33": Homography("h33"),
    "H-det": Homography("det"),
    "frame-lie": HomographyInFrame(_T1, _T2, metric="lie", screen=0.5),
    "frame-lie-inf": HomographyInFrame(_T1, _T2, metric="lie", screen=np.inf),
    "frame-lie_linear": HomographyInFrame(_T1, _T2, metric="lie_linear"),
    "frame-frobenius": HomographyInFrame(_T1, _T2, metric="frobenius", normalization="h33"),
}
#: The Gram-matrix paths (``||a||^2 + ||b||^2 - 2 a.b`` and the first-order screen)
#: cancel for close pairs: the absolute error of a distance is ~sqrt(eps) ~ 1.5e-8
#: times the size of the frame matrices (O(1)), so they get atol 1e-7; every other
#: path evaluates the same formula as ``distance`` and gets rtol 1e-9, atol 1e-10.
GRAM = {"frame-lie": 1e-7, "frame-lie_linear": 1e-7, "frame-frobenius": 1e-7}


@pytest.mark.parametrize("name", list(MANIFOLDS))
@REFERENCE
@given(seed=seeds, n=st.integers(2, 14), m=st.integers(1, 9), block=st.sampled_from([7, 50,
                                                                                     10**6]))
def test_pairwise_distance_matches_distance_loop(name, seed, n, m, block):
    """Fast paths: ``pairwise_distance`` in all its forms: the symmetric broadcast
    (``n <= small_pairwise``), the upper-triangle gather (forced with
    ``small_pairwise = 0``), blocked rows of ``(a, b)`` (forced by a small
    ``PAIRWISE_BLOCK``), SE(3) ``relative`` broadcast, the HomographyInFrame Gram /
    first-order screened paths.
    Reference: ``distance(a[i], b[j])`` for one pair at a time."""
    manifold = MANIFOLDS[name]
    rng = np.random.default_rng(seed)
    a = sample_points(name, manifold, n, rng)
    b = sample_points(name, manifold, m, rng)
    atol = GRAM.get(name, 1e-10)
    rtol = 0 if name in GRAM else 1e-9
    with mock.patch.object(geometry_base, "PAIRWISE_BLOCK", block):
        ref_ab = loop_pairwise(manifold, a, b)
        np.testing.assert_allclose(manifold.pairwise_distance(a, b), ref_ab, rtol=rtol, atol=atol)
        ref_aa = loop_pairwise(manifold, a, a)
        if manifold.is_symmetric:
            # the symmetric paths mirror the upper triangle and zero the diagonal
            ref_aa = np.triu(ref_aa, 1) + np.triu(ref_aa, 1).T
        np.testing.assert_allclose(manifold.pairwise_distance(a), ref_aa, rtol=rtol, atol=atol)
        with mock.patch.object(manifold, "small_pairwise", 0):
            np.testing.assert_allclose(manifold.pairwise_distance(a), ref_aa, rtol=rtol,
                                       atol=atol)


@pytest.mark.parametrize("name", ["SE2", "SE3-relative", "frame-lie"])
def test_pairwise_distance_large_switches_match_distance_on_sampled_pairs(name):
    """Fast paths: the size switches above the broadcast limits (SE(2)
    ``small_pairwise = 512``, SE(3) ``relative`` broadcast up to 400 poses,
    HomographyInFrame screen) with several ``PAIRWISE_BLOCK`` blocks.
    Reference: ``distance`` on 300 sampled pairs (the full loop would be slow).
    Tolerances as in :func:`test_pairwise_distance_matches_distance_loop`."""
    manifold = MANIFOLDS[name]
    rng = np.random.default_rng(1)
    a = sample_points(name, manifold, 600, rng)
    with mock.patch.object(geometry_base, "PAIRWISE_BLOCK", 20_000):
        D = manifold.pairwise_distance(a)
    i, j = rng.integers(0, 600, (2, 300))
    i, j = i[i != j], j[i != j]
    ref = np.array([float(manifold.distance(a[p], a[q])) for p, q in zip(i, j, strict=True)])
    atol = GRAM.get(name, 1e-10)
    np.testing.assert_allclose(D[i, j], ref, rtol=0 if name in GRAM else 1e-9, atol=atol)
    np.testing.assert_array_equal(D, D.T)
    np.testing.assert_array_equal(np.diag(D), 0.0)


@REFERENCE
@given(seed=seeds)
def test_homography_in_frame_distance_matches_plain_formula(seed):
    """Fast path: ``HomographyInFrame.distance`` / ``pairwise_distance`` (frames,
    adjugate inverses, cube-root det normalisation, screen).
    Reference: the docstring formula evaluated plainly per pair: ``Hn = T2 H T1^-1``
    scaled to ``det 1``; first-order ``(||Hn1^-1 Hn2 - I|| + ||Hn2^-1 Hn1 - I||)/2``
    by ``np.linalg.inv``; below the screen ``||scipy.linalg.logm(Hn1^-1 Hn2)||_F``.
    Tolerance atol 1e-7 (Gram cancellation in the pairwise screen, see GRAM)."""
    g = MANIFOLDS["frame-lie"]
    rng = np.random.default_rng(seed)
    H = sample_points("frame", g, 8, rng)

    def frame(h):
        hn = _T2 @ h @ np.linalg.inv(_T1)
        return hn / np.cbrt(np.linalg.det(hn))

    ref = np.zeros((8, 8))
    for p, q in product(range(8), range(8)):
        A, B = frame(H[p]), frame(H[q])
        first = 0.5 * (np.linalg.norm(np.linalg.inv(A) @ B - np.eye(3))
                       + np.linalg.norm(np.linalg.inv(B) @ A - np.eye(3)))
        ref[p, q] = (np.linalg.norm(scipy_logm(np.linalg.inv(A) @ B))
                     if first < g.screen else first)
    np.fill_diagonal(ref, 0.0)
    np.testing.assert_allclose(g.pairwise_distance(H), ref, rtol=0, atol=1e-7)
    np.testing.assert_allclose(g.distance(H[:, None], H[None]), ref, rtol=0, atol=1e-9)


@REFERENCE
@given(seed=seeds)
def test_line_log_matches_plain_angle_reasoning(seed):
    """Fast path: ``Line2D.log`` / ``distance`` (vectorised wrap and flip).
    Reference: for each pair, try both normals of the other line ``(theta, rho)`` and
    ``(theta + pi, -rho)`` and take the one whose angle difference (wrapped by
    ``atan2(sin, cos)``) is at most pi/2; offsets measured from the origin.
    Tolerance atol 1e-12 (a few angle operations on O(10) numbers)."""
    rng = np.random.default_rng(seed)
    g = MANIFOLDS["line"]
    a = np.c_[rng.uniform(-4, 4, 10), rng.uniform(-5, 5, 10)]
    b = np.c_[rng.uniform(-4, 4, 10), rng.uniform(-5, 5, 10)]
    ox, oy = g.origin
    for p, q in zip(a, b, strict=True):
        best = None
        for th, rho in ((q[0], q[1]), (q[0] + np.pi, -q[1])):
            dth = np.arctan2(np.sin(th - p[0]), np.cos(th - p[0]))
            if abs(dth) <= np.pi / 2:
                best = (dth, (rho - np.cos(th) * ox - np.sin(th) * oy)
                        - (p[1] - np.cos(p[0]) * ox - np.sin(p[0]) * oy))
        ref = np.hypot(g.length_scale * best[0], best[1])
        np.testing.assert_allclose(g.log(q, p), best, rtol=0, atol=1e-12)
        np.testing.assert_allclose(g.distance(p, q), ref, rtol=0, atol=1e-12)
