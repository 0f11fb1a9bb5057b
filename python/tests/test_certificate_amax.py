"""`amax --certify` on a grid of devices with loop elements: one certificate holding every
row's proof, replayed row by row by the standalone checker, and edits of one row (a changed
digit, a removed strip, a changed element parameter, a dropped row) rejected even with the
CRC recomputed."""

import json
import subprocess

import pytest

from conftest import executable
from test_certificate import CHECK, recrc, rejected, roots

# a 1 kg device at 1 ms, 1.5 samples of delay, two dampings; a hand that stays on the handle
# and a 30 Hz low-pass velocity filter; walls with 0 to 10 N s/m of damping
DEVICE = ["amax", "--mass", "1", "--period", "0.001", "--damping", "0.5,1",
          "--delay-samples", "1.5", "--wall-damping-min", "0", "--wall-damping-max", "10",
          "--hand-mass", "0.3", "--hand-damping", "2", "--hand-stiffness", "300",
          "--always-gripped", "--velocity-filter-cutoff", "30"]


@pytest.fixture(scope="module")
def grid(tmp_path_factory):
    """The certificate's text and the rows on stdout."""
    path = tmp_path_factory.mktemp("amax") / "amax.json"
    p = subprocess.run([executable(), *DEVICE, "--certify", str(path)], capture_output=True,
                       text=True)
    assert p.returncode == 0, p.stderr
    return path.read_text(), p.stdout


def edited(text, edit):
    """The certificate after `edit` on its JSON, written back with a recomputed CRC."""
    cert = json.loads(text)
    edit(cert)
    cert.pop("crc32")
    body = json.dumps(cert, indent=2)
    return recrc(body[:body.rindex("\n}")] + ',\n  "crc32": "00000000"\n}\n')


def test_grid_is_accepted_and_matches_the_rows(grid):
    text, out = grid
    proved = CHECK.verify(CHECK.load(text.encode()))
    assert proved.startswith("2 rows"), proved
    header, *rows = out.splitlines()
    cols = header.split(",")
    cert = json.loads(text)
    assert cert["claim"] == {"rows": 2}
    for row, line in zip(cert["rows"], rows):
        cells = dict(zip(cols, map(float, line.split(","))))
        claim = row["claim"]
        lo, hi = (float.fromhex(claim[k]) for k in ("alpha_lo", "alpha_hi"))
        assert (lo, hi) == (cells["alpha_lo_certified"], cells["alpha_hi_certified"])
        assert lo <= cells["alpha_max"] < hi
        assert row["stable_below"]["model"]["elements"] == ["hand", "filter"]


def test_a_changed_digit_is_rejected(grid):
    """The first fraction digit of a coefficient of the second row's stable wall."""
    text, _ = grid
    row = '"kind": "alpha_max"'
    second = text.index(row, text.index(row) + 1)
    i = text.index('"mid": "0x1.', second) + 12
    digit = "2" if text[i] == "1" else "1"
    assert rejected(recrc(text[:i] + digit + text[i + 1:]))


@pytest.mark.parametrize("row", [0, 1])
def test_a_removed_strip_is_rejected(grid, row):
    text, _ = grid
    assert rejected(edited(text, lambda c: c["rows"][row].pop("unstable_above")))

    def drop_leaf(c):
        c["rows"][row]["unstable_above"]["leaves"].pop()
    assert rejected(edited(text, drop_leaf))


def test_a_changed_element_parameter_is_rejected(grid):
    """The hand's mass ratio, in both proofs of a row (the same loop, but not the one the
    enclosures were computed for), and in one only (two loops)."""
    text, _ = grid

    def hand(c, parts):
        for part in parts:
            inputs = c["rows"][0][part]["inputs"]
            mu = float.fromhex(inputs["hand"]["mu_h"])
            inputs["hand"]["mu_h"] = CHECK.canonical_hex(mu * 1.001)
    assert rejected(edited(text, lambda c: hand(c, ["stable_below", "unstable_above"])))
    assert rejected(edited(text, lambda c: hand(c, ["unstable_above"])))


def test_a_dropped_row_is_rejected(grid):
    """A row removed without the claim's count changed, and an empty grid."""
    text, _ = grid
    assert rejected(edited(text, lambda c: c["rows"].pop()))
    assert rejected(edited(text, lambda c: c.update(rows=[], claim={"rows": 0})))


