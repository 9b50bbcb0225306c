"""Comparison: scores of the ellipsoids against the exact polytope, and their tables."""

from polyell.comparison.candidates import Candidate
from polyell.comparison.comparison import COMPARED_KINDS, SCORE_NAMES, Comparison, Scores, compare
from polyell.comparison.layout import TableLayout
from polyell.comparison.limits import limits_table
from polyell.comparison.set_comparison import SetComparison, SetScores

__all__ = [
    "COMPARED_KINDS",
    "SCORE_NAMES",
    "Candidate",
    "Comparison",
    "Scores",
    "SetComparison",
    "SetScores",
    "TableLayout",
    "compare",
    "limits_table",
]
