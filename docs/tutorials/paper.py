"""Every number of the paper's section 6, from the library."""

import numpy as np

import polyell as pe

arm = pe.robots.load("chiacchio2000")

redundant = pe.analyze(arm.dynamics([np.pi / 2, -np.pi / 2, -np.pi / 2]), arm.tau_max)
print("x_g =", np.round(redundant.xg, 3) + 0.0)  # + 0.0: no "-0." from rounding
for kind in ("yoshikawa", "chiacchio"):
    E = redundant.ellipsoid(kind)
    print(f"{kind}: N = 1e-3 *", np.round(E.core * 1e3, 4).tolist())
    print(f"  semi-axes {np.round(E.semi_axes, 3)}, axes (columns)", np.round(E.axes, 4).tolist())
lo, hi = redundant.ellipsoid("chiacchio").limits([1.0, 0.0])
print(f"interval along x (eq. 24): [{lo:.3f}, {hi:.3f}]")
for kind, equation in (("chiacchio", "33"), ("yoshikawa", "26")):
    qdd, tau_n = redundant.inverse([hi, 0.0], kind=kind)
    print(
        f"eq. {equation}: qdd = {np.round(qdd, 4)}, tau_n = {np.round(tau_n, 4)}, "
        f"|tau_n| = {np.linalg.norm(tau_n):.4f}"
    )

singular = pe.analyze(arm.dynamics([np.pi / 6, 0.0, 0.0]), arm.tau_max)
print("\nsingular: x_g =", np.round(singular.xg, 4), " rank M =", singular.rank)
print("M =", np.round(singular.M, 3).tolist())
print(
    "sigma_1 =",
    round(float(singular.svd.sigma[0]), 3),
    " U_1 =",
    np.round(singular.svd.U1[:, 0], 3),
)
E = singular.ellipsoid("chiacchio")
print("N = 1e-3 *", np.round(E.core * 1e3, 4).tolist())
t = np.array([-0.5, np.sqrt(3) / 2])
lo, hi = E.limits(t)
print(f"interval along U_1: [{lo:.3f}, {hi:.3f}]")
qdd, tau_n = singular.inverse(lo * t)
print(f"eq. 40 at the lower end: qdd = {np.round(qdd, 3)}, tau_n = {np.round(tau_n, 4)}")
