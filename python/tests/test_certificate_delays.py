"""Certified verdicts over a set of devices that differ in their delay (`check --certify
--delay-samples LO..HI`, the paper's loop): the checker tools/verify_certificate.py accepts
each certificate and rejects it once changed (a digit, a cell taken out, the interval
widened), and the claim agrees with an independent evaluation at many members of the set:
the closed loop's state matrix at 40 digits (mpmath) and its eigenvalues.
"""

import json
import zlib

import pytest

from stabound import verify_certificate as CHECK

mpmath = pytest.importorskip("mpmath")
from test_certificate_elements import state_matrix  # noqa: E402

DEVICE = ["--mass", "1", "--period", "1", "--damping", "0.5", "--wall-damping", "0.3"]


def certificate(cli, tmp_path, stiffness, delays, *extra):
    path = tmp_path / "delays.json"
    code, out, err = cli("check", *DEVICE, "--stiffness", stiffness, "--delay-samples", delays,
                         *extra, "--certify", path)
    assert code == 0, err
    return out, path.read_text()


def checked(text):
    """The checker's verdict on a certificate's text, or None when it rejects it."""
    try:
        return CHECK.verify(CHECK.load(text.encode()))
    except CHECK.Reject:
        return None


def sealed(cert):
    """The certificate as JSON text with a CRC-32 of its own (so that the checker's other
    tests, not the CRC, must catch an edit)."""
    body = json.dumps({k: v for k, v in cert.items() if k != "crc32"}, indent=2)[:-2] + ",\n"
    return body + '  "crc32": "%08x"\n}\n' % zlib.crc32(body.encode())


def radius(inputs, d):
    """The spectral radius of the paper's loop at the delay d (a member of the set)."""
    S = state_matrix({**inputs, "d": float(d).hex()})
    return max(abs(v) for v in mpmath.eig(S)[0])


@pytest.mark.parametrize("stiffness, delays, verdict", [
    ("0.1", "1..3", "stable"),     # alpha_max is 0.2 at d = 3, higher below
    ("0.1", "0..5", "stable"),
    ("1.5", "1..3", "unstable"),
    ("0.18", "1.25..2.75", "stable"),
])
def test_the_claim_holds_at_every_member_tried(cli, tmp_path, stiffness, delays, verdict):
    out, text = certificate(cli, tmp_path, stiffness, delays)
    cert = json.loads(text)
    assert cert["claim"]["verdict"] == verdict and f"{verdict} at every delay" in out
    assert checked(text).startswith(f"{verdict} at every delay")
    lo, hi = (float(x) for x in delays.split(".."))
    mpmath.mp.dps = 40
    members = [lo + (hi - lo) * k / 60 for k in range(61)]
    for d in members:
        r = radius(cert["inputs"], d)
        assert (r < 1) == (verdict == "stable"), (d, r)


def test_a_wall_that_crosses_the_boundary_is_not_proved(cli, tmp_path):
    # stable at d = 1, unstable at d = 3 (alpha_max 0.2 there): no claim for the whole set
    mpmath.mp.dps = 40
    out, text = certificate(cli, tmp_path, "0.25", "1..3", "--certify-leaves", "64")
    cert = json.loads(text)
    claim = cert["claim"]
    assert claim["verdict"] == "not proved" and "not proved" in out
    assert claim["stable"] > 0 and claim["unstable"] > 0
    assert checked(text).startswith("not proved")
    # each decided cell's claim holds at its ends and middle
    for cell in cert["leaves"]:
        if cell["claim"] == "undecided":
            continue
        e0, e1 = (float.fromhex(x) for x in cell["box"]["eps"])
        for eps in (e0, (e0 + e1) / 2, e1):
            r = radius(cert["inputs"], cell["box"]["n"] + eps)
            assert (r < 1) == (cell["claim"] == "stable"), (cell["box"]["n"], eps, r)


def test_changes_are_rejected(cli, tmp_path):
    _, text = certificate(cli, tmp_path, "0.1", "1..3")
    cert = json.loads(text)
    assert checked(text) and checked(sealed(cert))
    # a changed digit, caught by the CRC-32 and, resealed, by the recomputation
    i = text.index('"mid": "0x1.') + 12
    digit = "2" if text[i] == "1" else "1"
    assert checked(text[:i] + digit + text[i + 1:]) is None
    edits = []
    changed = json.loads(text)
    ball = changed["leaves"][0]["coefficients"][1]
    ball["mid"] = (float.fromhex(ball["mid"]) * 1.001).hex()
    edits.append(("a coefficient moved", changed))
    for k in range(len(cert["leaves"])):
        fewer = json.loads(text)
        del fewer["leaves"][k]
        edits.append((f"cell {k} taken out", fewer))
    for lo, hi in (("0x1p+0", "0x1.cp+1"), ("0x1p-1", "0x1.8p+1")):  # 1..3.5, 0.5..3
        wider = json.loads(text)
        wider["inputs"]["d"] = [lo, hi]
        edits.append((f"the delays widened to {lo}..{hi}", wider))
    last = json.loads(text)
    last["leaves"][-1]["box"]["eps"][1] = "0x1.cp-1"  # the last cell short of the end
    edits.append(("a cell narrowed", last))
    claim = json.loads(text)
    claim["claim"]["stable"] += 1
    edits.append(("the count changed", claim))
    arcs = json.loads(text)
    cell = next(c for c in arcs["leaves"] if "arcs" in c)
    cell["arcs"] = [cell["arcs"][0], cell["arcs"][-1]]
    edits.append(("the arcs thinned", arcs))
    for what, edited in edits:
        assert checked(sealed(edited)) is None, what
    # a delay interval's cells enclose the paper's loop by its own formulas, which take no
    # member's mass: inputs that state one are refused before any cell is replayed
    heavier = json.loads(text)
    heavier["inputs"] |= {"mass": "0x1p+1", "reference_mass": "0x1p+0"}
    with pytest.raises(CHECK.Reject, match="no elements or masses"):
        CHECK.wall_inputs(CHECK.load(sealed(heavier).encode()))


def test_sets_it_does_not_cover_are_refused(cli, tmp_path):
    path = tmp_path / "c.json"
    for extra in (["--delay-samples", "1..3", "--hand-mass", "0.3"],
                  ["--delay", "1..3"],
                  ["--delay-samples", "1", "--damping", "0.5..1"]):
        args = [a for a in DEVICE if a not in ("--damping", "0.5")] if "--damping" in extra \
            else DEVICE
        code, _, err = cli("check", *args, "--stiffness", "0.1", *extra, "--certify", path)
        assert code == 2 and "--delay-samples LO..HI" in err, (extra, err)
        assert not path.exists()


@pytest.mark.parametrize("stiffness, delays, leaves", [(0.1, (1, 3), None), (1.5, (1, 3), None),
                                                       (0.25, (1, 3), 64)])
def test_python_gives_the_command_lines_certificate(cli, tmp_path, stiffness, delays, leaves):
    import stabound

    extra = [] if leaves is None else ["--certify-leaves", str(leaves)]
    _, text = certificate(cli, tmp_path, repr(stiffness), f"{delays[0]}..{delays[1]}", *extra)
    c = stabound.certify(mass=1.0, period=1.0, damping=0.5, stiffness=stiffness,
                         wall_damping=0.3, delay_samples=stabound.Interval(*delays),
                         **({} if leaves is None else {"leaves": leaves}))
    assert c.certificate == text
    claim = json.loads(text)["claim"]
    assert (c.verdict, c.leaves) == (claim["verdict"], (claim["stable"], claim["unstable"],
                                                        claim["undecided"]))
