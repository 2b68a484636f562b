"""Hypothesis-space fast paths checked against plain, per-model / per-sample references.

Vectorised residuals, batched minimal solvers, the (weighted, normalised) DLT,
batched Kabsch, the 2D landmark association shared between inlier test and
refit, chunked 3D triplet matching and subset sampling. Each test's docstring
names the fast path and its reference; tolerances are float64 with a reason.
"""

from itertools import combinations, permutations
from math import comb
from unittest import mock

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.optimize import linear_sum_assignment

import clap_unified.spaces.landmarks3d as landmarks3d
from clap_unified.geometry import SE2, so3_exp
from clap_unified.localization import LANDMARK_TYPES, load_field
from clap_unified.refine import refit_on_inliers
from clap_unified.spaces import (
    Correspondence3DSpace,
    HomographySpace,
    Landmark3DSpace,
    LineSpace,
    dlt,
    kabsch,
    sample_subsets,
)
from clap_unified.spaces.homography import four_point_homography, normalise_points
from clap_unified.spaces.landmarks2d import Landmark2DSpace
from clap_unified.spaces.rigid3d import min_altitude

REFERENCE = settings(derandomize=True, max_examples=15, deadline=None,
                     suppress_health_check=[HealthCheck.too_slow])
seeds = st.integers(0, 2**32 - 1)
FIELD = load_field("adult")


# ------------------------------------------------------------------ references
def ref_kabsch(P, Q, w=None):
    """Textbook weighted Kabsch for one point set: SVD of the cross-covariance."""
    w = np.ones(len(P)) if w is None else np.asarray(w, float)
    w = w / w.sum()
    cp, cq = w @ P, w @ Q
    H = np.zeros((3, 3))
    for k in range(len(P)):
        H += w[k] * np.outer(P[k] - cp, Q[k] - cq)
    U, _, Vt = np.linalg.svd(H)
    d = 1.0 if np.linalg.det(Vt.T @ U.T) >= 0 else -1.0
    R = Vt.T @ np.diag([1.0, 1.0, d]) @ U.T
    return R, cq - R @ cp


def ref_dlt(src, dst, w=None):
    """Plain DLT: null vector of the (weighted) 2N x 9 system by ``np.linalg.svd``,
    no normalisation, scaled to ``H[2, 2] = 1``."""
    rows = []
    w = np.ones(len(src)) if w is None else w
    for (x, y), (u, v), wk in zip(src, dst, w, strict=True):
        s = np.sqrt(wk)
        rows.append(s * np.array([-x, -y, -1, 0, 0, 0, u * x, u * y, u]))
        rows.append(s * np.array([0, 0, 0, -x, -y, -1, v * x, v * y, v]))
    A = np.array(rows)
    H = np.linalg.svd(A, full_matrices=True)[2][-1].reshape(3, 3)
    return H / H[2, 2]


def ref_hartley(points):
    """Plain Hartley normalisation: centroid to 0, mean distance to sqrt(2)."""
    c = sum(points) / len(points)
    mean_d = sum(np.hypot(*(p - c)) for p in points) / len(points)
    s = np.sqrt(2) / mean_d
    return np.array([[s, 0, -s * c[0]], [0, s, -s * c[1]], [0, 0, 1.0]])


def ref_normalised_dlt(src, dst):
    T1, T2 = ref_hartley(src), ref_hartley(dst)
    a = (np.c_[src, np.ones(len(src))] @ T1.T)[:, :2]
    b = (np.c_[dst, np.ones(len(dst))] @ T2.T)[:, :2]
    H = np.linalg.inv(T2) @ ref_dlt(a, b) @ T1
    return H / H[2, 2]


def apply_h(H, x, y):
    p = H @ np.array([x, y, 1.0])
    return p[:2] / p[2]


def random_homography(rng):
    H = np.eye(3) + 0.15 * rng.standard_normal((3, 3))
    H[2, :2] *= 0.1
    return H / H[2, 2]


def match_poses(fast, ref, tol):
    """Every fast pose has its own reference pose within ``tol`` (optimal assignment)."""
    assert len(fast) == len(ref)
    if len(fast) == 0:
        return
    cost = np.abs(fast[:, None] - ref[None]).max(axis=(-2, -1))
    r, c = linear_sum_assignment(cost)
    assert cost[r, c].max() <= tol, cost[r, c].max()


