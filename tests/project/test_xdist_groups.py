"""The suite's ``--dist loadgroup`` groups what it is told to: tests marked ``xdist_group`` share
a workspace built once (the README's commands run in order in one folder, the small report is
built once), so a group split over two workers builds it twice, or finds it empty and fails by
chance. pytest-xdist marks a grouped test by its id (``...@group``) and schedules by that."""

import pytest


@pytest.mark.xdist_group("probe")
def test_a_grouped_test_carries_its_group_to_the_scheduler(request):
    if not getattr(request.config.option, "loadgroup", False):
        pytest.skip("only under the suite's --dist loadgroup (pyproject.toml's addopts); with -n 0 every test runs in one process and there are no groups to keep together")
    assert request.node.nodeid.endswith("@probe"), (
        "pytest-xdist groups nothing with this pytest (pytest-dev/pytest-xdist#1386): install the test extra's pytest")
