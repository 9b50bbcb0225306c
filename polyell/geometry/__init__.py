"""Geometry: the exact polytopes, ellipsoids, affine sets and directional limits."""

from polyell.geometry.combine import in_frame, intersection, minkowski_sum
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.hpolytope import HPolytope
from polyell.geometry.limits import DirectionalLimits
from polyell.geometry.polytope import Polytope
from polyell.geometry.subspace import AFFINE_RTOL, RANK_RTOL, AffineSubspace, rank_revealing_svd

__all__ = [
    "AFFINE_RTOL",
    "RANK_RTOL",
    "AffineSubspace",
    "DirectionalLimits",
    "Ellipsoid",
    "HPolytope",
    "Polytope",
    "in_frame",
    "intersection",
    "minkowski_sum",
    "rank_revealing_svd",
]