# ------------------------------------------------------------------ lines
@REFERENCE
@given(seed=seeds)
def test_line_residuals_and_minimal_solver_match_loops(seed):
    """Fast paths: ``LineSpace.residuals`` (one matrix product for all models and
    points) and the batched ``LineSpace.solve_minimal``.
    References: ``|x cos(theta) + y sin(theta) - rho|`` per model and point; per
    sample the line through the two points (normal ``(-dy, dx)/|d|``), degenerate
    when they coincide. Tolerance atol 1e-12 * 10 (coordinates up to 10)."""
    rng = np.random.default_rng(seed)
    space = LineSpace()
    pts = rng.uniform(-10, 10, (12, 2))
    pts[3] = pts[2]  # a coincident pair
    samples = np.array(list(combinations(range(12), 2)))
    models, owner = space.solve_minimal(pts, samples)
    keep = [s for s in range(len(samples)) if not np.array_equal(*pts[samples[s]])]
    np.testing.assert_array_equal(owner, keep)
    for model, s in zip(models, owner, strict=True):
        p, q = pts[samples[s]]
        d = q - p
        n = np.array([-d[1], d[0]]) / np.hypot(*d)
        # same line: both points on it and the same normal up to sign
        normal = np.array([np.cos(model[0]), np.sin(model[0])])
        assert abs(abs(normal @ n) - 1) < 1e-12
        assert 0 <= model[0] < np.pi
        for point in (p, q):
            assert abs(normal @ point - model[1]) < 1e-11
    r = space.residuals(models, pts)
    for h, (th, rho) in enumerate(models):
        for k, (x, y) in enumerate(pts):
            assert abs(r[h, k] - abs(x * np.cos(th) + y * np.sin(th) - rho)) <= 1e-11


# ------------------------------------------------------------------ homographies
@REFERENCE
@given(seed=seeds, kind=st.sampled_from(["transfer", "symmetric"]))
def test_homography_residuals_match_loop(seed, kind):
    """Fast path: ``HomographySpace.residuals`` (``transfer`` and ``symmetric``),
    all models against all matches with batched products and inverses.
    Reference: per model and match ``H @ [x, y, 1]`` divided by its last entry;
    ``symmetric`` = ``sqrt((fwd^2 + bwd^2) / 2)`` with ``np.linalg.inv(H)``.
    Tolerance rtol 1e-9: a few divisions by O(1) denominators, pixel-size values."""
    rng = np.random.default_rng(seed)
    space = HomographySpace(residual=kind)
    H = np.array([random_homography(rng) for _ in range(6)])
    src = rng.uniform(0, 50, (15, 2))
    dst = np.array([apply_h(H[0], *p) for p in src]) + rng.normal(0, 1, (15, 2))
    data = np.c_[src, dst]
    r = space.residuals(H, data)
    for h in range(len(H)):
        Hinv = np.linalg.inv(H[h])
        for k in range(len(data)):
            fwd = np.hypot(*(apply_h(H[h], *src[k]) - dst[k]))
            bwd = np.hypot(*(apply_h(Hinv, *dst[k]) - src[k]))
            ref = fwd if kind == "transfer" else np.sqrt(0.5 * (fwd**2 + bwd**2))
            np.testing.assert_allclose(r[h, k], ref, rtol=1e-9, atol=1e-12)


@REFERENCE
@given(seed=seeds)
def test_homography_minimal_solver_matches_plain_dlt(seed):
    """Fast paths: ``HomographySpace.solve_minimal`` (closed-form 4-point solver in
    the Hartley frame, cofactors, batched) and ``four_point_homography``.
    Reference: per sample the plain DLT, null vector of the 8 x 9 system by
    ``np.linalg.svd``, compared at ``H33 = 1`` (equal up to scale).
    Well-conditioned inputs (coordinates in [-3, 3], no three points nearly
    collinear); tolerance rtol 1e-6, atol 1e-8 (the unnormalised SVD loses a few
    digits to the conditioning of the 8 x 9 system)."""
    rng = np.random.default_rng(seed)
    H0 = random_homography(rng)
    src = rng.uniform(-3, 3, (12, 2))
    dst = np.array([apply_h(H0, *p) for p in src]) + rng.normal(0, 0.05, (12, 2))
    data = np.c_[src, dst]
    samples = sample_subsets(12, 4, 30, rng=rng)
    good = [s for s in range(30)
            if min(min_altitude(np.c_[data[samples[s][list(t)]][:, c:c + 2], np.zeros(3)][None])[0]
                   for t in combinations(range(4), 3) for c in (0, 2)) > 0.2]
    samples = samples[good]
    space = HomographySpace()
    models, owner = space.solve_minimal(data, samples)
    np.testing.assert_array_equal(owner, np.arange(len(samples)))
    closed = four_point_homography(src[samples], dst[samples])
    for k, s in enumerate(samples):
        ref = ref_dlt(src[s], dst[s])
        np.testing.assert_allclose(models[k], ref, rtol=1e-6, atol=1e-8)
        np.testing.assert_allclose(closed[k] / closed[k][2, 2], ref, rtol=1e-6, atol=1e-8)


