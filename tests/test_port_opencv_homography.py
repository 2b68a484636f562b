"""OpenCV's homography and fundamental-matrix tests, ported to clap_unified (issue 27).

The situations of ``modules/calib3d/test/test_homography.cpp`` and of the homography
and fundamental-matrix tests of ``modules/calib3d/test/test_usac.cpp`` (opencv/opencv,
4.x), each mapped to :func:`clap_unified.imaging.estimate_homography` and/or
:func:`clap_unified.fit` with RANSAC and CLAP (and the command line where it adds
something). Each test names the upstream test in a comment. The data are drawn as
upstream draws them (the same distributions and sizes), from numpy's generator with
fixed seeds instead of ``cv::theRNG()``; the checks are upstream's checks, with
upstream's tolerances.

Deliberate differences (each test that meets one skips with ``deliberate difference:``):

* ``LMEDS`` and ``RHO``: OpenCV's least-median and PROSAC-RHO estimators have no
  counterpart among clap_unified's strategies (RHO's progressive sampling is
  ``estimate_homography(..., quality=...)``, which needs a quality per match that
  these data do not have); OpenCV's RANSAC and USAC run as peers (``cv2_ransac``,
  ``magsac``, ``usac_accurate``) and are OpenCV's own code, not ported.
* ``Calib3d_Homography.fromImages``: OpenCV's ``cv/optflow/image{1,2}.png`` (opencv_extra)
  are not available here; the library's own image pairs are tested in
  ``tests/test_stitching.py``.
* An inlier is ``residual < threshold`` in clap_unified and ``<=`` in OpenCV; the mask
  checks below compare with ``<`` (a residual exactly at the threshold has measure zero).
* ``estimate_homography`` needs at least 8 matches (``MIN_MATCHES``); 4 to 7 matches are
  fitted with :func:`fit` directly (the library's documented minimum for its protocols).
* ``usac_Fundamental.regression_19639``: seven matches are one minimal sample; its
  7-point solution fits all seven, and fit's one success rule (no fewer inliers than a
  minimal sample) accepts it, as four matches give a homography; OpenCV's MAGSAC returns
  no matrix.
* ``usac_Essential``, ``usac_P3P``, ``usac_Affine2D``, ``usac_SE2``, ``usac_SIM2``,
  ``usac_SE3``, ``usac_SIM3``, ``usac_solvePnPRansac.regression_21105`` and the
  essential/PnP/affine parts of ``usac_testUsacParams``: models clap_unified has no
  space for here (out of the issue's scope: homographies and fundamental matrices).

Documented gaps (strict ``xfail``: each fails today and says why; it turns into a failure
the day it passes):

* ``Calib3d_Homography.EKcase`` with CLAP: 9 of the 10 inliers at 0.01 px (the refit of
  the consensus centre leaves the 10th at 0.0245 px; see ``EK_CLAP_GAP``);
* ``Calib3d_Homography.not_normalized`` with randomized Hough in the anchor-transfer
  space (``metric="transfer"``, not its protocol's): that manifold's log chart has no
  coordinates for ``H33 = 0`` (in its protocol's lie_linear frame it passes);
* ``usac_testUsacParams`` (fundamental part) with CLAP: at 37 % inliers USAC's 5000
  iterations are enough for RANSAC, not for a cluster of fundamental matrices
  (``F_CLAP_GAP``).

Issue 27's fixes these cases exercised (regression tests in
``tests/test_issue27_success_rule.py``): ``not_normalized`` (``H33 = 0``) was
"degenerate" for every method; ``accuracy`` at ``N = 4`` failed for CLAP.
"""

import json

import numpy as np
import pytest

from clap_unified import fit
from clap_unified.cli import main
from clap_unified.imaging.estimate import estimate_homography
from clap_unified.spaces.fundamental import FundamentalSpace
from clap_unified.spaces.homography import HomographySpace

