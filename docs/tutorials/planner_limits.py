"""Directional limits for a motion planner: how hard can the tool accelerate on a path."""

import numpy as np

import polyell as pe

arm = pe.robots.load("chiacchio2000")
analysis = pe.analyze(arm.dynamics([0.4, 1.1, -0.6]), arm.tau_max)
P, E = analysis.polytope, analysis.ellipsoid("chiacchio")

# Unit tangents of a planned path at three waypoints.
angles = np.deg2rad([0.0, 60.0, 135.0])
tangents = np.column_stack([np.cos(angles), np.sin(angles)])
exact = P.limits(tangents)  # closed form, exact
lp = P.limits(tangents, method="lp")  # the LP reference agrees
ellipsoid = E.limits(tangents)  # eq. 24: inside the exact interval
for k, angle in enumerate(np.rad2deg(angles)):
    print(
        f"{angle:5.0f} deg: exact [{exact.lo[k]:8.3f}, {exact.hi[k]:8.3f}]  "
        f"LP [{lp.lo[k]:8.3f}, {lp.hi[k]:8.3f}]  "
        f"new ellipsoid [{ellipsoid.lo[k]:8.3f}, {ellipsoid.hi[k]:8.3f}] m/s^2"
    )

# A planned acceleration is feasible iff it lies in the polytope: some torque within the
# limits produces it.  The minimum-norm torque of eq. 33 need not be that torque: outside
# the new ellipsoid its largest component can exceed 1 although the point is feasible.
demand = 0.9 * exact.hi[1] * tangents[1]
print("feasible:", bool(P.contains(demand)), " inside the new ellipsoid:", bool(E.contains(demand)))
qdd, tau_n = analysis.inverse(demand)
print("minimum-norm torque (eq. 33): |tau_n|_inf =", round(float(np.abs(tau_n).max()), 4))