def test_homography_minimal_solver_rejects_collinear_samples():
    """Fast path: the batched degeneracy test of ``solve_minimal`` (triple
    determinants). Reference: a sample with three exactly collinear points (either
    side) has no homography, plain DLT would give a rank-deficient one."""
    rng = np.random.default_rng(0)
    src = rng.uniform(0, 10, (8, 2))
    dst = src + 1.0
    src[2] = 0.5 * (src[0] + src[1])  # 0, 1, 2 collinear in the source
    dst[6] = 0.25 * dst[4] + 0.75 * dst[5]  # 4, 5, 6 collinear in the destination
    samples = np.array([[0, 1, 2, 3], [4, 5, 6, 7], [0, 1, 3, 4], [3, 4, 5, 7]])
    _, owner = HomographySpace().solve_minimal(np.c_[src, dst], samples)
    np.testing.assert_array_equal(owner, [2, 3])


@REFERENCE
@given(seed=seeds, n=st.integers(4, 20))
def test_dlt_on_exact_data_matches_unnormalised_svd(seed, n):
    """Fast path: ``dlt`` (Hartley-normalised; SVD of A below 8 matches, eigh of the
    9 x 9 normal equations from moments from 8 on), weighted and unweighted.
    Reference: unnormalised plain SVD of the weighted 2N x 9 system on exact
    correspondences, coordinates in [-2, 2] (well conditioned).
    Tolerance rtol 1e-7, atol 1e-9: the normal equations square the condition
    number (~1e3 here), so ~1e-10 relative is expected."""
    rng = np.random.default_rng(seed)
    H0 = random_homography(rng)
    src = rng.uniform(-2, 2, (n, 2))
    dst = np.array([apply_h(H0, *p) for p in src])
    w = rng.uniform(0.2, 3.0, n)
    for weights in (None, w):
        est = dlt(src, dst, weights)
        np.testing.assert_allclose(np.linalg.norm(est), 1.0, rtol=1e-12)
        np.testing.assert_allclose(est / est[2, 2], ref_dlt(src, dst, weights), rtol=1e-7,
                                   atol=1e-9)
        np.testing.assert_allclose(est / est[2, 2], H0, rtol=1e-7, atol=1e-9)


