"""Loop elements through Python: the same verdicts and radii, bit for bit, as the command
line's `check` with the element flags, and the same refusals."""

import json

import numpy as np
import pytest

import stabound

DEVICE = dict(mass=0.1, period=1e-3, damping=0.0, delay_samples=1)
CLI_DEVICE = ["--mass", 0.1, "--period", 0.001, "--damping", 0, "--delay-samples", 1]

CASES = [
    (dict(velocity_filter_cutoff=3.18), ["--velocity-filter-cutoff", 3.18]),
    (dict(velocity_filter_samples=4), ["--velocity-filter-samples", 4]),
    (dict(hand_mass=0.2, hand_damping=2.0, hand_stiffness=300.0),
     ["--hand-mass", 0.2, "--hand-damping", 2, "--hand-stiffness", 300]),
    (dict(handle_mass=0.03, transmission_stiffness=2e5, transmission_damping=5.0, encoder="handle"),
     ["--handle-mass", 0.03, "--transmission-stiffness", 200000, "--transmission-damping", 5,
      "--encoder", "handle"]),
    (dict(actuator_time_constant=2e-4), ["--actuator-time-constant", 0.0002]),
]


def held(kw):
    """``always_gripped=True`` where ``kw`` names a hand: alpha_max and table then answer for
    the one loop with the hand, not for the set that includes the hand let go."""
    return dict(always_gripped=True) if "hand_mass" in kw else {}


@pytest.mark.parametrize("kw,flags", CASES)
def test_elements_match_the_command_line(cli_ok, kw, flags):
    walls = [(2000.0, 10.0), (10800.0, 42.5), (60000.0, 5.0)]
    r = stabound.check(**DEVICE, stiffness=[k for k, _ in walls],
                       wall_damping=[b for _, b in walls], **kw)
    for i, (k, b) in enumerate(walls):
        v = json.loads(cli_ok("check", *CLI_DEVICE, "--stiffness", k, "--wall-damping", b,
                              *flags, "--format", "json", "--radius"))
        assert r.verdict[i] == v["verdict"], (kw, k, b)
        assert r.spectral_radius[i] == v["spectral_radius"], (kw, k, b)


def test_the_filter_lag_example():
    # paper Section VIII: the 75 % wall is stable without the filter and not with 50 ms lag
    plain = stabound.check(**DEVICE, stiffness=10800.0, wall_damping=42.5)
    lagged = stabound.check(**DEVICE, stiffness=10800.0, wall_damping=42.5,
                            velocity_filter_cutoff=3.18)
    assert (plain.verdict, lagged.verdict) == ("stable", "unstable")


def test_element_refusals():
    with pytest.raises(ValueError, match="physical units"):
        stabound.check(0.1, 0.3, 0.5, 1.0, velocity_filter_cutoff=30.0)
    with pytest.raises(ValueError, match="Nyquist"):
        stabound.check(**DEVICE, stiffness=1e3, wall_damping=1.0, velocity_filter_cutoff=600.0)
    with pytest.raises(ValueError, match="both the handle mass and the coupling stiffness"):
        stabound.check(**DEVICE, stiffness=1e3, wall_damping=1.0, handle_mass=0.03)
    with pytest.raises(ValueError, match="one number"):
        stabound.check(mass=[0.1, 0.2], period=1e-3, damping=0.0, delay_samples=1,
                       stiffness=1e3, wall_damping=1.0, hand_mass=0.1)
    with pytest.raises(ValueError, match="encoder"):
        stabound.check(**DEVICE, stiffness=1e3, wall_damping=1.0, handle_mass=0.03,
                       transmission_stiffness=1e5, encoder="middle")
    assert np.isscalar(stabound.check(**DEVICE, stiffness=1e3, wall_damping=1.0,
                                      hand_mass=0.1).spectral_radius)


@pytest.mark.parametrize("kw,flags", CASES)
def test_alpha_max_of_a_loop_against_its_point_test(kw, flags):
    # the largest stable stiffness, read from the loop's boundary, against check with the
    # same elements: stable just below it at its damping, unstable just above
    a = stabound.alpha_max(**DEVICE, **kw, **held(kw))
    m, t = DEVICE["mass"], DEVICE["period"]
    assert a.stiffness == pytest.approx(a.alpha_max * m / t**2, rel=1e-12)
    below = stabound.check(**DEVICE, stiffness=a.stiffness * (1 - 1e-5),
                           wall_damping=a.wall_damping, **kw)
    above = stabound.check(**DEVICE, stiffness=a.stiffness * (1 + 1e-5),
                           wall_damping=[a.wall_damping * f for f in (0.98, 1.0, 1.02)], **kw)
    assert below.verdict == "stable", kw
    assert set(above.verdict.tolist()) == {"unstable"}, kw


