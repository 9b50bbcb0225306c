"""Quick start: the comparison table for the paper's arm."""

import numpy as np

import polyell as pe

arm = pe.robots.load("chiacchio2000")  # Chiacchio (2000), section 6
analysis = pe.analyze(arm.dynamics([np.pi / 2, -np.pi / 2, -np.pi / 2]), arm.tau_max)
comparison = pe.compare(analysis)
print(comparison.to_markdown())