@REFERENCE
@given(seed=seeds, n=st.integers(5, 25))
def test_dlt_on_noisy_data_matches_textbook_normalised_dlt(seed, n):
    """Fast paths: ``dlt`` (moments / eigh or SVD branch, batched over problems) and
    ``normalise_points``.
    References: Hartley normalisation by a plain loop (centroid, mean distance
    sqrt 2), then the SVD of the 2N x 9 system and de-normalisation; integer
    weights against duplicated correspondences (an exact equivalence).
    Noisy pixel data (the minimiser depends on the normalisation, so both must
    normalise the same way). Tolerance rtol 1e-7, atol 1e-9 (normal equations:
    squared condition number, ~1e-10 relative expected)."""
    rng = np.random.default_rng(seed)
    H0 = random_homography(rng)
    H0[:2, 2] *= 100
    src = rng.uniform(0, 640, (n, 2))
    dst = np.array([apply_h(H0, *p) for p in src]) + rng.normal(0, 2.0, (n, 2))
    q, T = normalise_points(src)
    np.testing.assert_allclose(T, ref_hartley(src), rtol=1e-12)
    np.testing.assert_allclose(q, (np.c_[src, np.ones(n)] @ T.T)[:, :2], rtol=0, atol=1e-12)
    est = dlt(src, dst)
    ref = ref_normalised_dlt(src, dst)
    np.testing.assert_allclose(est / est[2, 2], ref, rtol=1e-7, atol=1e-9)
    # batched over problems: the same as one at a time
    src2 = rng.uniform(0, 640, (n, 2))
    dst2 = np.array([apply_h(H0, *p) for p in src2]) + rng.normal(0, 2.0, (n, 2))
    both = dlt(np.stack([src, src2]), np.stack([dst, dst2]))
    np.testing.assert_allclose(both[0] / both[0][2, 2], ref, rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(both[1] / both[1][2, 2], ref_normalised_dlt(src2, dst2),
                               rtol=1e-7, atol=1e-9)
    # integer weights are duplicated rows (the weighted normalisation included)
    w = rng.integers(1, 4, n)
    dup = np.repeat(np.arange(n), w)
    est_w = dlt(src, dst, w.astype(float))
    np.testing.assert_allclose(est_w / est_w[2, 2], ref_normalised_dlt(src[dup], dst[dup]),
                               rtol=1e-7, atol=1e-9)


# ------------------------------------------------------------------ 3D rigid
@REFERENCE
@given(seed=seeds, k=st.integers(3, 8))
def test_batched_kabsch_matches_per_sample_svd(seed, k):
    """Fast path: ``kabsch`` / ``_kabsch`` (einsum cross-covariances, batched SVD and
    reflection fix over a stack of problems).
    Reference: textbook weighted Kabsch per problem with an explicit outer-product
    loop. Tolerance atol 1e-9: SVD of well-separated singular values, O(1) data."""
    rng = np.random.default_rng(seed)
    P = rng.uniform(-3, 3, (10, k, 3))
    R0 = so3_exp(rng.normal(0, 1.5, (10, 3)))
    Q = np.einsum("sij,skj->ski", R0, P) + rng.uniform(-5, 5, (10, 1, 3))
    Q += rng.normal(0, 0.3, Q.shape)
    Q[0] = P[0] * np.array([1.0, 1.0, -1.0])  # a mirror: the reflection fix must act
    w = rng.uniform(0.1, 2.0, (10, k))
    for weights in (None, w):
        R, t = kabsch(P, Q, weights)
        for s in range(10):
            Rr, tr = ref_kabsch(P[s], Q[s], None if weights is None else weights[s])
            np.testing.assert_allclose(R[s], Rr, rtol=0, atol=1e-9)
            np.testing.assert_allclose(t[s], tr, rtol=0, atol=1e-9)
            assert np.linalg.det(R[s]) > 0


def ref_min_altitude(tri):
    """Smallest distance of a vertex to the line through the other two."""
    best = np.inf
    for i in range(3):
        p, a, b = tri[i], tri[(i + 1) % 3], tri[(i + 2) % 3]
        d = b - a
        if np.linalg.norm(d) == 0:
            return 0.0
        best = min(best, np.linalg.norm(np.cross(p - a, d)) / np.linalg.norm(d))
    return best


@REFERENCE
@given(seed=seeds)
def test_correspondence3d_residuals_and_solver_match_loops(seed):
    """Fast paths: ``Correspondence3DSpace.residuals`` (einsum over models and data),
    its batched ``solve_minimal`` (distance check, then collinearity, then batched
    Kabsch) and ``min_altitude``.
    References: ``|R p + t - q|`` per model and datum; per triplet the three
    distance checks in a loop, the smallest vertex-to-opposite-line distance, and
    a per-sample SVD Kabsch. Tolerance atol 1e-9 (SVD of O(1) data)."""
    rng = np.random.default_rng(seed)
    space = Correspondence3DSpace(distance_tolerance=0.2, min_altitude=0.3)
    p = rng.uniform(-3, 3, (10, 3))
    q = p @ so3_exp(rng.normal(0, 1, 3)).T + rng.uniform(-2, 2, 3) + rng.normal(0, 0.05, (10, 3))
    q[7:] = rng.uniform(-3, 3, (3, 3))  # wrong correspondences
    p[5] = 0.5 * (p[0] + p[1]) + 0.01  # nearly collinear with 0 and 1
    data = np.c_[p, q]
    samples = np.array(list(combinations(range(10), 3)))
    models, owner = space.solve_minimal(data, samples)
    ref_owner = []
    for s, tri in enumerate(samples):
        P, Q = p[tri], q[tri]
        if all(abs(np.linalg.norm(P[a] - P[b]) - np.linalg.norm(Q[a] - Q[b])) <= 0.2
               for a, b in combinations(range(3), 2)) and min(
                ref_min_altitude(P), ref_min_altitude(Q)) >= 0.3:
            ref_owner.append(s)
    np.testing.assert_array_equal(owner, ref_owner)
    for model, s in zip(models, owner, strict=True):
        R, t = ref_kabsch(p[samples[s]], q[samples[s]])
        np.testing.assert_allclose(model[:3, :3], R, rtol=0, atol=1e-9)
        np.testing.assert_allclose(model[:3, 3], t, rtol=0, atol=1e-9)
    tri = rng.uniform(-3, 3, (20, 3, 3))
    np.testing.assert_allclose(min_altitude(tri), [ref_min_altitude(x) for x in tri],
                               rtol=1e-10)
    r = space.residuals(models, data)
    for h, T in enumerate(models):
        for k in range(len(data)):
            np.testing.assert_allclose(r[h, k], np.linalg.norm(T[:3, :3] @ p[k] + T[:3, 3] - q[k]),
                                       rtol=1e-12, atol=1e-12)


def landmark3d_scene(rng, m=12):
    positions = rng.uniform(-6, 6, (m, 3))
    types = rng.choice(["a", "b", "c"], m)
    types[:3] = ["a", "b", "c"]
    space = Landmark3DSpace(positions, types, distance_tolerance=0.3, min_altitude=0.2)
    truth = np.eye(4)
    truth[:3, :3] = so3_exp(rng.normal(0, 1, 3))
    truth[:3, 3] = rng.uniform(-2, 2, 3)
    seen = rng.permutation(m)[:8]
    body = (positions[seen] - truth[:3, 3]) @ truth[:3, :3] + rng.normal(0, 0.05, (8, 3))
    ids = space.type_ids[seen].astype(float)
    ids[-2:] = rng.integers(0, 3, 2)  # wrong types
    body[-1] = rng.uniform(-6, 6, 3)  # a false detection
    return space, np.c_[ids, body], truth


@REFERENCE
@given(seed=seeds, mask_limit=st.sampled_from([20_000_000, 144 * 7, 144]))
def test_landmark3d_match_triplets_matches_triple_loop(seed, mask_limit):
    """Fast path: ``Landmark3DSpace.match_triplets`` (pair masks over all map pairs,
    third-landmark masks, chunked by ``MASK_LIMIT``; small limits force chunks of
    7 and of 1 triplets) and the batched Kabsch of ``solve_minimal``.
    Reference: for each observed triplet that is not near-collinear, a plain loop
    over ordered distinct map triplets checking the three types and the three
    pairwise distances within the tolerance, and the map triplet's altitude; then
    a per-sample SVD Kabsch. Same set of matches (exact); poses atol 1e-9."""
    rng = np.random.default_rng(seed)
    space, data, _ = landmark3d_scene(rng)
    samples = sample_subsets(len(data), 3, 25, rng=rng)
    with mock.patch.object(landmarks3d, "MASK_LIMIT", mask_limit):
        owner, marks = space.match_triplets(data, samples)
        models, model_owner = space.solve_minimal(data, samples)
    fast = sorted(zip(owner.tolist(), map(tuple, marks.tolist()), strict=True))
    X, tol, m = space.positions, space.distance_tolerance, len(space.positions)
    ref = []
    for s, (i, j, k) in enumerate(samples):
        P = data[[i, j, k], 1:]
        if ref_min_altitude(P) < space.min_altitude:
            continue
        for a, b, c in permutations(range(m), 3):
            types = [space.type_ids[a], space.type_ids[b], space.type_ids[c]]
            if types != data[[i, j, k], 0].tolist():
                continue
            if (abs(np.linalg.norm(X[a] - X[b]) - np.linalg.norm(P[0] - P[1])) <= tol
                    and abs(np.linalg.norm(X[a] - X[c]) - np.linalg.norm(P[0] - P[2])) <= tol
                    and abs(np.linalg.norm(X[b] - X[c]) - np.linalg.norm(P[1] - P[2])) <= tol
                    and ref_min_altitude(X[[a, b, c]]) >= space.min_altitude):
                ref.append((s, (a, b, c)))
    assert fast == sorted(ref)
    np.testing.assert_array_equal(model_owner, owner)
    for T, s, lm in zip(models, owner, marks, strict=True):
        R, t = ref_kabsch(data[samples[s], 1:], X[lm])
        np.testing.assert_allclose(T[:3, :3], R, rtol=0, atol=1e-9)
        np.testing.assert_allclose(T[:3, 3], t, rtol=0, atol=1e-9)


@pytest.mark.parametrize("observed_y, map_y, min_alt, expected", [
    (0.3, 0.15, 0.2, 0),   # observed triplet fine, map triplet near-collinear: rejected
    (0.3, 0.15, 0.1, 1),   # both above the altitude limit: one match
    (0.15, 0.3, 0.2, 0),   # observed triplet near-collinear: rejected before matching
])
def test_landmark3d_match_triplets_altitude_checks(observed_y, map_y, min_alt, expected):
    """Fast path: the two collinearity checks of ``match_triplets`` (observed
    triplets, then map triplets). Reference: hand-built triangles whose smallest
    altitude (vertex 2 above the side 0-1) straddles ``min_altitude`` while their
    pairwise distances agree within the tolerance (|2.0224 - 2.0056| < 0.3)."""
    positions = np.array([[0.0, 0, 0], [4.0, 0, 0], [2.0, map_y, 0], [9.0, 9, 9]])
    space = Landmark3DSpace(positions, ["a", "b", "c", "c"], distance_tolerance=0.3,
                            min_altitude=min_alt)
    obs = np.c_[[0, 1, 2], [[0.0, 0, 0], [4.0, 0, 0], [2.0, observed_y, 0]]]
    owner, marks = space.match_triplets(obs, np.array([[0, 1, 2]]))
    assert len(owner) == expected
    if expected:
        assert marks.tolist() == [[0, 1, 2]]


@REFERENCE
@given(seed=seeds)
def test_landmark3d_residuals_match_double_loop(seed):
    """Fast path: ``Landmark3DSpace.nearest_landmarks`` / ``residuals`` (per-type
    broadcast over poses, observations and landmarks).
    Reference: for each pose and observation a loop over the map keeping the nearest
    landmark of the same type. Tolerance rtol 1e-12 (one norm); indices exact."""
    rng = np.random.default_rng(seed)
    space, data, truth = landmark3d_scene(rng)
    models = np.stack([truth] + [space.manifold.exp(rng.normal(0, 0.5, 6), truth)
                                 for _ in range(5)])
    dist, index = space.nearest_landmarks(models, data)
    np.testing.assert_array_equal(space.residuals(models, data), dist)
    for h, T in enumerate(models):
        for n, (kind, *p) in enumerate(data):
            world = T[:3, :3] @ np.array(p) + T[:3, 3]
            best, arg = np.inf, -1
            for a, x in enumerate(space.positions):
                if space.type_ids[a] == kind and np.linalg.norm(world - x) < best:
                    best, arg = np.linalg.norm(world - x), a
            np.testing.assert_allclose(dist[h, n], best, rtol=1e-12)
            assert index[h, n] == arg


# ------------------------------------------------------------------ 2D landmarks
def landmark2d_scene(rng, n_true=7, n_false=3, noise=0.03):
    truth = SE2.from_xytheta(rng.uniform(-5, 5), rng.uniform(-3, 3), rng.uniform(-np.pi, np.pi))
    idx = rng.permutation(len(FIELD.positions))[:n_true]
    local = (np.linalg.inv(truth) @ np.c_[FIELD.positions[idx], np.ones(n_true)].T).T[:, :2]
    local += rng.normal(0, noise, local.shape)
    ids = [LANDMARK_TYPES.index(t) for t in FIELD.types[idx]]
    false = np.c_[rng.integers(0, 4, n_false), rng.uniform(-5, 5, (n_false, 2))]
    return np.r_[np.c_[ids, local], false], truth


def ref_pose_from_pair(p, q, m, n):
    """SE(2) taking observed ``p, q`` onto map ``m, n``: rotation from complex numbers
    ``(n - m) / (q - p)``, translation from the midpoints."""
    rot = complex(*(n - m)) / complex(*(q - p))
    rot /= abs(rot)
    t = complex(*((m + n) / 2)) - rot * complex(*((p + q) / 2))
    return SE2.from_xytheta(t.real, t.imag, np.angle(rot))


def ref_world(T, p):
    return T[:2, :2] @ p + T[:2, 2]


def ref_nearest(space, world, kind):
    best, arg = np.inf, -1
    for a, x in enumerate(FIELD.positions):
        if LANDMARK_TYPES.index(FIELD.types[a]) == kind and np.linalg.norm(world - x) < best:
            best, arg = np.linalg.norm(world - x), a
    return best, arg


@REFERENCE
@given(seed=seeds, on_field=st.booleans())
def test_landmark2d_minimal_solver_matches_per_sample_construction(seed, on_field):
    """Fast path: ``Landmark2DSpace.solve_minimal`` (all observation pairs against all
    ordered map pairs in one mask, closed-form poses, on-field bounds).
    Reference: per sample a loop over ordered map pairs with the type and
    separation checks, the pose by complex-number rotation and midpoints, and the
    field-bounds check. Same owners; poses matched one to one within atol 1e-9
    (a few trigonometric operations on O(10) numbers)."""
    rng = np.random.default_rng(seed)
    data, _ = landmark2d_scene(rng)
    space = Landmark2DSpace(FIELD, on_field=on_field)
    samples = np.array(list(combinations(range(len(data)), 2)))[rng.permutation(45)[:20]]
    models, owner = space.solve_minimal(data, samples)
    X = FIELD.positions
    ref_models, ref_owner = [], []
    for s, (i, j) in enumerate(samples):
        p, q = data[i, 1:], data[j, 1:]
        sep = np.linalg.norm(q - p)
        for a in range(len(X)):
            for b in range(len(X)):
                if a == b or sep <= 1e-9:
                    continue
                if (LANDMARK_TYPES.index(FIELD.types[a]) != data[i, 0]
                        or LANDMARK_TYPES.index(FIELD.types[b]) != data[j, 0]):
                    continue
                if abs(sep - np.linalg.norm(X[b] - X[a])) > space.distance_tolerance:
                    continue
                T = ref_pose_from_pair(p, q, X[a], X[b])
                if on_field and (abs(T[0, 2]) > space.bounds[0] or abs(T[1, 2]) > space.bounds[1]):
                    continue
                ref_models.append(T)
                ref_owner.append(s)
    np.testing.assert_array_equal(np.sort(owner), ref_owner)
    ref_models = np.array(ref_models).reshape(-1, 3, 3)
    for s in np.unique(owner):
        match_poses(models[owner == s], ref_models[np.array(ref_owner) == s], 1e-9)


@REFERENCE
@given(seed=seeds)
def test_landmark2d_residuals_and_association_match_double_loop(seed):
    """Fast paths: ``Landmark2DSpace.residuals`` (poses x observations x landmarks
    broadcast) and ``associate`` (nearest same-type landmark within a gate).
    Reference: double loop over observations and map landmarks keeping the nearest
    of the same type. Tolerance rtol 1e-12 (one norm); indices exact."""
    rng = np.random.default_rng(seed)
    data, truth = landmark2d_scene(rng)
    data[0, 0] = LANDMARK_TYPES.index("center_mark")
    space = Landmark2DSpace(FIELD)
    models = np.stack([truth] + [space.manifold.exp(rng.normal(0, 0.4, 3), truth)
                                 for _ in range(5)])
    r = space.residuals(models, data)
    gate = rng.uniform(0.2, 2.0)
    for h, T in enumerate(models):
        marks = space.associate(data, T, gate)
        for n, (kind, *p) in enumerate(data):
            best, arg = ref_nearest(space, ref_world(T, np.array(p)), kind)
            np.testing.assert_allclose(r[h, n], best, rtol=1e-12)
            assert marks[n] == (arg if best <= gate else -1)


@REFERENCE
@given(seed=seeds)
def test_landmark2d_local_hypotheses_match_plain_route(seed):
    """Fast path: ``Landmark2DSpace.local_hypotheses`` (association under the prior,
    cached upper-triangle pairs, batched poses).
    Reference: associate each observation by a double loop, then every pair
    ``i < j`` of associated observations whose separations agree gives one pose by
    the complex-number construction (on-field bounds applied). Same samples in
    order; poses atol 1e-9."""
    rng = np.random.default_rng(seed)
    data, truth = landmark2d_scene(rng, n_true=8, n_false=3, noise=0.05)
    space = Landmark2DSpace(FIELD)
    prior = space.manifold.exp(rng.normal(0, 0.1, 3), truth)
    gate = rng.uniform(0.3, 1.5)
    for _ in range(2):  # the second call reuses the cached pair indices
        hyps = space.local_hypotheses(data, prior, gate)
    marks = []
    for kind, *p in data:
        best, arg = ref_nearest(space, ref_world(prior, np.array(p)), kind)
        marks.append(arg if best <= gate else -1)
    ref_models, ref_samples = [], []
    X = FIELD.positions
    for i, j in combinations(range(len(data)), 2):
        if marks[i] < 0 or marks[j] < 0:
            continue
        p, q = data[i, 1:], data[j, 1:]
        if (abs(np.linalg.norm(q - p) - np.linalg.norm(X[marks[j]] - X[marks[i]]))
                > space.distance_tolerance or np.linalg.norm(q - p) <= 1e-9):
            continue
        T = ref_pose_from_pair(p, q, X[marks[i]], X[marks[j]])
        if abs(T[0, 2]) > space.bounds[0] or abs(T[1, 2]) > space.bounds[1]:
            continue
        ref_models.append(T)
        ref_samples.append((i, j))
    np.testing.assert_array_equal(hyps.samples.reshape(-1, 2), np.array(ref_samples).reshape(-1, 2))
    np.testing.assert_allclose(hyps.models, np.array(ref_models).reshape(-1, 3, 3), rtol=0,
                               atol=1e-9)


def ref_weighted_procrustes_2d(src, dst, w):
    """Weighted 2D rigid fit by SVD with the reflection fix."""
    w = w / w.sum()
    cs, cd = w @ src, w @ dst
    S = sum(wk * np.outer(a - cs, b - cd) for wk, a, b in zip(w, src, dst, strict=True))
    U, _, Vt = np.linalg.svd(S)
    D = np.diag([1.0, np.sign(np.linalg.det(Vt.T @ U.T))])
    R = Vt.T @ D @ U.T
    t = cd - R @ cs
    return SE2.from_xytheta(t[0], t[1], np.arctan2(R[1, 0], R[0, 0]))


class _PlainRoute:
    """A view of a space whose ``refit_steps`` is the plain route: the residual
    test and ``refit(data[inliers], initial=model)``, nothing shared."""

    def __init__(self, space):
        self._space = space
        self.min_samples = space.min_samples

    def residuals(self, models, data):
        return self._space.residuals(models, data)

    def refit(self, data, weights=None, initial=None):
        return self._space.refit(data, weights, initial)

    def refit_steps(self, data, threshold):
        def inliers(model):
            return self.residuals(np.asarray(model)[None], data)[0] < threshold

        def refit(inl, model):
            return self.refit(data[inl], initial=model)

        return inliers, refit


@REFERENCE
@given(seed=seeds, threshold=st.floats(0.1, 1.0))
def test_landmark2d_refit_steps_match_plain_route(seed, threshold):
    """Fast path: ``Landmark2DSpace.refit_steps`` (inlier test and refit sharing one
    association per pose) and ``refine.refit_on_inliers`` using it.
    References: ``space.residuals(model[None], data)[0] < threshold`` and
    ``space.refit(data[inliers], initial=model)``; the refit itself against a
    weighted SVD Procrustes to the nearest same-type landmarks (range-noise
    weights ``1 / (s0 + s1 r^2)^2``). Masks exact; poses atol 1e-10
    (identical arithmetic for the shared route, SVD vs atan2 for Procrustes)."""
    rng = np.random.default_rng(seed)
    data, truth = landmark2d_scene(rng, n_true=8, n_false=3, noise=0.05)
    space = Landmark2DSpace(FIELD)
    inliers, refit = space.refit_steps(data, threshold)
    for _ in range(4):
        model = space.manifold.exp(rng.normal(0, 0.05, 3), truth)
        inl = inliers(model)
        np.testing.assert_array_equal(inl, space.residuals(model[None], data)[0] < threshold)
        fast = refit(inl, model)
        plain = space.refit(data[inl], initial=model)
        if plain is None:
            assert fast is None
            continue
        np.testing.assert_allclose(fast, plain, rtol=0, atol=1e-10)
        sub = data[inl]
        targets = np.array([FIELD.positions[ref_nearest(space, ref_world(model, o[1:]), o[0])[1]]
                            for o in sub])
        s0, s1 = space.range_noise
        w = 1.0 / (s0 + s1 * np.sum(sub[:, 1:] ** 2, axis=1)) ** 2
        np.testing.assert_allclose(plain, ref_weighted_procrustes_2d(sub[:, 1:], targets, w),
                                   rtol=0, atol=1e-10)
    start = space.manifold.exp(rng.normal(0, 0.05, 3), truth)
    m1, i1 = refit_on_inliers(space, start, data, threshold)
    m2, i2 = refit_on_inliers(_PlainRoute(space), start, data, threshold)
    np.testing.assert_array_equal(i1, i2)
    np.testing.assert_allclose(m1, m2, rtol=0, atol=1e-10)


# ------------------------------------------------------------------ sampling
@REFERENCE
@given(seed=seeds, n=st.integers(1, 30), size=st.integers(1, 6), count=st.integers(0, 200))
def test_sample_subsets_rows_are_distinct_indices(seed, n, size, count):
    """Fast path: ``sample_subsets`` (Floyd's algorithm vectorised over rows).
    Reference: the definition: each row holds ``size`` distinct integers of
    ``range(n)`` (checked row by row with a Python set); same seed, same rows."""
    size = min(size, n)
    s = sample_subsets(n, size, count, rng=seed)
    assert s.shape == (count, size)
    for row in s.tolist():
        assert len(set(row)) == size and all(0 <= v < n for v in row)
    np.testing.assert_array_equal(s, sample_subsets(n, size, count, rng=seed))


def test_sample_subsets_uniform_over_subsets():
    """Fast path: ``sample_subsets``. Reference: uniform distribution over the
    C(6, 3) = 20 subsets (and each index in 3/6 of the rows); Pearson chi-square
    on 40,000 seeded draws below the 0.999 quantile of chi2(19) (43.8), index
    frequencies within 1 %."""
    n, size, count = 6, 3, 40_000
    s = sample_subsets(n, size, count, rng=12345)
    keys = {c: i for i, c in enumerate(combinations(range(n), size))}
    observed = np.bincount([keys[tuple(sorted(r))] for r in s.tolist()], minlength=comb(n, size))
    expected = count / comb(n, size)
    chi2 = float(((observed - expected) ** 2 / expected).sum())
    assert chi2 < 43.8, observed
    freq = np.bincount(s.ravel(), minlength=n) / count
    np.testing.assert_allclose(freq, size / n, atol=0.01)
