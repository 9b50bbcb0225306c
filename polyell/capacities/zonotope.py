r"""What the acceleration and velocity capacities share: a zonotope and its image ellipsoid.

Both sets are images of the unit cube of normalized joint quantities under an affine map
:math:`x = M u + x_c`, :math:`\|u\|_\infty \le 1`: the zonotope with generators M and
centre :math:`x_c`.  The image of the unit ball, :math:`\{x_c + M u : \|u\| \le 1\}`,
is an ellipsoid inside it (the ball lies in the cube) with the axes and semi-axes of the
SVD of M (eq. 35); at a singular configuration both lie in :math:`x_c + \operatorname{Im}
M` (eq. 38).  Its inverse is the minimum-norm one, :math:`u = M^+ (x - x_c)`.
"""

from __future__ import annotations

import warnings
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from polyell.cached import cached_property
from polyell.capacities.base import Analysis, label_rows
from polyell.errors import ProjectedInputWarning, UnreachableAccelerationError
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.polytope import Polytope
from polyell.geometry.subspace import RankRevealingSVD, rank_revealing_svd
from polyell.inverse import AffineMap
from polyell.models.dynamics import Dynamics
from polyell.validation import check_magnitudes

__all__ = ["ZonotopeAnalysis"]


class ZonotopeAnalysis(Analysis):
    """A capacity whose exact set is the zonotope ``{M u + xg : |u|_inf <= 1}``.

    Attributes
    ----------
    M : ndarray, shape (m, n)
        The generators [task unit per unit normalized joint quantity].
    xg : ndarray, shape (m,)
        The common centre of the zonotope and the ellipsoids [task unit].
    svd : RankRevealingSVD
        Eq. (35) for M; its rank decision is shared by the polytope, the ellipsoids and
        the inverse maps.
    """

    M: NDArray[np.float64]
    xg: NDArray[np.float64]
    svd: RankRevealingSVD

    #: What the sets hold and what ``M`` and ``xg`` are, for the messages of
    #: :func:`~polyell.validation.check_magnitudes`.
    magnitude_names: ClassVar[tuple[str, str, str]] = (
        "accelerations",
        "the generators M (eq. 14)",
        "xg (eq. 8)",
    )
    #: The block paths (:mod:`polyell.studies.batch`) compute the acceleration zonotope of
    #: :meth:`_acceleration_dynamics` and its sets: this capacity's sets by the names of
    #: the acceleration sets that are them (``{acceleration set: set}``).
    acceleration_names: ClassVar[dict[str, str]] = {
        "polytope": "polytope",
        "chiacchio": "chiacchio",
        "yoshikawa": "yoshikawa",
    }

    @classmethod
    def _acceleration_dynamics(cls, dyn: Dynamics) -> Dynamics:
        """The batch whose acceleration zonotope, within this capacity's limits, is its set."""
        return dyn

    @classmethod
    def _check_generators(cls, M: NDArray[np.float64], xg: NDArray[np.float64]) -> None:
        """Refuse generators and centres (one set or a batch) beyond floating point."""
        check_magnitudes(M, xg, quantity=cls.magnitude_names, limits=cls.limit_keywords[0])

    def _set_generators(self, M: NDArray[np.float64], xg: NDArray[np.float64], rtol: float) -> None:
        self._check_generators(M, xg)
        self.M, self.xg = M, xg
        self.svd = rank_revealing_svd(M, rtol)

    @property
    def center(self) -> NDArray[np.float64]:
        """``xg``: the centre of the zonotope and of the image ellipsoid."""
        return self.xg

    @property
    def rank(self) -> int:
        """Numerical rank of ``M`` (equal to that of J)."""
        return self.svd.rank

    @cached_property
    def polytope(self) -> Polytope:
        """The exact set: the zonotope with generators ``M`` about ``xg``.

        Generators negligible against the largest (``RANK_RTOL``: a joint that does not move
        the task point, as the Panda's last joint for its position) add nothing to the set
        and are left out of it (its vertex enumeration would take them as degenerate).
        """
        M, svd = self.M, self.svd
        norms = np.sqrt(np.add.reduce(M * M, 0))
        threshold = svd.rtol * np.maximum.reduce(norms, None)
        keep = None if np.minimum.reduce(norms, None) > threshold else norms > threshold
        if keep is None or not keep.any():  # every generator, or M = 0 (a point)
            polytope = Polytope(M, self.xg, svd=svd)
        else:
            svd = svd._replace(V1=svd.V1.compress(keep, 0))
            polytope = Polytope(M.compress(keep, 1), self.xg, svd=svd)
        polytope.affine_rtol = self.affine_rtol
        label_rows(polytope, self.task)
        return polytope

    def _image_ellipsoid(self, kind: str) -> Ellipsoid:
        """``{xg + M u : |u| <= 1}``: axes ``U_1``, semi-axes the singular values of M."""
        return Ellipsoid(self.xg, self.svd.U1, self.svd.sigma, kind=kind)

    def _minimum_norm_map(self) -> AffineMap:
        """``x -> M^+ (x - xg)``: the smallest normalized joint quantity reaching x."""
        return AffineMap(self.svd.pinv(), self.xg, np.zeros(self.n))

    def _on_affine_set(self, x: NDArray[np.float64], name: str) -> NDArray[np.float64]:
        """Points of a singular configuration projected onto ``xg + Im(M)``, or refused."""
        if not self.is_singular:
            return x
        affine_set = self.polytope.affine_set
        if not np.all(affine_set.near(x, self.affine_rtol)):
            distance = np.max(affine_set.distance(x))
            raise UnreachableAccelerationError(
                f"{name}: expected points in the affine set xg + Im(M) of dimension "
                f"{self.rank}, got one at distance {distance:.3g} from it (more than "
                f"affine_rtol = {self.affine_rtol:g} relative); no joint quantity "
                "produces it at this singular configuration. Fix: project it with "
                "analysis.polytope.affine_set.project(...)."
            )
        moved = np.max(affine_set.distance(x))
        if moved > self.polytope.atol:
            warnings.warn(
                f"{name}: taken as rounded and projected onto the affine set of this "
                f"singular configuration (distance {moved:.3g}); the inverse maps the "
                "projection.",
                ProjectedInputWarning,
                stacklevel=3,
            )
        projected: NDArray[np.float64] = affine_set.project(x)
        return projected