@pytest.mark.parametrize("kw,flags", CASES)
def test_boundary_of_a_loop(kw, flags):
    b = stabound.boundary(**DEVICE, tol=1e-7, **kw)
    a = stabound.alpha_max(**DEVICE, **kw, **held(kw))
    assert b.alpha[0] == b.alpha[-1] and b.beta[0] == b.beta[-1]
    assert float(b.alpha.max()) == pytest.approx(a.alpha_max, abs=1e-6)
    # vertices pulled 1 % toward the region's centre are stable by the point test
    ca, cb = float(b.alpha.mean()), float(b.beta.mean())
    ia, ib = ca + 0.99 * (b.alpha - ca), cb + 0.99 * (b.beta - cb)
    m, t = DEVICE["mass"], DEVICE["period"]
    r = stabound.check(**DEVICE, stiffness=ia[::50] * m / t**2, wall_damping=ib[::50] * m / t, **kw)
    assert set(r.verdict.tolist()) == {"stable"}, kw


def test_loop_keywords_are_refused_with_normalized_values():
    with pytest.raises(ValueError, match="physical units"):
        stabound.alpha_max(0.0, 1.0, velocity_filter_cutoff=30.0)
    with pytest.raises(ValueError, match="missing period="):
        stabound.boundary(mass=0.1, damping=0.0, delay_samples=1, hand_mass=0.1)
    with pytest.raises(TypeError, match="hand_mas"):
        stabound.alpha_max(**DEVICE, hand_mas=0.1)


STEP_WALL = dict(stiffness=5000.0, wall_damping=20.0)
STEP_CLI_WALL = ["--stiffness", 5000, "--wall-damping", 20]
STEP_RUN = dict(duration=0.02, points_per_period=3)
STEP_CLI_RUN = ["--duration", 0.02, "--points-per-period", 3]


@pytest.mark.parametrize("kw,flags", CASES)
def test_step_with_elements_matches_the_command_line(cli_ok, kw, flags):
    # the same positions, bit for bit, as `stabound step` with the element flags, and the
    # summary's list of what was modelled
    r = stabound.step(**DEVICE, **STEP_WALL, **STEP_RUN, **kw)
    lines = cli_ok("step", *CLI_DEVICE, *STEP_CLI_WALL, *STEP_CLI_RUN, *flags).splitlines()[1:]
    assert [float(l.split(",")[3]) for l in lines] == r.time.tolist()
    assert [float(l.split(",")[4]) for l in lines] == r.position.tolist()
    summary = cli_ok("step", *CLI_DEVICE, *STEP_CLI_WALL, *STEP_CLI_RUN, *flags,
                     "--format", "summary")
    assert summary.rstrip().endswith("; elements: " + ", ".join(r.elements)), summary
    assert r.elements
    bare = stabound.step(**DEVICE, **STEP_WALL, **STEP_RUN)
    assert bare.elements == ()
    assert r.position.tolist() != bare.position.tolist(), kw


def test_step_final_value_and_margin_with_elements():
    # a hand's spring to ground shares the static deflection with the wall: F / (K + k_h)
    r = stabound.step(**DEVICE, stiffness=2000.0, wall_damping=10.0, duration=0.5,
                      hand_mass=0.05, hand_damping=1.0, hand_stiffness=500.0)
    assert r.final_value == pytest.approx(1.0 / 2500.0, rel=1e-13)
    assert r.verdict == "stable"
    assert float(r.samples[-1]) == pytest.approx(1.0 / 2500.0, rel=1e-6)
    # margin= takes the loop's alpha_max, as `stabound step --margin`
    kw = dict(velocity_filter_cutoff=100.0, hand_mass=0.05)
    a = stabound.alpha_max(**DEVICE, **kw, **held(kw))
    rs = stabound.step(**{**DEVICE, "damping": [0.0]}, margin=0.75, **kw)
    assert len(rs) == 1
    assert rs[0].alpha == pytest.approx(0.75 * a.alpha_max, rel=1e-12)
    assert rs[0].beta == pytest.approx(a.beta_at_max, rel=1e-12)
    assert rs[0].verdict == "stable"


def test_step_element_refusals():
    with pytest.raises(ValueError, match="hand mass"):
        stabound.step(**DEVICE, **STEP_WALL, hand_mass=-1.0)
    with pytest.raises(ValueError, match="Nyquist"):
        stabound.step(**DEVICE, **STEP_WALL, velocity_filter_cutoff=600.0)
    with pytest.raises(ValueError, match="encoder"):
        stabound.step(**DEVICE, **STEP_WALL, handle_mass=0.03, transmission_stiffness=1e5,
                      encoder="middle")
    with pytest.raises(TypeError, match="hand_mas"):
        stabound.step(**DEVICE, **STEP_WALL, hand_mas=0.1)


