"""pe.robots.load: names and options of a wrong kind are refused by name."""

from __future__ import annotations

import pytest

import polyell as pe


@pytest.mark.parametrize(
    ("name", "options", "fragment"),
    [
        (5, {}, "name: expected one of ['chiacchio2000'"),
        (None, {}, "name: expected one of"),
        (
            "chiacchio2000",
            {"tip": "x"},
            "options: expected keyword arguments among ['tau_max', 'tau_min', 'qd_max', "
            "'qd_min', 'torque_speed'] for the planar arm",
        ),
        ("panda", {"payload": {"mass": 1.0}}, "payload: expected a pe.Payload(mass, com, inertia)"),
        ("panda", {"payload": 5}, "payload: expected a pe.Payload"),
        ("panda", {"payload": (1.0, [0, 0, 0])}, "payload: expected a pe.Payload"),
        ("panda", {"tip_frame": "x"}, "options: expected keyword arguments among ['task'"),
    ],
)
def test_bad_names_and_options(name, options, fragment):
    with pytest.raises(pe.InputError) as info:
        pe.robots.load(name, **options)
    assert fragment in str(info.value)


def test_a_payload_object_is_carried():
    light = pe.robots.load("panda")
    heavy = pe.robots.load("panda", payload=pe.Payload(mass=2.0, com=(0.0, 0.0, 0.05)))
    q = [0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8]
    # A load at the tip pulls down: the gravity torque of the shoulder (joint 2) grows.
    assert abs(heavy.dynamics(q).g[1]) > abs(light.dynamics(q).g[1])


@pytest.mark.parametrize(
    ("name", "meant"),
    [("pandaa", "panda"), ("Panda", "panda"), ("ur_5", "ur5"), ("chiacchio", "chiacchio2000")],
)
def test_a_misspelled_name_gets_the_closest_one(name, meant):
    with pytest.raises(pe.InputError) as info:
        pe.robots.load(name)
    assert str(info.value).endswith(f"Fix: did you mean {meant!r}?")
    if meant != "chiacchio2000":  # the library arms by their URDF, too
        with pytest.raises(pe.InputError, match=f"did you mean {meant!r}"):
            pe.robots.urdf_path(name)


def test_a_name_like_none_lists_every_name():
    with pytest.raises(pe.InputError) as info:
        pe.robots.load("quadruped")
    assert "did you mean" not in str(info.value)
    assert "use one of ['chiacchio2000', 'kinova', 'panda'" in str(info.value)
