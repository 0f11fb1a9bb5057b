"""`stabound.certify`: the certified verdicts of `stabound check --certify` from Python (one
wall, or a box of walls given with `Interval`), byte for byte the command line's, replayed by
the standalone checker; and the checker's strictness on certificates of every kind: each
member of an object taken out or one added, and each entry of a list taken out, is rejected.
"""

import json
import random
import zlib

import pytest

import stabound
from stabound import Interval
from stabound import verify_certificate as CHECK

DELTA, D = 0.5, 1.0


def checked(text):
    """The checker's verdict on a certificate's text, or None when it rejects it."""
    try:
        return CHECK.verify(CHECK.load(text.encode()))
    except CHECK.Reject:
        return None


def from_cli(cli, tmp_path, *args):
    """The certificate `stabound check ARGS --certify FILE` writes."""
    path = tmp_path / "cli.json"
    code, _, err = cli("check", *args, "--certify", path)
    assert code == 0, err
    return path.read_text()


@pytest.mark.parametrize("wall, verdict", [((0.1, 0.3), "stable"), ((3.0, 0.3), "unstable"),
                                           ((0.0, 0.3), "marginal")])
def test_one_wall_is_the_command_lines_certificate(cli, tmp_path, wall, verdict):
    c = stabound.certify(*wall, DELTA, D)
    assert c.verdict == verdict and c.leaves is None
    text = from_cli(cli, tmp_path, "--alpha", repr(wall[0]), "--beta", repr(wall[1]),
                    "--delta", repr(DELTA), "--d", repr(D))
    assert c.certificate == text
    assert json.loads(text)["claim"]["verdict"] == verdict
    assert checked(c.certificate).startswith(verdict)


@pytest.mark.parametrize("alpha, beta, leaves, verdict", [
    ((0.1, 0.15), (0.2, 0.3), None, "stable"),
    ((3.0, 3.5), (0.3, 0.4), 64, "not proved"),
    ((1.8, 1.9), (0.0, 0.02), None, "unstable"),
    ((0.1, 0.2), 0.3, None, "stable"),  # a flat box: one damping
    ((0.1, 1.5), (0.25, 0.3), 100, "not proved"),  # across the boundary
])
def test_a_box_is_the_command_lines_certificate(cli, tmp_path, alpha, beta, leaves, verdict):
    side = [Interval(*x) if isinstance(x, tuple) else x for x in (alpha, beta)]
    path = tmp_path / "py.json"
    extra = {} if leaves is None else {"leaves": leaves}
    c = stabound.certify(*side, DELTA, D, path=path, **extra)
    flag = [f"{x[0]!r}..{x[1]!r}" if isinstance(x, tuple) else repr(x) for x in (alpha, beta)]
    text = from_cli(cli, tmp_path, "--alpha", flag[0], "--beta", flag[1], "--delta",
                    repr(DELTA), "--d", repr(D), "--certify-leaves", leaves or 1024)
    assert c.certificate == text == path.read_text()
    claim = json.loads(text)["claim"]
    assert (c.verdict, c.leaves) == (claim["verdict"], (claim["stable"], claim["unstable"],
                                                        claim["undecided"]))
    assert c.verdict == verdict and sum(c.leaves) <= (leaves or 1024)
    assert checked(c.certificate).startswith(verdict)


PHYSICAL = {"mass": 1.0, "period": 1e-3, "damping": 0.5, "stiffness": 1000.0,
            "wall_damping": 5.0}


@pytest.mark.parametrize("delay, elements", [
    ({"delay_samples": 1.5}, {"hand_mass": 0.3, "velocity_filter_cutoff": 30.0}),
    ({"delay_samples": 2}, {"hand_mass": 0.3, "hand_damping": 2.0, "hand_stiffness": 400.0,
                            "velocity_filter_cutoff": 50.0, "velocity_filter_order": 2}),
    ({"delay": 1.2e-3}, {}),
], ids=["hand-filter", "hand-butterworth", "paper"])
def test_a_physical_wall_is_the_command_lines_certificate(cli, tmp_path, delay, elements):
    kw = {**PHYSICAL, **delay, **elements}
    c = stabound.certify(**kw)
    flags = [x for k, v in kw.items() for x in ("--" + k.replace("_", "-"), repr(v))]
    text = from_cli(cli, tmp_path, *flags)
    assert c.certificate == text and c.leaves is None
    cert = json.loads(text)
    named = [k for k, prefix in (("hand", "hand_"), ("filter", "velocity_filter_"))
             if any(e.startswith(prefix) for e in elements)]
    assert cert["model"]["elements"] == named
    assert c.verdict == cert["claim"]["verdict"]
    assert checked(c.certificate).startswith(c.verdict)
    # the physical wall is the normalized one the certificate records
    ins = cert["inputs"]
    assert float.fromhex(ins["alpha"]) == pytest.approx(1000.0 * 1e-6, rel=1e-15)
    assert float.fromhex(ins["beta"]) == pytest.approx(5.0 * 1e-3, rel=1e-15)