TABLE = dict(mass=0.1, period=1e-3, damping=[0.0, 1.0, 2.0, 4.0], delay_samples=[1.0, 2.0])
CLI_TABLE = ["--mass", 0.1, "--period", 0.001, "--damping", "0,1,2,4", "--delay-samples", "1,2"]


@pytest.mark.parametrize("kw,flags", [CASES[0], CASES[2], CASES[4]])
def test_table_with_elements_is_the_loops_alpha_max(cli_ok, kw, flags):
    t = stabound.table(**TABLE, **kw, **held(kw))
    bare = stabound.table(**TABLE)
    # every node is alpha_max of its own device's loop, by the one-device route
    for i, dl in enumerate(TABLE["delay_samples"]):
        for j, b in enumerate(TABLE["damping"]):
            one = stabound.alpha_max(mass=0.1, period=1e-3, damping=b, delay_samples=dl, **kw,
                                     **held(kw))
            # the same loop (the elements depend on mass and period alone): equal to the
            # rounding of the plant's normalization
            assert t.alpha_max[i, j] == pytest.approx(one.alpha_max, rel=1e-12), (kw, b, dl)
            assert t.stiffness[i, j] == pytest.approx(one.stiffness, rel=1e-12), (kw, b, dl)
    # the elements change every node by far more than the boundary's tolerance
    assert (np.abs(t.alpha_max - bare.alpha_max) > 1e-3 * bare.alpha_max).all(), kw
    assert "Loop elements modelled" in t.c_header and "Loop elements" not in bare.c_header
    # the command line with the element flags writes the same text
    # with a hand, both the command line's and Python's are for the one loop only when the
    # hand is always gripped (without it the set includes the hand let go)
    gripped = ["--always-gripped"] if "hand_mass" in kw else []
    assert cli_ok("table", *CLI_TABLE, *flags, *gripped) == t.csv
    header = cli_ok("table", *CLI_TABLE, *flags, *gripped, "--format", "c")
    assert header == t.c_header
    if gripped:
        assert "hand always on the handle" in t.c_header


def _not_stable_between_nodes(t, kw):
    """The queries between nodes (39 per row, none a node nor a point the construction
    tested) whose wall, by the lookup's procedure in physical units, is not stable for the
    loop with elements ``kw`` on that query's device."""
    bs = np.asarray(TABLE["damping"])
    bad = []
    for i, dl in enumerate(TABLE["delay_samples"]):
        for b in np.linspace(0.0, 4.0, 41)[1:-1] + 1e-3:
            k = float(np.interp(b, bs, t.stiffness[i]))
            bw = float(np.interp(b, bs, t.wall_damping[i]))
            r = stabound.check(mass=0.1, period=1e-3, damping=float(b), delay_samples=dl,
                               stiffness=k, wall_damping=bw, **kw)
            if r.verdict != "stable":
                bad.append((b, dl, k, bw))
    return bad


def test_conservative_table_with_elements_is_stable_between_nodes():
    kw = dict(velocity_filter_cutoff=30.0)
    assert _not_stable_between_nodes(stabound.table(**TABLE, conservative=True, **kw), kw) == []
    # the check can fail: the bare loop's conservative table, checked the same way with
    # the filter, has walls the filter makes unstable
    assert _not_stable_between_nodes(stabound.table(**TABLE, conservative=True), kw) != []


def test_table_elements_refusals():
    with pytest.raises(ValueError, match="physical units"):
        stabound.table([0.0, 1.0], [1.0], hand_mass=0.1)
    with pytest.raises(ValueError, match="hand mass"):
        stabound.table(**TABLE, hand_mass=-1.0)
    with pytest.raises(ValueError, match="Nyquist"):
        stabound.table(**TABLE, velocity_filter_cutoff=600.0)
    with pytest.raises(TypeError, match="hand_mas"):
        stabound.table(**TABLE, hand_mas=0.1)


def _stub_element_keywords():
    """The element keywords the type stubs list (the fields of `_LoopElements`), and the
    functions whose `**elements` take them."""
    import ast
    from pathlib import Path

    stub = Path(stabound.__file__).with_name("__init__.pyi")
    if not stub.exists():
        stub = Path(__file__).resolve().parents[1] / "stabound" / "__init__.pyi"
    tree = ast.parse(stub.read_text())
    fields, takers, buzz = set(), set(), set()
    for node in tree.body:
        if isinstance(node, ast.ClassDef) and node.name == "_LoopElements":
            fields = {s.target.id for s in node.body if isinstance(s, ast.AnnAssign)}
        if isinstance(node, ast.ClassDef) and node.name == "_Buzz":
            buzz = {s.target.id for s in node.body if isinstance(s, ast.AnnAssign)}
        if isinstance(node, ast.FunctionDef) and node.args.kwarg is not None:
            if "_LoopElements" in ast.unparse(node.args.kwarg.annotation):
                takers.add(node.name)
    return fields, takers, buzz