def test_normalized_grid_agrees_with_the_roots(cli, tmp_path):
    """A grid of the paper's loop (two deltas, two delays): each row's wall at alpha_lo is
    stable at its certified damping and alpha_hi is unstable at 11 dampings of the range,
    by the 60-digit roots; the checker accepts the grid."""
    path = tmp_path / "grid.json"
    code, out, err = cli("amax", "--delta", "0.5,1", "--d", "1,2.5", "--beta-min", "0",
                         "--beta-max", "0.1", "--certify", path)
    assert code == 0, err
    text = path.read_text()
    assert CHECK.verify(CHECK.load(text.encode())).startswith("4 rows")
    rows = json.loads(text)["rows"]
    for row, line in zip(rows, out.splitlines()[1:]):
        delta, d, amax, _, lo, hi = map(float, line.split(","))
        assert lo <= amax < hi
        beta = float.fromhex(row["stable_below"]["inputs"]["beta"])
        assert max(abs(r) for r in roots(lo, beta, delta, d)) < 1
        for k in range(11):
            assert max(abs(r) for r in roots(hi, k / 100, delta, d)) > 1, (delta, d, k)


@pytest.fixture(scope="module")
def capped(tmp_path_factory):
    """The certificate of the paper's loop at delta = 1, d = 1 for dampings 0 to 0.1: its
    upper end is proved for every stiffer wall, up to a cap and beyond."""
    path = tmp_path_factory.mktemp("capped") / "amax.json"
    p = subprocess.run([executable(), "amax", "--delta", "1", "--d", "1", "--beta-min", "0",
                        "--beta-max", "0.1", "--certify", str(path)], capture_output=True,
                       text=True)
    assert p.returncode == 0, p.stderr
    return path.read_text()


def test_every_stiffer_wall_is_unstable_by_the_roots(capped):
    """The checker proves the claim for alpha_hi and every stiffer wall; at 9 stiffnesses
    from alpha_hi to twice the cap (geometric steps) every one of 201 dampings of the range
    has a root outside the unit circle by the 60-digit roots."""
    proved = CHECK.verify(CHECK.load(capped.encode()))
    assert proved.endswith("stabilizes alpha_hi or any stiffer wall"), proved
    cert = json.loads(capped)
    hi = float.fromhex(cert["claim"]["alpha_hi"])
    cap = float.fromhex(cert["cap"]["alpha"])
    assert cert["claim"]["stiffer"] == "none stable" and hi < cap
    assert cert["unstable_above"]["inputs"]["alpha"] == [cert["claim"]["alpha_hi"],
                                                          cert["cap"]["alpha"]]
    for i in range(9):
        alpha = hi * (2 * cap / hi) ** (i / 8)
        for k in range(201):
            assert max(abs(r) for r in roots(alpha, k / 2000, 1.0, 1.0)) > 1, (alpha, k)


def test_an_edited_cap_or_box_is_rejected(capped):
    """A cap far lower (its condition then holds for stable walls) or higher (the box no
    longer reaches it), another rule, the cap removed with the claim kept, a removed leaf
    of the box, and a changed digit of a leaf's coefficient: each rejected with the CRC
    recomputed."""
    def cap_times(f):
        def edit(c):
            c["cap"]["alpha"] = CHECK.canonical_hex(float.fromhex(c["cap"]["alpha"]) * f)
        return edit

    def other_rule(c):
        c["cap"] = {"alpha": c["cap"]["alpha"], "rule": "coefficient",
                    "k": (c["cap"].get("k", 0) + 1) % 3, "sign": -1}
    assert not rejected(edited(capped, lambda c: None))
    for edit in [cap_times(0.5), cap_times(1.5), other_rule, lambda c: c.pop("cap"),
                 lambda c: c["unstable_above"]["leaves"].pop(3)]:
        assert rejected(edited(capped, edit))
    i = capped.index('"mid": "0x1.', capped.index('"unstable_above"')) + 12
    digit = "2" if capped[i] == "1" else "1"
    assert rejected(recrc(capped[:i] + digit + capped[i + 1:]))