# ------------------------------------------------------------------ upstream constants
MAX_DIFF = 0.032  # HomographyTestUtils::max_diff
MAX_2DIFF = 0.020  # HomographyTestUtils::max_2diff
IMAGE_SIZE = 100
REPROJ_THRESHOLD = 3.0
SIGMA = 0.01


def transfer(H, p):
    q = np.c_[p, np.ones(len(p))] @ np.asarray(H).T
    return q[:, :2] / q[:, 2:]


def forward_error(H, m):
    """upstream ``getError(Homogr)``: ``||H x1 - x2||``."""
    return np.linalg.norm(transfer(H, m[:, :2]) - m[:, 2:], axis=1)


def sampson(F, m):
    """upstream ``getError(Fundam)``: ``|x2' F x1| / sqrt(l1x^2 + l1y^2 + l2x^2 + l2y^2)``."""
    x1 = np.c_[m[:, :2], np.ones(len(m))]
    x2 = np.c_[m[:, 2:], np.ones(len(m))]
    l2 = x1 @ np.asarray(F).T
    l1 = x2 @ np.asarray(F)
    return np.abs(np.sum(x2 * l2, axis=1)) / np.sqrt(l1[:, 0] ** 2 + l1[:, 1] ** 2
                                                     + l2[:, 0] ** 2 + l2[:, 1] ** 2)


def norms(a):
    """``cv::norm`` of a difference in NORM_L1, NORM_L2, NORM_INF."""
    a = np.ravel(a)
    return np.abs(a).sum(), np.sqrt((a * a).sum()), np.abs(a).max()


def h33(H):
    return np.asarray(H) / H[2, 2]


# ------------------------------------------------------------------ Calib3d_Homography.accuracy
def rigid_case(n, seed):
    """upstream: ``N`` points in ``[0, 100)^2``, ``H`` a rotation by ``fi`` and a
    translation in ``[0, 10)^2``, exact correspondences."""
    rng = np.random.default_rng(seed)
    src = rng.random((n, 2)) * IMAGE_SIZE
    fi = rng.random() * 2 * np.pi
    tx, ty = rng.random(2) * np.sqrt(IMAGE_SIZE)
    H = np.array([[np.cos(fi), -np.sin(fi), tx], [np.sin(fi), np.cos(fi), ty], [0, 0, 1.0]])
    return np.c_[src, transfer(H, src)], H


ACCURACY_N = [4, 5, 7, 8, 20, 100, 303]  # upstream: every N in [4, 303]


def fit_method(method, m, threshold=REPROJ_THRESHOLD, rng=0, **options):
    """One upstream method on matches ``m`` through clap_unified."""
    if method == "least_squares":  # method 0: every point, no robust step
        return HomographySpace().refit(m), np.ones(len(m), bool)
    if len(m) >= 8:
        res = estimate_homography(m, method, rng=rng, threshold=threshold, **options)
    else:  # estimate_homography's protocols need 8 matches: fit directly
        space = HomographySpace.for_data(m, metric="transfer") if method == "clap" \
            else HomographySpace()
        res = fit(space, m, method, rng=rng, threshold=threshold, **options)
    assert res.success, (method, res.reason)
    return res.model, res.inliers


@pytest.mark.parametrize("n", ACCURACY_N)
@pytest.mark.parametrize("method", ["least_squares", "ransac", "clap", "lmeds", "rho"])
def test_accuracy_exact_correspondences(n, method):
    # upstream: TEST(Calib3d_Homography, accuracy), first half (no noise)
    if method in ("lmeds", "rho"):
        pytest.skip(f"deliberate difference: OpenCV's {method.upper()} has no counterpart")
    m, H = rigid_case(n, seed=n)
    model, inliers = fit_method(method, m)
    assert model.shape == (3, 3)  # check_matrix_size
    for diff in norms(h33(model) - H):  # check_matrix_diff in L1, L2 and INF
        assert diff <= MAX_DIFF
    if method != "least_squares":  # check_ransac_mask_1: no outlier among exact matches
        assert inliers.shape == (n,) and inliers.dtype == bool and inliers.all()


