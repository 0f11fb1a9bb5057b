"""Sets of devices in Python (``stabound.Interval``, ``always_gripped=``) against the command
line's ``LO..HI`` and ``--always-gripped``: the same rows, tables and verdicts, bit for bit.

The tool prints shortest round-trip floats, so ``float`` of its text is the exact double it
computed; ``==`` on floats below is exact comparison on purpose.
"""

import json
import re

import numpy as np
import pytest

import stabound
from stabound import Interval
from conftest import rows

# the robust example of the model document: a delay that jitters between 1 and 3 samples
JITTER = dict(mass=1.0, period=1.0, damping=0.5)
JITTER_FLAGS = ["--mass", "1", "--period", "1", "--damping", "0.5", "--delay-samples", "1..3"]
# a light device held by a hand that can let go (the reproducer of the free-device wall)
HELD = dict(mass=0.1, period=1e-3, damping=0.0, delay_samples=1)
HAND = dict(hand_mass=0.3, hand_damping=2.0, hand_stiffness=300.0)
HELD_FLAGS = ["--mass", "0.1", "--period", "1e-3", "--damping", "0", "--delay-samples", "1",
              "--hand-mass", "0.3", "--hand-damping", "2", "--hand-stiffness", "300"]


def _same_robust_row(r, row, margin=False):
    """A RobustAmax against the command line's robust row, field by field."""
    pairs = [
        (r.alpha_max, "alpha_max"), (r.beta_at_max, "beta_at_max"),
        (r.alpha_verified, "alpha_verified"), (r.stiffness, "K_max"),
        (r.wall_damping, "B"), (r.stiffness_verified, "K_verified"),
    ]
    if margin:
        pairs += [(r.alpha_margin, "alpha_margin"), (r.beta_margin, "beta_margin"),
                  (r.stiffness_margin, "K_margin")]
    for value, key in pairs:
        assert value == float(row[key]), (key, value, row[key])
    assert r.members_examined == int(row["members_examined"])
    assert r.verification == row["verification"]
    assert " | ".join(r.binding) == row["binding"]
    assert "; ".join(r.set) == row["set"]


def test_delay_interval_alpha_max_is_the_command_lines(cli_ok):
    r = stabound.alpha_max(**JITTER, delay_samples=Interval(1, 3))
    assert isinstance(r, stabound.RobustAmax)
    [row] = rows(cli_ok("amax", *JITTER_FLAGS))
    _same_robust_row(r, row)
    # the set's optimum is below the single device's at the interval's low end
    one = stabound.alpha_max(**JITTER, delay_samples=1)
    assert r.alpha_max < one.alpha_max


def test_margin_on_a_set_is_the_command_lines(cli_ok):
    r = stabound.alpha_max(**JITTER, delay_samples=Interval(1, 3), margin=0.75)
    [row] = rows(cli_ok("amax", *JITTER_FLAGS, "--margin", "0.75"))
    _same_robust_row(r, row, margin=True)
    assert r.alpha_margin == 0.75 * r.alpha_verified


def test_hand_lets_go_unless_always_gripped(cli_ok):
    # without always_gripped the free device is a member, as on the command line
    r = stabound.alpha_max(**HELD, **HAND)
    assert isinstance(r, stabound.RobustAmax)
    [row] = rows(cli_ok("amax", *HELD_FLAGS))
    _same_robust_row(r, row)
    assert "let go" in "; ".join(r.set)
    free = stabound.alpha_max(**HELD)
    assert r.stiffness <= free.stiffness
    # always gripped: the one device with the hand, the command line's --always-gripped
    held = stabound.alpha_max(**HELD, **HAND, always_gripped=True)
    assert isinstance(held, stabound.AmaxPhysical)
    [row] = rows(cli_ok("amax", *HELD_FLAGS, "--always-gripped"))
    assert held.stiffness == float(row["K_max_N_per_m"])
    assert held.wall_damping == float(row["B_at_max_Ns_per_m"])


def test_element_interval(cli_ok):
    r = stabound.alpha_max(**HELD, hand_mass=Interval(0.2, 0.5), hand_damping=2.0,
                           hand_stiffness=300.0, always_gripped=True)
    flags = [f for f in HELD_FLAGS]
    flags[flags.index("--hand-mass") + 1] = "0.2..0.5"
    [row] = rows(cli_ok("amax", *flags, "--always-gripped"))
    _same_robust_row(r, row)
    assert "hand mass 0.2..0.5 kg" in "; ".join(r.set)


