"""Finite sets of devices in Python (``stabound.OneOf``) against the command line's
``one-of:LIST``: the same rows, verdicts and regions, bit for bit; and the members' own
answers (a plain array of values, one result each) as the independent route.

The tool prints shortest round-trip floats, so ``float`` of its text is the exact double it
computed; ``==`` on floats below is exact comparison on purpose.
"""

import json
import warnings

import numpy as np
import pytest

import stabound
from stabound import Interval, OneOf
from conftest import rows

JITTER = dict(mass=1.0, period=1.0, damping=0.5)
JITTER_FLAGS = ["--mass", "1", "--period", "1", "--damping", "0.5"]
HELD = dict(mass=0.1, period=1e-3, damping=0.0, delay_samples=1)
HELD_FLAGS = ["--mass", "0.1", "--period", "1e-3", "--damping", "0", "--delay-samples", "1"]


def _same_robust_row(r, row):
    """A RobustAmax against the command line's robust row, field by field."""
    for value, key in [
        (r.alpha_max, "alpha_max"), (r.beta_at_max, "beta_at_max"),
        (r.alpha_verified, "alpha_verified"), (r.stiffness, "K_max"),
        (r.wall_damping, "B"), (r.stiffness_verified, "K_verified"),
    ]:
        assert value == float(row[key]), (key, value, row[key])
    assert r.members_examined == int(row["members_examined"])
    assert r.verification == row["verification"]
    assert " | ".join(r.binding) == row["binding"]
    assert "; ".join(r.set) == row["set"]


def test_one_of_is_a_tuple_of_its_values():
    s = OneOf(3, 1, 2)
    assert tuple(s) == (3, 1, 2) and repr(s) == "OneOf(3, 1, 2)"
    assert isinstance(s, tuple) and not isinstance(Interval(1, 3), OneOf)
    with pytest.raises(ValueError, match="at least one value"):
        OneOf()


def test_delay_list_alpha_max_is_the_command_lines_and_the_least_member(cli_ok):
    r = stabound.alpha_max(**JITTER, delay_samples=OneOf(1, 2, 3))
    assert isinstance(r, stabound.RobustAmax)
    [row] = rows(cli_ok("amax", *JITTER_FLAGS, "--delay-samples", "one-of:1,2,3"))
    _same_robust_row(r, row)
    assert r.verified and r.verification.startswith("checked for every member")
    assert r.members_examined == 3 and r.alpha_verified == r.alpha_max
    # independently: the members as an array of three single devices
    each = stabound.alpha_max(**JITTER, delay_samples=np.array([1.0, 2.0, 3.0]))
    least = int(np.argmin(each.stiffness))
    assert abs(r.stiffness - each.stiffness[least]) <= 1e-9 * each.stiffness[least]
    assert r.binding == (f"delay = {least + 1} samples",)
    # and the wall is stable on each member (1e-6 below the edge: clear of the marginal band)
    members = stabound.check(**JITTER, delay_samples=np.array([1.0, 2.0, 3.0]),
                             stiffness=r.stiffness_verified * (1 - 1e-6),
                             wall_damping=r.wall_damping)
    assert bool(members.stable.all())


def test_list_and_interval_together_is_the_command_lines(cli_ok):
    r = stabound.alpha_max(mass=Interval(0.9, 1.1), period=1.0, damping=0.5,
                           delay_samples=OneOf(1, 2))
    [row] = rows(cli_ok("amax", "--mass", "0.9..1.1", "--period", "1", "--damping", "0.5",
                        "--delay-samples", "one-of:1,2"))
    _same_robust_row(r, row)
    assert r.set == ("mass 0.9..1.1 kg", "delay 1 or 2 samples")


def test_hand_mass_list_is_the_command_lines(cli_ok):
    hand = dict(hand_damping=2.0, hand_stiffness=300.0, velocity_filter_cutoff=50.0)
    flags = ["--hand-damping", "2", "--hand-stiffness", "300", "--velocity-filter-cutoff", "50"]
    for gripped, extra in [(False, []), (True, ["--always-gripped"])]:
        r = stabound.alpha_max(**HELD, hand_mass=OneOf(0.5, 0.2), **hand,
                               always_gripped=gripped)
        [row] = rows(cli_ok("amax", *HELD_FLAGS, "--hand-mass", "one-of:0.5,0.2", *flags,
                            *extra))
        _same_robust_row(r, row)
        assert r.members_examined == (2 if gripped else 3)


@pytest.mark.parametrize("k", ["0.2", "0.25"])
def test_check_on_a_list_is_the_command_lines(cli_ok, k):
    r = stabound.check(**JITTER, delay_samples=OneOf(1, 2, 3), stiffness=float(k),
                       wall_damping=0.3)
    assert isinstance(r, stabound.SetCheck)
    j = json.loads(cli_ok("check", *JITTER_FLAGS, "--delay-samples", "one-of:1,2,3",
                          "--stiffness", k, "--wall-damping", "0.3", "--format", "json"))
    assert (r.verdict, r.stable, r.verification) == (
        j["verdict"], j["for_every_member"], j["verification"])
    assert r.failing_member == j.get("failing_member")
    # independently: the wall on each of the three members, and only those
    members = stabound.check(**JITTER, delay_samples=np.array([1.0, 2.0, 3.0]),
                             stiffness=float(k), wall_damping=0.3)
    assert r.stable == bool(members.stable.all())


def test_boundary_of_a_list_is_the_command_lines(cli_ok):
    with warnings.catch_warnings():
        # exact for a finite set: no warning that the members are a sample
        warnings.simplefilter("error")
        b, curves = stabound.boundary(mass=0.1, period=1e-3, damping=10.0,
                                      delay_samples=OneOf(1, 3), tol=1e-5, members=True)
    got = rows(cli_ok("boundary", "--mass", "0.1", "--period", "1e-3", "--damping", "10",
                      "--tol", "1e-5", "--delay-samples", "one-of:1,3"))
    assert [float(g["alpha"]) for g in got] == b.alpha.tolist()
    assert [float(g["beta"]) for g in got] == b.beta.tolist()
    assert [c.label for c in curves] == ["delay = 1 samples", "delay = 3 samples"]
    # the region is no larger than either member's own, to the curves' tolerance
    assert b.alpha.max() <= min(c.boundary.alpha.max() for c in curves) + 1e-5


def test_lists_are_refused_where_one_device_is_answered():
    with pytest.raises(TypeError, match="OneOf"):
        stabound.step(**JITTER, delay_samples=OneOf(1, 2), stiffness=0.1, wall_damping=0.1)
    with pytest.raises(ValueError, match="the delay list is empty"):
        # a subclass that skips the constructor's check still meets the library's refusal
        stabound.alpha_max(**JITTER, delay_samples=tuple.__new__(OneOf, ()))