@pytest.mark.parametrize("n", ACCURACY_N)
@pytest.mark.parametrize("method", ["least_squares", "ransac", "clap"])
def test_accuracy_noisy_correspondences(n, method):
    # upstream: TEST(Calib3d_Homography, accuracy), second half (noise sigma = 0.01)
    m, H = rigid_case(n, seed=1000 + n)
    rng = np.random.default_rng(2000 + n)
    noise = rng.normal(0, SIGMA, (n, 2))
    clean = m[:, 2:].copy()
    m[:, 2:] += noise
    model, inliers = fit_method(method, m)
    found = transfer(model, m[:, :2])
    if method == "least_squares":  # methods 0 and LMEDS: reprojection against the clean points
        for k in range(n):
            d = np.array(norms(found[k] - clean[k])) - np.array(norms(noise[k]))
            assert np.all(d <= MAX_2DIFF), k
        assert np.all(np.array(norms(found - clean)) - np.array(norms(noise)) <= MAX_DIFF)
        return
    # RANSAC and RHO: the mask is exactly the matches within the threshold ...
    diff = np.linalg.norm(found - m[:, 2:], axis=1)
    if method == "clap":  # the "clap" protocol's inliers are by the symmetric error (polish)
        space = HomographySpace(residual="symmetric")
        diff = space.residuals(model[None], m)[0]
    np.testing.assert_array_equal(inliers, diff < REPROJ_THRESHOLD)
    # ... every original inlier (all: the noise is far below 3 px) is found ...
    assert inliers.all()
    # ... and each inlier's reprojection is within max_2diff of its noise
    for k in np.flatnonzero(inliers):
        d = np.array(norms(found[k] - clean[k])) - np.array(norms(noise[k]))
        assert np.all(d <= MAX_2DIFF), k


# ------------------------------------------------------------------ Calib3d_Homography.EKcase
EK1 = np.array([
    280.073029, 239.591217, 221.912201, 259.783997, 216.053192, 278.826569, 222.782532,
    282.330383, 209.924820, 289.122559, 211.077698, 289.384674, 225.287689, 288.795532,
    211.180801, 289.653503, 224.126404, 290.466064, 210.914429, 290.886963, 223.439362,
    291.657715, 224.809387, 291.891602, 209.809082, 292.891113, 208.771164, 293.093231,
    223.160095, 293.259460, 207.874023, 293.989990, 208.963638, 294.209839, 223.963165,
    294.479645, 223.241791, 294.887817, 209.438782, 295.233337, 208.901886, 295.762878,
    221.867981, 295.747711, 224.195511, 298.270905, 209.331345, 305.958191, 224.727875,
    307.186035, 226.718842, 308.095795, 225.363953, 308.200226, 219.897797, 313.845093,
    225.013474, 315.558777], dtype=np.float32).reshape(-1, 2)
EK2 = np.array([
    184.072723, 143.591202, 125.912483, 163.783859, 206.439407, 220.573929, 143.801437,
    180.703903, 9.77904129, 249.660202, 13.8458405, 214.502701, 150.636337, 215.597183,
    64.3103180, 251.667648, 154.952499, 220.780014, 126.638412, 243.040924, 367.568909,
    18.3624954, 160.657944, 221.794052, -1.29507828, 332.472443, 8.51442242, 415.561554,
    127.161377, 197.260361, 5.40714645, 490.978302, 22.5571690, 396.912415, 295.664978,
    7.36064959, 127.241104, 198.887573, -1.25569367, 387.713226, 10.4194012, 431.495758,
    125.868874, 199.751617, 128.195480, 202.270355, 223.436356, 180.489182, 128.727692,
    211.185410, 203.336639, 252.182083, 129.366486, 212.201904, 123.897598, 217.847351,
    129.015259, 219.560623], dtype=np.float32).reshape(-1, 2)
EK = np.c_[EK1, EK2].astype(float)