TABLE_FLAGS = ["--mass", "0.1", "--period", "1e-3", "--damping", "0,2,4", "--delay-samples", "1",
               "--hand-mass", "0.3", "--hand-damping", "2", "--hand-stiffness", "300"]


@pytest.mark.parametrize("gripped", [False, True])
def test_table_with_a_hand_is_the_command_lines(cli_ok, gripped):
    t = stabound.table(mass=0.1, period=1e-3, damping=[0.0, 2.0, 4.0], delay_samples=[1],
                       **HAND, always_gripped=gripped)
    extra = ["--always-gripped"] if gripped else []
    assert t.csv == cli_ok("table", *TABLE_FLAGS, *extra)
    assert t.c_header == cli_ok("table", *TABLE_FLAGS, *extra, "--format", "c")
    assert ("let go" in t.c_header) != gripped


def test_table_of_a_mass_interval_is_the_command_lines(cli, cli_ok):
    axes = dict(period=1.0, damping=[0.0, 0.5, 1.0], delay_samples=[1])
    t = stabound.table(mass=Interval(0.9, 1.1), **axes)
    assert t.csv == cli_ok("table", "--mass", "0.9..1.1", "--period", "1", "--damping", "0,0.5,1",
                           "--delay-samples", "1")
    # no node is stiffer than either end's own K_max at its damping
    for m in (0.9, 1.1):
        one = stabound.table(mass=m, **axes)
        assert (t.stiffness <= one.stiffness).all(), m
    # the table's axes are the damping and the delay: an interval of either is refused, as
    # the command line refuses it
    with pytest.raises(ValueError) as e:
        stabound.table(mass=1.0, period=1.0, damping=[0.0, 0.5], delay_samples=Interval(1, 3))
    code, _, err = cli("table", "--mass", "1", "--period", "1", "--damping", "0,0.5",
                       "--delay-samples", "1..3")
    assert code == 2 and "error: " + str(e.value) in err, err


@pytest.mark.parametrize("k", [0.1, 0.25])
def test_check_on_a_set_is_the_command_lines(cli_ok, k):
    r = stabound.check(**JITTER, delay_samples=Interval(1, 3), stiffness=k, wall_damping=0.3)
    assert isinstance(r, stabound.SetCheck)
    j = json.loads(cli_ok("check", *JITTER_FLAGS, "--stiffness", k, "--wall-damping", "0.3",
                          "--format", "json"))
    assert r.verdict == j["verdict"]
    assert r.stable == j["for_every_member"]
    assert r.verification == j["verification"]
    assert r.failing_member == j.get("failing_member")
    assert list(r.set) == j["set"]
    # independently: the wall on a dense set of delays in [1, 3], fractional ones included
    members = stabound.check(**JITTER, delay_samples=np.linspace(1.0, 3.0, 81), stiffness=k,
                             wall_damping=0.3)
    assert r.stable == bool(members.stable.all())


def test_intervals_are_refused_where_one_device_is_answered():
    with pytest.raises(TypeError, match="Interval"):
        stabound.step(mass=0.1, period=1e-3, damping=0.0, delay_samples=Interval(1, 2),
                      stiffness=1e3)
    with pytest.raises(TypeError, match="Interval"):
        stabound.alpha_max(0.0, Interval(1, 2))
    with pytest.raises(ValueError, match="physical units"):
        stabound.alpha_max(0.0, 1.0, hand_mass=Interval(0.1, 0.2))
    with pytest.raises(ValueError, match="inverted"):
        stabound.alpha_max(**JITTER, delay_samples=Interval(3, 1))
    # a plain tuple stays an array of devices, one result each
    two = stabound.alpha_max(**JITTER, delay_samples=(1, 3))
    assert two.alpha_max.shape == (2,)


def _as_flags(message):
    """A message of the package with its keywords spelled as the command line's flags."""
    return re.sub(r"\b([a-z_]+)=", lambda m: "--" + m.group(1).replace("_", "-"), message)


