"""Where a sweep runs: scheduler addresses checked before any connection."""

from __future__ import annotations

import pytest

import polyell as pe
from polyell.studies.cluster import check_scheduler


@pytest.mark.parametrize(
    "scheduler",
    [None, "processes", "tcp://127.0.0.1:8786", "tcp://host", "tcp://[::1]:8786", "tls://h.org:1"],
)
def test_well_formed_schedulers_pass_unchanged(scheduler):
    assert check_scheduler(scheduler) == scheduler


@pytest.mark.parametrize(
    "scheduler",
    [
        "tcp://foo:bar",
        "tcp://[::1",
        "tcp://",
        "tcp://:8786",
        "tcp://h:0",
        "tcp://h:99999",
        "tcp://h:-1",
        "tcp://h:1/x",
        "tcp://h:1:2",
        "tcp://a b:1",
        "threads",
        "",
        "inproc://x",
        "\u00e9://x",
        5,
        b"tcp://h:1",
        ["processes"],
    ],
)
def test_malformed_schedulers_are_refused_with_the_expected_form(scheduler):
    with pytest.raises(pe.InputError, match="scheduler: expected None, 'processes' or a Dask"):
        check_scheduler(scheduler)
    with pytest.raises(pe.InputError, match="scheduler: expected None, 'processes' or a Dask"):
        pe.sweep(pe.robots.load("chiacchio2000"), [[0.1, 0.2, 0.3]], scheduler=scheduler)