#: The CLAP gap of EKcase (measured, seeds 0-9): CLAP finds 9 of the 10 inliers in 9 of 10
#: seeds with 2000 candidates (6 of 10 with 5000). Eight of the ten inliers sit in a small
#: patch; only samples holding both far inliers (0 and 1, about 1 sample in 850) give the
#: 10-inlier homography, and they fall in the cluster of the 9-inlier ones, whose centre's
#: refit leaves inlier 1 at 0.0245 px, beyond the 0.01 px threshold: the refinement cannot
#: grow the set (OpenCV keeps the mask of its best sample).
EK_CLAP_GAP = ("documented gap: CLAP's consensus centre refits on 9 inliers and the 10th "
               "stays at 0.0245 px > 0.01 px (see EK_CLAP_GAP's comment)")


@pytest.mark.parametrize("method", [
    "ransac", pytest.param("clap", marks=pytest.mark.xfail(strict=True, reason=EK_CLAP_GAP))])
def test_ekcase(method):
    # upstream: TEST(Calib3d_Homography, EKcase): RANSAC at 0.01 px finds >= 10 inliers,
    # reprojected within 0.01 px (NORM_INF over the inliers). OpenCV's budget: findHomography's
    # default maxIters, 2000 (the "ransac" protocol's 1000 find 9 in 3 of 4 seeds; with 2000,
    # 10 in 8 of seeds 0-9: a sample must hold both far inliers)
    res = estimate_homography(EK, method, rng=0, threshold=0.01, n_hypotheses=2000)
    assert res.success, res.reason
    err = np.abs(transfer(res.model, EK[res.inliers, :2]) - EK[res.inliers, 2:]).max()
    assert res.n_inliers >= 10 and err <= 0.01


def test_ekcase_command_line_agrees(tmp_path, capsys):
    # upstream: TEST(Calib3d_Homography, EKcase), through `clap-unified fit homography`
    f = tmp_path / "ek.csv"
    np.savetxt(f, EK, delimiter=",")
    code = main(["fit", "homography", str(f), "--threshold", "0.01", "--seed", "0",
                 "--method", "ransac", "--hypotheses", "2000"])
    d = json.loads(capsys.readouterr()[0])
    lib = estimate_homography(EK, "ransac", rng=0, threshold=0.01, n_hypotheses=2000)
    assert code == 0 and d["success"] and d["inliers"] == lib.n_inliers >= 10
    np.testing.assert_array_equal(np.array(d["model"]["H"]), h33(lib.model))


# ------------------------------------------------------------------ fromImages, minPoints
def test_from_images():
    # upstream: TEST(Calib3d_Homography, fromImages)
    pytest.skip("deliberate difference: OpenCV's test images (opencv_extra cv/optflow) are "
                "not available; image pairs are tested in tests/test_stitching.py")


@pytest.mark.parametrize("method", ["ransac", "clap"])
def test_min_points(method):
    # upstream: TEST(Calib3d_Homography, minPoints): 2 points raise
    m = np.c_[EK1[:2], EK2[:2]].astype(float)
    with pytest.raises(ValueError, match="matches"):
        estimate_homography(m, method, threshold=0.01)
    with pytest.raises(ValueError, match="matches"):
        fit(HomographySpace(), m, method, threshold=0.01)


@pytest.mark.parametrize("method", ["ransac", "clap", "randomized_hough"])
def test_exactly_four_points(method):
    # upstream: TEST(Calib3d_Homography, accuracy) at N = MIN_COUNT_OF_POINTS = 4, every
    # strategy (issue 27: CLAP failed, one possible sample)
    m, H = rigid_case(4, seed=44)
    res = fit(HomographySpace.for_data(m, metric="transfer"), m, method, threshold=3.0, rng=0)
    assert res.success and res.n_inliers == 4
    assert np.abs(h33(res.model) - H).max() <= MAX_DIFF