def test_physical_refusals_say_what_is_taken():
    with pytest.raises(ValueError, match="physical units"):
        stabound.certify(0.1, 0.3, DELTA, D, hand_mass=0.3)  # elements need the device
    with pytest.raises(ValueError, match="missing"):
        stabound.certify(mass=1.0, period=1e-3, damping=0.5, stiffness=1e3, wall_damping=5.0)
    with pytest.raises(ValueError, match="normalized units"):
        stabound.certify(mass=1.0, period=1e-3, damping=0.5, stiffness=Interval(1e3, 2e3),
                         wall_damping=5.0, delay_samples=1)
    with pytest.raises(ValueError, match="paper's loop"):
        stabound.certify(Interval(0.1, 0.2), 0.3, DELTA, D, hand_mass=0.3)
    with pytest.raises(TypeError, match="unexpected keyword"):
        stabound.certify(**PHYSICAL, delay_samples=1, hand_mas=0.3)
    with pytest.raises(ValueError, match="delay_samples=Interval"):
        stabound.certify(**{**PHYSICAL, "damping": Interval(0.5, 1.0)}, delay_samples=1)
    with pytest.raises(ValueError, match="paper's loop"):  # the library's refusal
        stabound.certify(**PHYSICAL, delay_samples=Interval(1, 3), hand_mass=0.3)


def test_refusals_are_the_librarys_errors(tmp_path):
    with pytest.raises(ValueError, match="alpha"):
        stabound.certify(Interval(0.2, 0.1), 0.3, DELTA, D)  # hi below lo
    with pytest.raises(ValueError, match="leaves"):
        stabound.certify(Interval(0.1, 0.2), 0.3, DELTA, D, leaves=0)
    with pytest.raises(ValueError, match="delta"):
        stabound.certify(0.1, 0.3, -1.0, D)
    with pytest.raises(ValueError, match="band"):
        stabound.certify(0.1, 0.3, DELTA, D, marginal_band=0.7)
    with pytest.raises(TypeError):
        stabound.certify("0.1", 0.3, DELTA, D)
    with pytest.raises(OSError, match="cannot write"):
        stabound.certify(0.1, 0.3, DELTA, D, path=tmp_path / "no such dir" / "c.json")


def dumped(cert):
    """The certificate as JSON text with its CRC-32 (the checker reads any layout)."""
    body = json.dumps({k: v for k, v in cert.items() if k != "crc32"}, indent=2)[:-2] + ",\n"
    return body + '  "crc32": "%08x"\n}\n' % zlib.crc32(body.encode())


def places(node, path=()):
    """Every (path, container) of an object or list in the certificate's tree."""
    if isinstance(node, (dict, list)):
        yield path, node
        for k, v in (node.items() if isinstance(node, dict) else enumerate(node)):
            yield from places(v, path + (k,))


def edits(cert, rng, most):
    """Certificates with one member of an object taken out or one added, or one entry of a
    list taken out (not of the arcs, whose points a valid proof may do without), at most
    `most` of each kind drawn at random."""
    objects = [p for p, n in places(cert) if isinstance(n, dict)]
    lists = [p for p, n in places(cert) if isinstance(n, list) and n and p[-1] != "arcs"]
    members = [p + (k,) for p in objects for k in at(cert, p) if p + (k,) != ("crc32",)]
    entries = [p + (i,) for p in lists for i in range(len(at(cert, p)))]
    for what in (rng.sample(members, min(most, len(members)))
                 + rng.sample(entries, min(most, len(entries)))):
        edited = json.loads(json.dumps(cert))
        del at(edited, what[:-1])[what[-1]]
        yield f"without {what}", edited
    for where in rng.sample(objects, min(most, len(objects))):
        edited = json.loads(json.dumps(cert))
        at(edited, where)["extra"] = "0x1p+0"
        yield f"extra member in {where}", edited


def at(node, path):
    for k in path:
        node = node[k]
    return node


DEVICE = ["--mass", "1", "--period", "0.001", "--damping", "0.5", "--delay-samples", "1.5",
          "--hand-mass", "0.3", "--velocity-filter-cutoff", "30"]


# a hand that can let go: a set of two devices
HAND_SET = ["--mass", "0.1", "--period", "0.001", "--damping", "80,82", "--delay-samples", "1",
            "--velocity-filter-cutoff", "30", "--hand-mass", "0.3"]


@pytest.mark.parametrize("args, most", [
    (["check", "--alpha", "0.1", "--beta", "0.3", "--delta", "0.5", "--d", "1.5"], 8),
    (["check", *DEVICE, "--stiffness", "1000", "--wall-damping", "5"], 8),
    (["check", "--alpha", "0.1..0.2", "--beta", "0.3", "--delta", "0.5", "--d", "1"], 8),
    (["check", *DEVICE, "--stiffness", "900..1000", "--wall-damping", "4..5"], 8),
    (["amax", "--delta", "0.5", "--d", "1", "--beta-min", "0", "--beta-max", "0.1"], 4),
    (["table", "--delta", "0.9,1", "--d", "1", "--conservative", "--certify-boxes", "16"], 3),
    (["table", *HAND_SET, "--conservative", "--certify-boxes", "16"], 2),
], ids=["wall", "wall-elements", "box", "box-elements", "alpha_max", "table", "table-set"])
def test_every_member_and_entry_is_checked(cli, tmp_path, args, most):
    """The certificate is accepted as written and laid out anew; each edit (at most `most`
    of each kind, drawn at random) is rejected."""
    path = tmp_path / "c.json"
    code, _, err = cli(*args, "--certify", path)
    assert code == 0, err
    cert = json.loads(path.read_text())
    assert checked(path.read_text()) and checked(dumped(cert))
    for what, edited in edits(cert, random.Random(1), most):
        assert checked(dumped(edited)) is None, what
