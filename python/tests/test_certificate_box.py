"""Certified boxes of walls: `stabound check --alpha LO..HI --beta LO..HI --certify` and the
standalone checker's replay of every leaf.

Each decided leaf's claim is compared with the roots at 60 digits (mpmath, from the closed
forms, in test_certificate) at its corners and centre; the leaves must cover the box exactly,
and edits of a leaf (its bounds, its claim, its enclosures, a missing leaf) are rejected.
"""

import json
import re

import pytest

from test_certificate import CHECK, recrc, rejected, roots, verify

DELTA, D = 0.5, 1.0


def certify_box(cli, tmp_path, alpha, beta, *extra, delta=DELTA, d=D):
    """Writes a box certificate: its text and the report on stdout."""
    path = tmp_path / "box.json"
    code, out, err = cli("check", "--alpha", alpha, "--beta", beta, "--delta", repr(delta),
                         "--d", repr(d), "--certify", path, *extra)
    assert code == 0, err
    return path.read_text(), out


def corners(leaf):
    (a0, a1), (b0, b1) = ([float.fromhex(x) for x in leaf["box"][k]] for k in ("alpha", "beta"))
    return [(a0, b0), (a0, b1), (a1, b0), (a1, b1), ((a0 + a1) / 2, (b0 + b1) / 2)]


def agrees(leaf, delta=DELTA, d=D):
    """The leaf's claim holds at its corners and centre by the 60-digit roots."""
    for a, b in corners(leaf):
        rs = [abs(r) for r in roots(a, b, delta, d)]
        if leaf["claim"] == "stable":
            assert max(rs) < 1, (leaf["box"], a, b)
        else:
            assert sum(r > 1 for r in rs) == leaf["outside"], (a, b, rs)


def test_box_inside_the_region_is_certified(cli, tmp_path):
    """A box well inside the stable region: every leaf stable, the checker agrees, and the
    claim holds at every leaf's corners by the independent roots."""
    text, out = certify_box(cli, tmp_path, "0.1..0.15", "0.2..0.3")
    assert "verdict: stable for every wall of the box" in out
    cert = json.loads(text)
    assert cert["claim"]["verdict"] == "stable"
    code, checked, err = verify(tmp_path / "box.json")
    assert code == 0 and checked.startswith("verified: stable for every wall of the box"), err
    for leaf in cert["leaves"][::5]:
        agrees(leaf)


def test_box_across_the_boundary_is_not_certified(cli, tmp_path):
    """A box that crosses the boundary is never claimed stable; its decided leaves (stable
    on one side, unstable on the other) agree with the independent roots."""
    text, out = certify_box(cli, tmp_path, "0.1..1.5", "0.25..0.3", "--certify-leaves", "300")
    assert "verdict: not proved for the whole box" in out
    cert = json.loads(text)
    claim = cert["claim"]
    assert claim["verdict"] == "not proved" and claim["stable"] > 0 and claim["unstable"] > 0
    assert len(cert["leaves"]) <= 300
    code, checked, err = verify(tmp_path / "box.json")
    assert code == 0 and checked.startswith("verified: not proved"), err
    decided = [leaf for leaf in cert["leaves"] if leaf["claim"] != "undecided"]
    for leaf in decided[::5]:
        agrees(leaf)
    # a box entirely past the boundary is proved unstable
    text, out = certify_box(cli, tmp_path, "3..3.2", "0.1..0.12")
    assert "verdict: unstable for every wall of the box" in out
    assert not rejected(text)


@pytest.fixture
def box(cli, tmp_path):
    text, _ = certify_box(cli, tmp_path, "0.1..0.12", "0.25..0.3", "--certify-leaves", "64")
    assert json.loads(text)["claim"]["verdict"] == "stable"
    return text


def test_changed_leaf_bounds_are_rejected(box):
    """With the CRC recomputed: a leaf's bound moved (gap or overlap), a leaf left out, or
    the box widened beyond its leaves are all rejected as not covering the box."""
    assert not rejected(box)
    cert = json.loads(box)
    first = cert["leaves"][0]
    lo, hi = first["box"]["alpha"]
    width = float.fromhex(hi) - float.fromhex(lo)
    # shrink (a gap) and grow (an overlap)
    for new in [CHECK.canonical_hex(float.fromhex(hi) + s * width / 4) for s in (-1, 1)]:
        edited = box.replace('"alpha": ["%s", "%s"]' % (lo, hi),
                             '"alpha": ["%s", "%s"]' % (lo, new), 1)
        assert edited != box
        assert rejected(recrc(edited)), new
    # the last leaf left out
    start = box.rindex(',\n    {"box"')
    end = box.index("]}", box.index('"reflections"', start)) + 2
    assert rejected(recrc(box[:start] + box[end:]))
    # the box's own bound moved
    top = cert["inputs"]["beta"][1]
    assert rejected(recrc(box.replace('"%s"]' % top, '"0x1.4p-1"]', 1)))