# ------------------------------------------------------------------ not_normalized (H33 = 0)
NN_P1 = np.array([[-1, -1], [-2, -2], [-1, 1], [-2, 2], [-1, 0]], float)
NN_P2 = np.array([[0, -1], [-1, -1], [0, 0], [-1, 0], [0, -0.5]], float)
NN_REF = np.array([[0.74276086, 0.0, 0.74276086], [0.18569022, 0.18569022, 0.0],
                   [-0.37138043, 0.0, 0.0]])


def up_to_scale(H):
    H = np.asarray(H, float) / np.linalg.norm(H)
    return H * np.sign(H.flat[np.argmax(np.abs(H))])


@pytest.mark.parametrize("method", ["least_squares", "ransac", "clap", "randomized_hough",
                                    "lmeds"])
def test_not_normalized(method):
    # upstream: TEST(Calib3d_Homography, not_normalized): H33 = 0; methods 0, RANSAC, LMEDS
    # give no NaN and the reference to 1e-8 (issue 27: "degenerate" for every method)
    if method == "lmeds":
        pytest.skip("deliberate difference: OpenCV's LMEDS has no counterpart")
    m = np.c_[NN_P1, NN_P2]
    if method == "least_squares":
        model = HomographySpace().refit(m)
    else:  # each strategy in its protocol's space (randomized Hough: the lie_linear frame)
        space = HomographySpace.for_data(m, metric="lie_linear" if method == "randomized_hough"
                                         else "transfer")
        res = fit(space, m, method, rng=0)
        assert res.success and res.n_inliers == 5, res.reason
        model = res.model
    assert np.all(np.isfinite(model))
    assert np.abs(up_to_scale(model) - up_to_scale(NN_REF)).max() <= 1e-8
    assert model[2, 2] == 0 or abs(model[2, 2]) < 1e-12  # the fallback form: unit norm
    assert np.linalg.norm(model) == pytest.approx(1.0)


@pytest.mark.xfail(strict=True, raises=ValueError, reason=(
    "documented gap: HomographyTransfer's log chart is Homography('h33')'s, which has no "
    "coordinates for H33 = 0; randomized Hough bins in that chart"))
def test_not_normalized_randomized_hough_in_the_transfer_chart():
    # upstream: TEST(Calib3d_Homography, not_normalized), randomized Hough outside its
    # protocol's space (metric="transfer" instead of the lie_linear frame)
    m = np.c_[NN_P1, NN_P2]
    res = fit(HomographySpace.for_data(m, metric="transfer"), m, "randomized_hough", rng=0)
    assert res.success and res.n_inliers == 5


def test_degenerate_collinear_points():
    # the situation (OpenCV returns an empty matrix): every source point on a line
    rng = np.random.default_rng(7)
    x = rng.uniform(0, 640, 40)
    m = np.c_[x, 0.3 * x + 5, rng.uniform(0, 640, (40, 2))]
    for method in ("ransac", "clap", "randomized_hough"):
        res = estimate_homography(m, method, rng=0)
        assert not res.success and res.model is None and res.reason


# ------------------------------------------------------------------ usac_* point generator
def euler(pitch, yaw, roll):
    rx = np.array([[1, 0, 0], [0, np.cos(roll), -np.sin(roll)], [0, np.sin(roll), np.cos(roll)]])
    ry = np.array([[np.cos(pitch), 0, np.sin(pitch)], [0, 1, 0],
                   [-np.sin(pitch), 0, np.cos(pitch)]])
    rz = np.array([[np.cos(yaw), -np.sin(yaw), 0], [np.sin(yaw), np.cos(yaw), 0], [0, 0, 1]])
    return rz @ ry @ rx


