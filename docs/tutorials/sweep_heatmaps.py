"""A sweep over (q2, q3) of the paper's arm and a heat map of the new ellipsoid's coverage."""

import tempfile
from pathlib import Path

import numpy as np

import polyell as pe
from polyell.figures import plot_score_map, save_figure

arm = pe.robots.load("chiacchio2000")
q2 = q3 = np.linspace(-np.pi, np.pi, 41)
frame = pe.sweep(arm, pe.grid(np.pi / 2, q2, q3))  # one row per configuration
print(len(frame), "configurations;", int((frame.polytope_dim < 2).sum()), "singular")
print(frame[["chiacchio_coverage", "yoshikawa_coverage"]].describe().round(3))

coverage = frame["chiacchio_coverage"].to_numpy().reshape(q2.size, q3.size)
figure = plot_score_map(
    coverage,
    q3,
    q2,
    xlabel="$q_3$ [rad]",
    ylabel="$q_2$ [rad]",
    label="coverage of the new ellipsoid",
)
with tempfile.TemporaryDirectory() as folder:
    files = save_figure(figure, Path(folder) / "coverage", formats=("png",), dpi=100)
    print("wrote", [f.name for f in files])
