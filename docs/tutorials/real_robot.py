"""A real robot: the Franka Panda from example-robot-data, through Pinocchio."""

import numpy as np

import polyell as pe

panda = pe.robots.load("panda")  # fingers locked, tip panda_hand_tcp, linear task
print("joints:", panda.joint_names)
print("torque limits [N m]:", panda.tau_max)

q = np.array([0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8])
analysis = pe.analyze(panda.dynamics(q), panda.tau_max)
P = analysis.polytope
print(
    f"polytope: dimension {P.dim}, {len(P.vertices)} vertices, {len(P.A)} facets, "
    f"volume {P.volume:.4g} (m/s^2)^3"
)
lo, hi = P.limits([0.0, 0.0, 1.0])
print(f"vertical acceleration of the tool: [{lo:.2f}, {hi:.2f}] m/s^2")

comparison = pe.compare(analysis, mvie=False)
for kind in ("chiacchio", "yoshikawa"):
    s = comparison[kind]
    print(
        f"{kind}: coverage {s.coverage:.3f}, inscribed scale {s.inscribed_scale:.3f}, "
        f"witness max |tau_n| {s.witness_torque_max:.3f}"
    )