def generate_points(rng, n, kind, inlier_ratio, noise_std):
    """upstream ``generatePoints`` for ``Homogr`` and ``Fundam``: ``(matches, n_inliers)``,
    the inliers first."""
    R = euler(*rng.uniform(-np.pi / 6, np.pi / 6, 3))
    t = np.array([rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(1.0, 2.0)])
    K = np.array([[rng.uniform(100, 1000), 0, 100.0], [0, rng.uniform(100, 1000),
                                                       rng.uniform(-100, 100)], [0, 0, 1]])
    inl = int(inlier_ratio * n)
    if kind == "homography":  # planar points, Z = 1
        X = np.r_[rng.uniform(0, 1, (2, inl)), np.ones((1, inl))]
    else:
        X = rng.uniform(0, 1, (3, inl))
    z = (R @ X + t[:, None])[2]
    if z.min() < 0:  # updateTranslation
        t[2] -= z.min() + 1.0
    p1 = K @ X
    p2 = K @ (R @ X + t[:, None])
    p1, p2 = (p1[:2] / p1[2]).T, (p2[:2] / p2[2]).T
    out = n - inl
    p1 = np.r_[p1, rng.uniform(0, 1000, (out, 2))]
    p2 = np.r_[p2, rng.uniform(0, 1000, (out, 2))]
    p1 += rng.normal(0, noise_std, p1.shape)
    p2 += rng.normal(0, noise_std, p2.shape)
    return np.c_[p1, p2], inl


def check_inliers_mask(error, inl_size, thr, inliers):
    """upstream ``checkInliersMask``: every reported inlier within ``1.001 thr``, more
    than 80 % of the true inliers found."""
    assert np.all(error[inliers] < thr * 1.001)
    assert np.count_nonzero(inliers) > 0.8 * inl_size


def max_iters(w, m, conf=0.99, slack=1.3):
    return int(slack * np.log(1 - conf) / np.log(1 - w ** m))


# ------------------------------------------------------------------ usac_Homography.accuracy
@pytest.mark.parametrize("ratio", [0.1, 0.3, 0.5, 0.7, 0.9])  # upstream: 0.1, 0.2, ..., 0.9
@pytest.mark.parametrize("method", ["ransac", "clap"])
def test_usac_homography_accuracy(method, ratio):
    # upstream: TEST(usac_Homography, accuracy): 1500 points, noise 0.1, thr 2, confidence
    # 0.99, max_iters with a 1.3 margin; USAC_* flags map to RANSAC and CLAP
    rng = np.random.default_rng(int(ratio * 100))
    m, inl = generate_points(rng, 1500, "homography", ratio, 0.1)
    budget = max_iters(ratio, 4)
    if method == "ransac":
        res = estimate_homography(m, "ransac", rng=0, threshold=2.0, n_hypotheses=budget,
                                  confidence=0.99)
        error = forward_error(res.model, m)
    else:  # CLAP: hypotheses for five all-inlier samples, at most the RANSAC budget
        res = estimate_homography(m, "clap", rng=0, threshold=2.0,
                                  max_hypotheses=max(budget, 1000))
        # the protocol's inliers are by the symmetric error; upstream's check is forward
        error = HomographySpace(residual="symmetric").residuals(res.model[None], m)[0]
    assert res.success, res.reason
    check_inliers_mask(error, inl, 2.0, res.inliers)
    # and upstream's forward error of every inlier, for CLAP too (within sqrt(2) thr: the
    # symmetric error is the RMS of forward and backward)
    assert np.all(forward_error(res.model, m)[res.inliers] < np.sqrt(2) * 2.0 * 1.001)


# ------------------------------------------------------------------ usac_Fundamental.accuracy
@pytest.mark.parametrize("ratio", [0.45, 0.65, 0.85])  # upstream: 0.25, 0.35, ..., 0.85
@pytest.mark.parametrize("method", ["ransac", "clap"])
def test_usac_fundamental_accuracy(method, ratio):
    # upstream: TEST(usac_Fundamental, accuracy): 2000 points, noise 0.1, thr 1 (Sampson),
    # confidence 0.99, max_iters with a 1.25 margin (7-point samples)
    rng = np.random.default_rng(int(ratio * 100))
    m, inl = generate_points(rng, 2000, "fundamental", ratio, 0.1)
    budget = max_iters(ratio, 7, slack=1.25)
    if method == "ransac":
        res = fit(FundamentalSpace(), m, "ransac", threshold=1.0, n_hypotheses=budget,
                  confidence=0.99, rng=0)
    else:
        res = fit(FundamentalSpace.for_data(m), m, "clap", threshold=1.0,
                  n_hypotheses=min(budget, 2000), rng=0)
    assert res.success, res.reason
    check_inliers_mask(sampson(res.model, m), inl, 1.0, res.inliers)


