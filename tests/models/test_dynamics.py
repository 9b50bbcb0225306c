from __future__ import annotations

import numpy as np
import pytest

import polyell as pe


def test_dynamics_keeps_clean_read_only_arrays():
    dyn = pe.Dynamics(J=[[1, 2, 3]], B=np.eye(3), g=[0, 0, 1])
    assert dyn.J.dtype == np.float64 and (dyn.m, dyn.n) == (1, 3)
    with pytest.raises(ValueError):
        dyn.J[0, 0] = 5.0


def test_nearly_symmetric_inertia_is_symmetrised_exactly():
    B = np.array([[2.0, 0.5], [0.5 + 1e-14, 1.0]])
    dyn = pe.Dynamics(J=np.eye(2), B=B, g=[0.0, 0.0])
    np.testing.assert_array_equal(dyn.B, dyn.B.T)


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"J": [1.0, 2.0]}, "J: expected an array of Jacobian entries with shape (m, n)"),
        ({"J": np.ones((0, 2))}, "at least one task row"),
        ({"J": [[np.nan, 1.0]]}, "finite values"),
        ({"B": [[1.0, 0.5], [0.0, 1.0]]}, "B: expected a symmetric matrix"),
        ({"B": [[1.0, 0.0], [0.0, -1.0]]}, "positive-definite"),
        ({"B": np.eye(3)}, "B: expected an array of real numbers with shape (2, 2)"),
        ({"g": [1.0]}, "g: expected an array of real numbers with shape (2,)"),
        ({"g": [1.0, np.inf]}, "g: expected finite values"),
        ({"g": ["a", "b"]}, "g: expected an array"),
    ],
)
def test_bad_dynamics_raise_input_errors(kwargs, fragment):
    args = {"J": [[1.0, 0.5]], "B": np.eye(2), "g": [0.0, 1.0]} | kwargs
    with pytest.raises(pe.InputError) as info:
        pe.Dynamics(**args)
    assert fragment in str(info.value)


def test_none_is_reported_as_none_not_as_nan():
    with pytest.raises(pe.InputError, match=r"g: expected an array .* got None"):
        pe.Dynamics(J=[[1.0, 0.5]], B=np.eye(2), g=None)