@pytest.mark.parametrize("call,args", [
    (lambda: stabound.alpha_max(mass=0.25, damping=1.0),
     ["amax", "--mass", "0.25", "--damping", "1"]),
    (lambda: stabound.table([0.0, 1.0], [1.0], delay=1e-3),
     ["table", "--delta", "0,1", "--d", "1", "--delay", "1e-3"]),
    (lambda: stabound.check(mass=0.25, period=1e-3, damping=1.0, delay=0.0),
     ["check", "--mass", "0.25", "--period", "1e-3", "--damping", "1", "--delay", "0"]),
    (lambda: stabound.check(0.1, 0.3),
     ["check", "--alpha", "0.1", "--beta", "0.3"]),
])
def test_device_resolution_is_one_message_in_two_spellings(cli, call, args):
    # the library resolves the device for both: the same message, keywords against flags
    with pytest.raises(ValueError) as e:
        call()
    code, _, err = cli(*args)
    assert code == 2 and err.strip() == "error: " + _as_flags(str(e.value)), (err, str(e.value))


# the device of the command line's robust-region example: 0.1 kg sampled at 1 kHz
REGION = dict(mass=0.1, period=1e-3, damping=10.0)
REGION_FLAGS = ["--mass", "0.1", "--period", "1e-3", "--damping", "10", "--tol", "1e-5"]


def _same_region_rows(b, got, mass, period):
    """A robust region's Boundary against the command line's rows of it, bit for bit in the
    normalized columns; the physical columns are the same numbers scaled by the device."""
    assert [float(g["alpha"]) for g in got] == b.alpha.tolist()
    assert [float(g["beta"]) for g in got] == b.beta.tolist()
    assert [g["piece"] for g in got] == b.piece.tolist()
    assert {(float(g["delta"]), float(g["d"])) for g in got} == {(b.delta, b.d)}
    k = np.array([float(g["stiffness_N_per_m"]) for g in got])
    w = np.array([float(g["wall_damping_Ns_per_m"]) for g in got])
    # the tool scales with its own rounding: a few ulps apart at most
    np.testing.assert_allclose(k, b.alpha * mass / period**2, rtol=1e-13, atol=1e-12)
    np.testing.assert_allclose(w, b.beta * mass / period, rtol=1e-13, atol=1e-12)


def _inside(b, fraction=0.99):
    """The region's vertices pulled 1 % toward its centroid (walls just inside its edge)."""
    ca, cb = float(b.alpha.mean()), float(b.beta.mean())
    return ca + fraction * (b.alpha - ca), cb + fraction * (b.beta - cb)


def test_boundary_of_a_delay_interval_is_the_command_lines(cli_ok):
    with pytest.warns(UserWarning, match="search over the whole set"):
        b = stabound.boundary(**REGION, delay_samples=Interval(1, 3), tol=1e-5)
    assert isinstance(b, stabound.Boundary)
    got = rows(cli_ok("boundary", *REGION_FLAGS, "--delay-samples", "1..3"))
    _same_region_rows(b, got, 0.1, 1e-3)
    # independently, numpy's roots of the model document's q(z): walls 1 % inside the
    # region's edge are stable at every delay in [1, 3], fractional delays included
    from test_published import q_coefficients
    ia, ib = _inside(b)
    for d in np.linspace(1.0, 3.0, 17):
        for a, be in zip(ia[::4], ib[::4]):
            rho = max(abs(np.roots(q_coefficients(a, be, b.delta, d))))
            assert rho < 1.0, (d, a, be, rho)
    # and the region is no larger than the worst member's: its stiffest wall is below the
    # three-sample device's
    three = stabound.boundary(b.delta, 3.0, tol=1e-5)
    assert b.alpha.max() <= three.alpha.max() + 1e-5


def test_boundary_of_a_hand_mass_interval_is_the_command_lines(cli_ok):
    hand = dict(hand_mass=Interval(0.2, 0.5), hand_damping=2.0, hand_stiffness=300.0)
    flags = [f for f in HELD_FLAGS]
    flags[flags.index("--hand-mass") + 1] = "0.2..0.5"
    for gripped in (False, True):
        extra = ["--always-gripped"] if gripped else []
        with pytest.warns(UserWarning, match="search over the whole set"):
            b = stabound.boundary(**HELD, **hand, tol=1e-5, always_gripped=gripped)
        got = rows(cli_ok("boundary", *flags, "--tol", "1e-5", *extra))
        _same_region_rows(b, got, 0.1, 1e-3)
    # independently of the region's search: walls 1 % inside its edge, checked member by
    # member (hands of 0.2 to 0.5 kg, fractional ones between the sampled three, and the hand
    # let go) by the point test of each loop's own state matrix
    with pytest.warns(UserWarning):
        b, curves = stabound.boundary(**HELD, **hand, tol=1e-5, members=True)
    assert [c.label for c in curves][-1] == "hand off"
    assert len(curves) == 4
    ia, ib = _inside(b)
    k, w = ia * 0.1 / 1e-3**2, ib * 0.1 / 1e-3
    free = stabound.check(**HELD, stiffness=k, wall_damping=w)
    assert set(free.verdict.tolist()) == {"stable"}
    for m in np.linspace(0.2, 0.5, 7):
        on = stabound.check(**HELD, stiffness=k, wall_damping=w, hand_mass=m, hand_damping=2.0,
                            hand_stiffness=300.0)
        assert set(on.verdict.tolist()) == {"stable"}, m
    # each member's curve is its own loop's boundary; the region lies within every one
    for c in curves:
        assert b.alpha.max() <= c.boundary.alpha.max() + 1e-5, c.label
    one = stabound.boundary(**HELD, hand_mass=0.5, hand_damping=2.0, hand_stiffness=300.0,
                            tol=1e-5)
    [at] = [c.boundary for c in curves if c.label.startswith("hand mass = 0.5")]
    assert at.alpha.tolist() == one.alpha.tolist() and at.beta.tolist() == one.beta.tolist()