def test_usac_fundamental_regression_19639():
    # upstream: TEST(usac_Fundamental, regression_19639): 7 matches, three of them the
    # same destination point: MAGSAC returns no matrix
    x = np.array([[941, 890], [596, 940], [898, 941], [894, 933], [586, 938], [902, 933],
                  [887, 935]], float)
    y = np.array([[1416, 806], [1157, 852], [1380, 855], [1378, 843], [1145, 849],
                  [1378, 843], [1378, 843]], float)
    m = np.c_[x, y]
    for method in ("ransac", "clap"):  # no crash, and what is returned holds
        res = fit(FundamentalSpace(), m, method, threshold=3.0, rng=0)
        if res.success:
            assert res.n_inliers >= 7 and np.all(sampson(res.model, m)[res.inliers] < 3.0)
        else:
            assert res.model is None and res.reason
    pytest.skip("deliberate difference: seven matches are one minimal sample; its 7-point "
                "solution fits all seven and fit's one success rule (no fewer inliers than "
                "a minimal sample) accepts it, as four matches give a homography "
                "(Calib3d_Homography.accuracy at N = 4); OpenCV's MAGSAC returns no matrix")


# ------------------------------------------------------------------ usac_testUsacParams
def usac_params_ratio(sample_size, max_iterations=5000, conf=0.99):
    """upstream ``getInlierRatio``: the ratio at which ``maxIterations`` just suffice."""
    return (1 - np.exp(np.log(1 - conf) / max_iterations)) ** (1 / sample_size)


#: Measured (data seed 21, 552 inliers of 1500): CLAP finds 28 inliers with 5000
#: candidates, 24 with 20000, 52 with 5000 escalating to 30000 (129 s): at 37 % inliers
#: 7-match samples are all-inlier once in 1100, and the fundamental matrices of noisy
#: all-inlier samples scatter too widely on ProjectiveMatrices to form a cluster.
F_CLAP_GAP = ("documented gap: CLAP does not find the fundamental matrix at 37 % inliers "
              "with USAC's 5000 iterations (nor 30000); RANSAC needs one all-inlier sample")


@pytest.mark.parametrize("kind,method", [
    ("homography", "ransac"), ("homography", "clap"), ("fundamental", "ransac"),
    pytest.param("fundamental", "clap", marks=pytest.mark.xfail(strict=True, reason=F_CLAP_GAP))])
def test_usac_params(kind, method):
    # upstream: TEST(usac_testUsacParams, accuracy), its homography and fundamental parts:
    # UsacParams() defaults (threshold 1.5, confidence 0.99, 5000 iterations), the inlier
    # ratio at which 5000 iterations just suffice, 1500 points, noise 0.1
    rng = np.random.default_rng(19 if kind == "homography" else 21)
    sample = 4 if kind == "homography" else 7
    m, inl = generate_points(rng, 1500, kind, usac_params_ratio(sample), 0.1)
    if kind == "homography":
        if method == "ransac":
            res = estimate_homography(m, "ransac", rng=0, threshold=1.5, n_hypotheses=5000)
            error = forward_error(res.model, m)
        else:
            res = estimate_homography(m, "clap", rng=0, threshold=1.5, n_hypotheses=5000)
            error = HomographySpace(residual="symmetric").residuals(res.model[None], m)[0]
    else:
        space = FundamentalSpace() if method == "ransac" else FundamentalSpace.for_data(m)
        res = fit(space, m, method, threshold=1.5, n_hypotheses=5000, rng=0)
        error = sampson(res.model, m)
    assert res.success, res.reason
    check_inliers_mask(error, inl, 1.5, res.inliers)