def test_stubs_list_every_element_keyword():
    """The stubs' element keywords are exactly the library's element list, and every
    function that takes loop elements takes them all."""
    keywords = set(stabound._stabound.ELEMENT_KEYWORDS)
    assert {"hand_mass", "motor_damping", "handle_damping", "velocity_filter_order"} <= keywords
    fields, takers, buzz = _stub_element_keywords()
    assert fields == keywords, (keywords - fields, fields - keywords)
    assert {"check", "alpha_max", "boundary", "table", "step"} <= takers
    nonlinear = set(stabound._stabound.NONLINEAR_KEYWORDS)
    assert {"encoder_resolution", "static_friction"} <= nonlinear
    assert buzz == nonlinear, (nonlinear - buzz, buzz - nonlinear)


def test_dampers_and_second_order_filter_keywords():
    """The new keywords reach the library: the handle's share 5 N s/m of 20 N s/m, given as
    either side, is the same loop; a second-order filter is not the first-order one, and an
    unknown keyword is a TypeError."""
    dev = dict(mass=0.1, period=1e-3, damping=20.0, delay_samples=1,
               handle_mass=0.03, transmission_stiffness=4e4)
    a = stabound.alpha_max(**dev, motor_damping=15.0)
    b = stabound.alpha_max(**dev, handle_damping=5.0)
    assert abs(a.alpha_max - b.alpha_max) <= 1e-12 * a.alpha_max
    assert a.alpha_max != stabound.alpha_max(**dev).alpha_max
    f = dict(mass=0.1, period=1e-3, damping=0.0, delay_samples=1, velocity_filter_cutoff=40.0)
    assert stabound.alpha_max(**f, velocity_filter_order=2).alpha_max != stabound.alpha_max(**f).alpha_max
    with pytest.raises(ValueError, match="velocity filter order"):
        stabound.alpha_max(**f, velocity_filter_order=3)
    with pytest.raises(TypeError):
        stabound.alpha_max(**f, velocity_filter_ordr=2)


def test_margin_wall_behind_a_wedge_matches_the_command_line(cli_ok):
    # an 8-sample average: 75 % of alpha_max at its damping is unstable, so the margin wall
    # is the fraction of a lower top at another damping, checked stable; warnings say so and
    # give the B >= 0 optimum beside the one that needs negative damping
    dev = dict(mass=0.1, period=1e-3, damping=50.0, delay_samples=0.999)
    with pytest.warns(UserWarning) as caught:
        r = stabound.alpha_max(**dev, velocity_filter_samples=8, margin=0.75)
    said = " ".join(str(w.message) for w in caught)
    assert "needs negative virtual damping" in said
    assert "the stiffest wall whose every stiffness" in said
    row = json.loads(cli_ok("amax", "--mass", 0.1, "--period", 0.001, "--damping", 50,
                            "--delay-samples", 0.999, "--velocity-filter-samples", 8,
                            "--margin", 0.75, "--format", "json"))[0]
    assert r.alpha_margin == row["alpha_margin"] and r.beta_margin == row["beta_margin"]
    assert r.stiffness_margin == row["K_margin_N_per_m"]
    assert r.beta_margin != r.beta_at_max
    wall_damping = r.beta_margin * dev["mass"] / dev["period"]
    c = stabound.check(**dev, stiffness=r.stiffness_margin, wall_damping=wall_damping,
                       velocity_filter_samples=8, method="state-space")
    assert c.verdict == "stable"


def test_paper_loop_says_when_its_wall_below_is_marginal():
    # delta = 100 with no delay: the wall a relative 1e-6 below alpha_max keeps a root about
    # 2e-10 inside the unit circle, so check calls it marginal; alpha_max of the paper's loop
    # says so as a loop with elements (and the command line) does, naming that wall
    with pytest.warns(UserWarning, match="within the marginal band") as caught:
        stabound.alpha_max(delta=100.0, d=0.0)
    said = str(caught[0].message)
    alpha = float(said.split("alpha = ")[1].split(",")[0])
    beta = float(said.split("beta = ")[1].split(",")[0])
    assert stabound.check(alpha, beta, 100.0, 0.0).verdict == "marginal"
    # an ordinary loop says nothing
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        stabound.alpha_max(delta=1.0, d=1.0)