def test_members_belong_to_a_set_and_a_set_to_the_alpha_beta_plane():
    with pytest.raises(ValueError, match="members=True"):
        stabound.boundary(**HELD, hand_mass=0.3, members=True)
    with pytest.raises(ValueError, match="alpha-beta plane"):
        stabound.boundary(**REGION, delay_samples=Interval(1, 3), method="bisect")
    with pytest.raises(ValueError, match="alpha-beta plane"):
        stabound.boundary(plane="delta-beta", alpha=0.5, d=1.0, mass=0.1, period=1e-3,
                          velocity_filter_cutoff=Interval(30, 60))


# a box of a hand's mass and damping, a cutoff and a lag that the box proof does not close
# in its budget (a narrower one, with or without the hand's damping, is proved)
PROVED3 = dict(mass=0.1, period=1e-3, damping=0.5, delay_samples=1,
               hand_mass=Interval(0.2, 0.5), hand_stiffness=300.0,
               velocity_filter_cutoff=Interval(30.0, 60.0),
               actuator_time_constant=Interval(3e-4, 6e-4))
SAMPLED = dict(PROVED3, hand_mass=Interval(0.1, 0.5), hand_damping=Interval(0.5, 3.0),
               velocity_filter_cutoff=Interval(20.0, 60.0),
               actuator_time_constant=Interval(2e-4, 8e-4))
SAMPLED_FLAGS = ["--mass", "0.1", "--period", "1e-3", "--damping", "0.5",
                 "--delay-samples", "1", "--hand-mass", "0.1..0.5", "--hand-stiffness", "300",
                 "--velocity-filter-cutoff", "20..60",
                 "--actuator-time-constant", "0.0002..0.0008", "--hand-damping", "0.5..3"]


def test_sampled_box_says_why_the_proof_stopped(cli_ok):
    r = stabound.alpha_max(**SAMPLED)
    row = rows(cli_ok("amax", *SAMPLED_FLAGS))[0]
    _same_robust_row(r, row)
    assert r.verification.startswith("sampling argument: ")
    assert r.proof_stopped.startswith("cell budget spent at 1024 cells with ")
    assert r.verification.endswith("the box proof stopped: " + r.proof_stopped + ")")
    # a proved or exact answer names no reason
    proved = stabound.alpha_max(**JITTER, delay_samples=Interval(1, 3))
    assert proved.verification.startswith("proved over the box")
    assert proved.proof_stopped is None
    three = stabound.alpha_max(**PROVED3)
    assert three.verification.startswith("proved over the box") and three.proof_stopped is None
    four = stabound.alpha_max(**PROVED3, hand_damping=Interval(1.0, 3.0))
    assert four.verification.startswith("proved over the box") and four.proof_stopped is None
    # one wall below the optimum: the check's reason is the command line's
    k, b = r.stiffness_verified * 0.99, r.wall_damping
    c = stabound.check(**SAMPLED, stiffness=k, wall_damping=b)
    j = json.loads(cli_ok("check", *SAMPLED_FLAGS, "--stiffness", repr(k),
                          "--wall-damping", repr(b), "--format", "json"))
    assert c.stable and c.verification == j["verification"]
    assert c.proof_stopped.startswith("cell budget spent at 1024 cells with ")
    assert j["verification"].endswith("the box proof stopped: " + c.proof_stopped + ")")