def test_changed_claims_and_enclosures_are_rejected(box):
    """A leaf's claim, a coefficient's radius, a reflection ball or the box's counts edited
    (CRC recomputed) are rejected; any changed digit without the CRC too."""
    assert rejected(recrc(box.replace('"claim": "stable"', '"claim": "unstable", "outside": 1',
                                      1)))
    assert rejected(recrc(box.replace('"claim": "stable"', '"claim": "undecided"', 1)))
    m = re.search(r'"rad": "(0x1\.[0-9a-f]+p-\d+)"', box)
    assert rejected(recrc(box[:m.start(1)] + "0x0p+0" + box[m.end(1):]))
    refl = box.index('"reflections": [')
    m = re.compile(r'"mid": "(-?0x1\.[0-9a-f]+p-\d+)"').search(box, refl)
    moved = float.fromhex(m.group(1)) * 1.001
    assert rejected(recrc(box[:m.start(1)] + CHECK.canonical_hex(moved) + box[m.end(1):]))
    n = json.loads(box)["claim"]["stable"]
    assert rejected(recrc(box.replace('"stable": %d' % n, '"stable": %d' % (n + 1))))
    for pos in range(0, len(box), 97):
        if box[pos] in "0123456789abcdef":
            assert rejected(box[:pos] + ("1" if box[pos] != "1" else "2") + box[pos + 1:])


def test_box_with_elements_in_physical_units(cli, tmp_path):
    """A box of walls in N/m and N s/m on a device with a hand and a velocity filter: the
    certificate names the elements and the checker accepts its stable claim."""
    path = tmp_path / "box.json"
    code, out, err = cli("check", "--mass", "1", "--period", "0.01", "--damping", "5",
                         "--delay-samples", "1", "--stiffness", "100..101",
                         "--wall-damping", "5..5.1", "--hand-mass", "0.3",
                         "--velocity-filter-cutoff", "30", "--certify", path)
    assert code == 0 and "stable for every wall of the box" in out, (out, err)
    text = path.read_text()
    assert '"elements": ["hand", "filter"]' in text
    code, checked, err = verify(path)
    assert code == 0 and "stable for every wall" in checked, err


def test_amax_enclosure_is_certified(cli, tmp_path):
    """`amax --certify`: the checker accepts the enclosure, which holds the reported
    alpha_max; by the 60-digit roots the wall below is stable and every sampled damping of
    the range leaves the stiffness above unstable; a moved bound is rejected."""
    path = tmp_path / "amax.json"
    code, out, err = cli("amax", "--delta", "0.5", "--d", "1", "--beta-min", "0",
                         "--beta-max", "1", "--certify", path)
    assert code == 0, err
    _, row = out.splitlines()
    _, _, amax, beta_at, lo, hi = map(float, row.split(","))
    assert lo <= amax < hi
    code, checked, err = verify(path)
    assert code == 0 and checked.startswith("verified: alpha_max in"), err
    assert max(abs(r) for r in roots(lo, beta_at, 0.5, 1.0)) < 1
    for k in range(11):
        assert max(abs(r) for r in roots(hi, k / 10, 0.5, 1.0)) > 1, k / 10
    text = path.read_text()
    claim = json.loads(text)["claim"]
    moved = CHECK.canonical_hex(float.fromhex(claim["alpha_hi"]) * 0.99)
    assert rejected(recrc(text.replace('"alpha_hi": "%s"' % claim["alpha_hi"],
                                       '"alpha_hi": "%s"' % moved)))


def test_a_tables_leaves_claim_stable(cli, tmp_path):
    """A certified table's leaves each claim stable and its claim counts them: with the CRC
    recomputed, a leaf claimed unstable or undecided, a leaf's claim left out, or the count
    of leaves changed is rejected."""
    path = tmp_path / "table.json"
    code, _, err = cli("table", "--delta", "0.9,1", "--d", "1", "--conservative",
                       "--certify-boxes", "16", "--certify", path)
    assert code == 0, err
    text = path.read_text()
    assert not rejected(text)
    n = json.loads(text)["claim"]["leaves"]
    for old, new in [('"claim": "stable",', '"claim": "unstable", "outside": 1,'),
                     ('"claim": "stable",', '"claim": "undecided",'),
                     (', "claim": "stable",', ','),
                     ('"leaves": %d}' % n, '"leaves": %d}' % (n + 1))]:
        assert old in text, old
        assert rejected(recrc(text.replace(old, new, 1))), new
