"""Every number printed in section 6 of Chiacchio (2000), reproduced to the printed digits.

Two notes on how the paper prints things:

* The "eigenvalues" it gives for each core N (18.341 and 31.323; 28.595 and 45.163) are
  the ellipsoid's semi-axis lengths, 1/sqrt(eigenvalue of N).
* It pairs them with the eigenvectors in the opposite order: N [0.7744, 0.6326]^T has the
  smaller eigenvalue, i.e. the *longer* semi-axis 31.323.  The tests check each printed
  eigenvector against the axis it really belongs to (N v = lambda v), not the pairing.
"""

from __future__ import annotations

import numpy as np
import pytest

import polyell as pe
from reference import (
    PAPER_Q_REDUNDANT,
    PAPER_Q_SINGULAR,
    assert_printed,
    paper_analysis,
)

X_DIRECTION = np.array([1.0, 0.0])
#: Orthogonal to the stretched arm at q1 = pi/6: the direction U_1 of the paper's SVD.
ARM_NORMAL = np.array([-0.5, np.sqrt(3.0) / 2.0])


@pytest.fixture(scope="module")
def redundant() -> pe.Analysis:
    return paper_analysis(PAPER_Q_REDUNDANT)


@pytest.fixture(scope="module")
def singular() -> pe.Analysis:
    return paper_analysis(PAPER_Q_SINGULAR)


def assert_axis(E: pe.Ellipsoid, printed_vector: str, printed_length: str) -> None:
    """The printed unit vector (up to sign) is the axis of the printed semi-axis length."""
    v = np.array(printed_vector.split(), dtype=float)
    index = int(np.argmax(np.abs(E.axes.T @ v)))
    axis = E.axes[:, index] * np.sign(E.axes[:, index] @ v)
    assert_printed(axis, printed_vector)
    assert_printed(E.semi_axes[index], printed_length)


# --- first case study: redundant arm at q = (pi/2, -pi/2, -pi/2) ---------------------------


def test_gravity_acceleration_eq8(redundant):
    assert_printed(redundant.xg, "0.000 -12.392")


def test_classic_core_eq27(redundant):
    assert_printed(redundant.ellipsoid("yoshikawa").core, "1.8011 -0.9571 -0.9571 2.1908", 1e-3)


def test_classic_axes_and_lengths(redundant):
    E = redundant.ellipsoid("yoshikawa")
    assert_axis(E, "0.7744 0.6326", "31.323")
    assert_axis(E, "0.6326 -0.7744", "18.341")


def test_new_core_eq32(redundant):
    assert_printed(redundant.ellipsoid("chiacchio").core, "0.5349 0.1752 0.1752 1.1784", 1e-3)


def test_new_axes_and_lengths(redundant):
    E = redundant.ellipsoid("chiacchio")
    assert_axis(E, "0.9691 -0.2467", "45.163")
    assert_axis(E, "0.2467 0.9691", "28.595")


def test_new_interval_along_x_eq24(redundant):
    lo, hi = redundant.ellipsoid("chiacchio").limits(X_DIRECTION)
    assert_printed([lo, hi], "-43.401 35.284")


def test_new_inverse_eq33_at_upper_limit(redundant):
    hi = redundant.ellipsoid("chiacchio").limits(X_DIRECTION).hi
    qdd, tau_n = redundant.inverse(hi * X_DIRECTION, kind="chiacchio")
    assert_printed(qdd, "6.8943 -6.8943 84.356")
    assert_printed(tau_n, "0.3020 0.5247 0.7959")
    assert_printed(np.linalg.norm(tau_n), "1.0000")


def test_classic_inverse_eq26_breaks_the_limits(redundant):
    hi = redundant.ellipsoid("chiacchio").limits(X_DIRECTION).hi
    solution = redundant.inverse(hi * X_DIRECTION, kind="yoshikawa")
    assert_printed(solution.qdd, "-23.522 23.522 23.522")
    assert_printed(solution.tau_n, "-0.7879 0.5754 1.1761")
    assert_printed(solution.torque_norm, "1.5281")
    assert not solution.within_limits  # the third torque exceeds its bound


# --- second case study: the stretched arm at q = (pi/6, 0, 0) -----------------------------


def test_singular_gravity_acceleration(singular):
    assert_printed(singular.xg, "4.5579 -7.8945")


def test_singular_M_eq14(singular):
    # The paper truncates M[0, 1] = 16.01277... to 16.012; every other entry is rounded.
    assert_printed(np.delete(singular.M.ravel(), 1), "-5.4745 -25.858 9.4820 -27.735 44.787")
    assert np.trunc(singular.M[0, 1] * 1e3) / 1e3 == 16.012
    assert singular.rank == 1
    assert singular.is_singular


def test_singular_svd_eq35(singular):
    svd = singular.svd
    U = np.hstack([svd.U1, svd.U2])
    U = U * np.sign(U[1])  # the paper's signs: second row positive
    assert_printed(U, "-0.5 0.866 0.866 0.5")
    assert_printed(svd.singular_values, "61.806 0.000")
    V1 = svd.V1[:, 0] * np.sign(svd.V1[0, 0])
    assert_printed(V1, "0.1771 -0.5182 0.8367")
    # The paper's other two rows are one orthonormal basis of Ker(M) among many: each
    # lies in the kernel to the printed digits.
    for printed in ("-0.9640 0.0798 0.2535", "0.1982 0.8515 0.4854"):
        v = np.array(printed.split(), dtype=float)
        assert np.linalg.norm(V1 @ v) <= 1.5e-4
        assert np.linalg.norm(singular.M @ v) <= np.linalg.norm(singular.M) * 1.5e-4


def test_singular_core_eq38(singular):
    E = singular.ellipsoid("chiacchio")
    assert_printed(E.core, "0.0654 -0.1134 -0.1134 0.1963", 1e-3)
    assert E.rank == 1  # a segment
    assert_axis(E, "-0.5 0.866", "61.806")


def test_singular_interval_eq24(singular):
    lo, hi = singular.ellipsoid("chiacchio").limits(ARM_NORMAL)
    assert_printed([lo, hi], "-70.922 52.690")


def test_singular_inverse_eq40_at_lower_limit(singular):
    lo = singular.ellipsoid("chiacchio").limits(ARM_NORMAL).lo
    xdd = lo * ARM_NORMAL
    assert_printed(xdd, "35.461 -61.420")
    qdd, tau_n = singular.inverse(xdd, kind="chiacchio")
    assert_printed(qdd, "-49.417 172.961 -364.223")
    assert_printed(tau_n, "-0.1771 0.5182 -0.8367")
    assert_printed(np.linalg.norm(tau_n), "1.0000")


def test_singular_polytope_is_a_segment_on_the_same_line(singular):
    P = singular.polytope
    assert P.dim == 1
    assert P.vertices.shape == (2, 2)
    direction = np.diff(P.vertices, axis=0)[0]
    assert abs(ARM_NORMAL @ direction) == pytest.approx(np.linalg.norm(direction), rel=1e-12)
    # Its length is 2 sum_i |U_1 . M_i| (eq. 15 along the only free direction).
    assert P.volume == pytest.approx(2 * np.abs(ARM_NORMAL @ singular.M).sum(), rel=1e-12)


def test_classic_ellipsoid_undefined_at_the_singularity(singular):
    with pytest.raises(pe.UndefinedEllipsoidError, match="J J\\^T"):
        singular.ellipsoid("yoshikawa")
