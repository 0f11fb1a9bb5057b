"""Certified boxes of walls on a loop with elements at fast sampling (1 ms, a hand and a
low-pass velocity filter), decided around their leaves' centres (Rouche on the unit circle):
the standalone checker replays the arcs, every decided leaf agrees with the eigenvalues of
the closed loop's state matrix at 60 digits (mpmath, from the certificate's inputs, in
test_certificate_elements) at its corners and seeded random walls inside it, and edits of
the arcs or the centre are rejected.
"""

import json
import random
import re

import pytest

from conftest import ROOT
from test_certificate import recrc, rejected, verify
from test_certificate_elements import state_matrix

mpmath = pytest.importorskip("mpmath")

DEVICE = ["--mass", "1", "--period", "0.001", "--damping", "0.5", "--delay-samples", "1.5",
          "--hand-mass", "0.3", "--hand-damping", "2", "--hand-stiffness", "300",
          "--velocity-filter-cutoff", "30"]


def certify_box(cli, tmp_path, stiffness, damping, *extra):
    path = tmp_path / "box.json"
    code, out, err = cli("check", *DEVICE, "--stiffness", stiffness, "--wall-damping", damping,
                         "--certify", path, *extra)
    assert code == 0, err
    return path.read_text(), out


def moduli(inputs, alpha, beta):
    """The moduli of the closed loop's eigenvalues at 60 digits."""
    with mpmath.workdps(60):
        s = state_matrix(dict(inputs, alpha=alpha.hex(), beta=beta.hex()))
        return [abs(v) for v in mpmath.eig(s, left=False, right=False)]


def agrees(cert, leaf, rng, random_walls):
    """The leaf's claim at its corners and random walls inside it, by the eigenvalues."""
    (a0, a1), (b0, b1) = ([float.fromhex(x) for x in leaf["box"][k]] for k in ("alpha", "beta"))
    walls = [(a0, b0), (a0, b1), (a1, b0), (a1, b1)]
    walls += [(rng.uniform(a0, a1), rng.uniform(b0, b1)) for _ in range(random_walls)]
    for a, b in walls:
        rs = moduli(cert["inputs"], a, b)
        if leaf["claim"] == "stable":
            assert max(rs) < 1, (a, b, max(rs))
        else:
            assert sum(r > 1 for r in rs) == leaf["outside"], (a, b, rs)


def test_narrow_box_at_fast_sampling_is_decided(cli, tmp_path):
    """K in [900, 900.01] N/m, B in [2, 2.01] N s/m: one leaf decided around its centre (the
    interval recursion over the box leaves 1024 leaves undecided), replayed by the checker,
    stable at 20 random walls inside by the 60-digit eigenvalues."""
    text, out = certify_box(cli, tmp_path, "900..900.01", "2..2.01")
    assert "verdict: stable for every wall of the box" in out
    cert = json.loads(text)
    (leaf,) = cert["leaves"]
    assert leaf["claim"] == "stable" and len(leaf["arcs"]) > 10
    code, checked, err = verify(tmp_path / "box.json")
    assert code == 0 and checked.startswith("verified: stable for every wall of the box"), err
    agrees(cert, leaf, random.Random(1), 20)


def test_boxes_across_and_past_the_boundary(cli, tmp_path):
    """A box across the boundary (near K = 2150 N/m) is not proved, its decided leaves on
    both sides agree with the eigenvalues; a box past it is proved unstable."""
    text, out = certify_box(cli, tmp_path, "1000..4000", "2..2.5", "--certify-leaves", "32")
    assert "verdict: not proved for the whole box" in out
    cert = json.loads(text)
    claim = cert["claim"]
    assert claim["stable"] > 0 and claim["unstable"] > 0, claim
    code, checked, err = verify(tmp_path / "box.json")
    assert code == 0 and checked.startswith("verified: not proved"), err
    rng = random.Random(2)
    decided = [leaf for leaf in cert["leaves"] if leaf["claim"] != "undecided"]
    assert any("arcs" in leaf for leaf in decided)
    for leaf in decided[::2]:
        agrees(cert, leaf, rng, 2)
    text, out = certify_box(cli, tmp_path, "4000..4500", "2..3")
    assert "verdict: unstable for every wall of the box" in out
    cert = json.loads(text)
    assert not rejected(text)
    for leaf in cert["leaves"]:
        agrees(cert, leaf, rng, 3)


def test_edits_of_the_arcs_and_the_centre_are_rejected(cli, tmp_path):
    """Any changed digit fails the CRC; with the CRC recomputed, a missing arc end, arcs that
    skip 2 or stop before 4, a centre moved to a corner, a leaf without its centre and arcs,
    and a stable leaf claimed unstable are rejected."""
    text, _ = certify_box(cli, tmp_path, "900..900.01", "2..2.01")
    assert not rejected(text)
    rng = random.Random(3)
    arcs = re.search(r'"arcs": \[([^\]]*)\]', text)
    for pos in rng.sample(range(arcs.start(1), arcs.end(1)), 10):
        if text[pos] in "0123456789abcdef" and text[pos - 1: pos + 1] != "0x":
            new = "1" if text[pos] != "1" else "2"
            assert rejected(text[:pos] + new + text[pos + 1:]), pos
    ends = arcs.group(1).split(", ")

    def with_arcs(e):
        return recrc(text.replace(arcs.group(1), ", ".join(e)))
    mid = len(ends) // 2
    assert rejected(with_arcs(ends[:mid] + ends[mid + 1:]))
    assert rejected(with_arcs([e for e in ends if e != '"0x1p+1"']))
    assert rejected(with_arcs(ends[:-1]))
    assert rejected(with_arcs(ends[:1] + ends[2:]))
    leaf = json.loads(text)["leaves"][0]
    centre = '"centre": {"alpha": "%s", "beta": "%s"}' % (leaf["centre"]["alpha"],
                                                          leaf["centre"]["beta"])
    assert rejected(recrc(text.replace(centre, '"centre": {"alpha": "%s", "beta": "%s"}' % (
        leaf["box"]["alpha"][0], leaf["box"]["beta"][0]))))
    plain = text.replace(", " + centre, "").replace(',\n     "arcs": [' + arcs.group(1) + "]", "")
    assert '"arcs"' not in plain and rejected(recrc(plain))
    claimed = text.replace('"claim": "stable"', '"claim": "unstable", "outside": 0', 1)
    assert rejected(recrc(claimed))


def test_the_checker_copies_are_identical():
    """tools/verify_certificate.py and the package's stabound/verify_certificate.py (run as
    `python -m stabound.verify_certificate`) are the same program, byte for byte."""
    tool = ROOT / "tools" / "verify_certificate.py"
    package = ROOT / "python" / "stabound" / "verify_certificate.py"
    assert tool.read_bytes() == package.read_bytes()
