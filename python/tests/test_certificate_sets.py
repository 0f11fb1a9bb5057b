"""Certified verdicts over a finite set of devices in Python (``stabound.certify`` with
``OneOf`` loop-element values) against the command line's ``one-of:LIST --certify``: the
same certificate, byte for byte; the standalone checker accepts it and rejects it tampered;
and each member's verdict agrees with an independent evaluation, the eigenvalues of the
member's closed-loop state matrix in mpmath at 40 digits (``test_certificate_elements``'s
reference, built from the member certificate's own inputs).
"""

import json
import subprocess
import sys
import zlib

import pytest

import stabound
from stabound import Interval, OneOf

mpmath = pytest.importorskip("mpmath")

from test_certificate_elements import moduli  # noqa: E402  (needs mpmath)

# a 0.1 kg device at 1 kHz, one sample of delay, held by a hand of 0.2 or 0.3 kg, its
# velocity filtered at 50 or 400 Hz: four members
DEVICE = dict(mass=0.1, period=1e-3, damping=0.0, delay_samples=1)
DEVICE_FLAGS = ["--mass", "0.1", "--period", "1e-3", "--damping", "0", "--delay-samples", "1"]
LISTS = dict(hand_mass=OneOf(0.2, 0.3), hand_damping=2.0, hand_stiffness=300.0,
             velocity_filter_cutoff=OneOf(50.0, 400.0))
LIST_FLAGS = ["--hand-mass", "one-of:0.2,0.3", "--hand-damping", "2", "--hand-stiffness",
              "300", "--velocity-filter-cutoff", "one-of:50,400"]


def cli_certificate(cli, tmp_path, *flags, lists=LIST_FLAGS):
    """The command line's certificate of ``check ... --certify`` (text) and its report."""
    path = tmp_path / "cli.json"
    code, out, err = cli("check", *DEVICE_FLAGS, *lists, *flags, "--certify", path)
    assert code == 0, err
    return path.read_text(), out


def checker(path):
    """``python -m stabound.verify_certificate PATH``: (exit code, stdout, stderr)."""
    p = subprocess.run([sys.executable, "-m", "stabound.verify_certificate", str(path)],
                       capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def sealed(cert):
    """The certificate as JSON text with a CRC-32 of its own, so that the checker's other
    tests, not the CRC, must catch an edit."""
    body = json.dumps({k: v for k, v in cert.items() if k != "crc32"}, indent=2)[:-2] + ",\n"
    return body + '  "crc32": "%08x"\n}\n' % zlib.crc32(body.encode())


def member_verdicts(text):
    """Each member's verdict, checked against its eigenvalues: stable with every modulus
    below 1, unstable with as many outside as its claim counts (or the largest above 1)."""
    verdicts = []
    for member in json.loads(text)["members"]:
        claim = member["claim"]
        rs = moduli(json.dumps(member))
        if claim["verdict"] == "stable":
            assert max(rs) < 1, rs
        elif "outside" in claim:
            assert claim["verdict"] == "unstable"
            assert sum(r > 1 for r in rs) == claim["outside"], rs
        else:
            assert claim["verdict"] == "unstable" and max(rs) > 1, rs
        verdicts.append(claim["verdict"])
    return verdicts


def members_are_the_combinations(text, hands):
    """The members' hand mass ratio and filter pole, in the order of the combinations (the
    hand outermost, the set holding each list's values in increasing order), from the lists
    given: mu_h = m_h / m, pole = exp(-2 pi f T)."""
    members = json.loads(text)["members"]
    seen = []
    for m in members:
        inputs = m["inputs"]
        mu = float.fromhex(inputs["hand"]["mu_h"])
        pole = float.fromhex(inputs["filter"]["pole"])
        seen.append((mu, pole))
    want = [(mh / 0.1, float(mpmath.exp(-2 * mpmath.pi * f * 1e-3)))
            for mh in sorted(hands) for f in (50.0, 400.0)]
    assert len(seen) == len(want)
    for (mu, pole), (mu0, pole0) in zip(seen, want):
        # the library rounds m_h / m and the pole once each in double precision
        assert abs(mu - mu0) <= 4e-16 * mu0 and abs(pole - pole0) <= 1e-15, (mu, pole)


# at 4000 N/m only the lighter hand with the slower filter fails; a list given in another
# order is the same set
@pytest.mark.parametrize("hands,stiffness", [
    ((0.2, 0.3), 1000.0), ((0.2, 0.3), 4000.0), ((0.3, 0.2), 4000.0), ((0.2, 0.3), 30000.0),
])
def test_one_wall_is_the_command_lines_and_each_member_agrees(cli, tmp_path, hands,
                                                              stiffness):
    path = tmp_path / "py.json"
    lists = dict(LISTS, hand_mass=OneOf(*hands))
    c = stabound.certify(**DEVICE, **lists, stiffness=stiffness, wall_damping=5.0, path=path)
    assert isinstance(c, stabound.SetCertified)
    flags = list(LIST_FLAGS)
    flags[1] = "one-of:" + ",".join(map(str, hands))
    text, report = cli_certificate(cli, tmp_path, "--stiffness", repr(stiffness),
                                   "--wall-damping", "5", lists=flags)
    assert c.certificate == text and path.read_text() == text
    code, out, err = checker(path)
    assert code == 0 and out.startswith("verified:"), err
    members_are_the_combinations(text, hands)
    verdicts = member_verdicts(text)
    assert c.members == 4 == len(verdicts)
    assert c.set == ("hand mass {} or {} kg".format(*sorted(hands)), "velocity filter cutoff 50 or 400 Hz",
                     "hand always on the handle (assumed: the free device is not a member)")
    # the set's verdict: stable when every member is, else the first unstable member's
    if all(v == "stable" for v in verdicts):
        assert c.verdict == "stable" and c.deciding_member is None
        assert "verdict: stable for every member of the set" in report
    else:
        first = verdicts.index("unstable")
        assert c.verdict == "unstable"
        hand, cutoff = [(h, f) for h in sorted(hands) for f in ("50", "400")][first]
        assert c.deciding_member == f"hand mass = {hand} kg; velocity filter cutoff = {cutoff} Hz"
        assert f"deciding member: {c.deciding_member}\n" in report
    assert json.loads(text)["claim"]["verdict"] == c.verdict


def test_verdicts_seen_cover_stable_and_unstable():
    """The walls above reach both verdicts (so the comparison above is not vacuous)."""
    seen = {stabound.certify(**DEVICE, **LISTS, stiffness=k, wall_damping=5.0).verdict
            for k in (1000.0, 30000.0)}
    assert seen == {"stable", "unstable"}


def test_box_of_walls_is_the_command_lines(cli, tmp_path):
    c = stabound.certify(**DEVICE, **LISTS, stiffness=Interval(500.0, 1000.0),
                         wall_damping=Interval(1.0, 5.0), leaves=64)
    text, report = cli_certificate(cli, tmp_path, "--stiffness", "500..1000",
                                   "--wall-damping", "1..5", "--certify-leaves", "64")
    assert c.certificate == text
    assert checker(tmp_path / "cli.json")[0] == 0
    cert = json.loads(text)
    assert cert["claim"]["verdict"] == c.verdict == "stable" and c.members == 4
    assert "at every wall of the box" in report
    # each member's box holds the physical box: alpha = K T^2 / m, beta = B T / m
    for m in cert["members"]:
        a = [float.fromhex(v) for v in m["inputs"]["alpha"]]
        b = [float.fromhex(v) for v in m["inputs"]["beta"]]
        assert a[0] <= 500.0 * 1e-6 / 0.1 and a[1] >= 1000.0 * 1e-6 / 0.1
        assert b[0] <= 1.0 * 1e-3 / 0.1 and b[1] >= 5.0 * 1e-3 / 0.1


def test_tampered_member_is_rejected(tmp_path):
    c = stabound.certify(**DEVICE, **LISTS, stiffness=1000.0, wall_damping=5.0)
    cert = json.loads(c.certificate)
    good = tmp_path / "good.json"
    good.write_text(sealed(cert))
    assert checker(good)[0] == 0
    # two members out of the combinations' order
    swapped = json.loads(c.certificate)
    swapped["members"][0], swapped["members"][1] = swapped["members"][1], swapped["members"][0]
    # a member's hand mass changed: that member is no longer the set's combination
    heavier = json.loads(c.certificate)
    heavier["members"][3]["inputs"]["hand"]["mu_h"] = float.hex(4.0)
    # a member's verdict changed
    claimed = json.loads(c.certificate)
    claimed["members"][2]["claim"]["verdict"] = "unstable"
    for name, bad in [("swapped", swapped), ("heavier", heavier), ("claimed", claimed)]:
        p = tmp_path / f"{name}.json"
        p.write_text(sealed(bad))
        code, out, err = checker(p)
        assert code != 0 and not out.startswith("verified:"), (name, out)


def test_intervals_are_refused_with_what_is_taken():
    wall = dict(stiffness=1000.0, wall_damping=5.0)
    with pytest.raises(ValueError, match="interval of a parameter is not certified: give its "
                                         "values as a list"):
        stabound.certify(**DEVICE, **dict(LISTS, hand_mass=Interval(0.2, 0.3)), **wall)
    with pytest.raises(ValueError, match="physical units"):
        stabound.certify(0.01, 0.05, **LISTS)


def test_lists_of_masses_and_delays_are_the_command_lines(cli, tmp_path):
    """Members of two masses and two delays besides the lists (sixteen): the command line's
    certificate, byte for byte, each member of the heavier mass stated with its mass and
    the reference mass, and the checker accepts it."""
    path = tmp_path / "py.json"
    device = dict(DEVICE, mass=OneOf(0.1, 0.12), delay_samples=OneOf(1, 2))
    c = stabound.certify(**device, **LISTS, stiffness=1000.0, wall_damping=5.0, path=path)
    assert isinstance(c, stabound.SetCertified) and c.members == 16
    cli_path = tmp_path / "cli.json"
    flags = ["--mass", "one-of:0.1,0.12", "--period", "1e-3", "--damping", "0",
             "--delay-samples", "one-of:1,2"]
    code, _, err = cli("check", *flags, *LIST_FLAGS, "--stiffness", "1000", "--wall-damping",
                       "5", "--certify", cli_path)
    assert code == 0, err
    assert c.certificate == cli_path.read_text() == path.read_text()
    inputs = [m["inputs"] for m in json.loads(c.certificate)["members"]]
    assert {float.fromhex(i["mass"]) for i in inputs} == {0.1, 0.12}
    assert {float.fromhex(i["reference_mass"]) for i in inputs} == {0.1}
    code, out, err = checker(path)
    assert code == 0 and out.startswith("verified:"), err


def test_refusals_name_no_command_line_flags():
    wall = dict(stiffness=1000.0, wall_damping=5.0)
    for kw in [dict(DEVICE, **dict(LISTS, hand_mass=Interval(0.2, 0.3)), **wall),
               dict(DEVICE, **dict(LISTS, delay_samples=Interval(1, 2)), **wall)]:
        with pytest.raises(ValueError) as e:
            stabound.certify(**kw)
        assert "--" not in str(e.value), e.value


def test_one_member_is_one_loops_certificate():
    """A list of one value is the one device: the certificate of one loop."""
    one = stabound.certify(**DEVICE, hand_mass=OneOf(0.2), hand_damping=2.0,
                           hand_stiffness=300.0, stiffness=1000.0, wall_damping=5.0)
    plain = stabound.certify(**DEVICE, hand_mass=0.2, hand_damping=2.0, hand_stiffness=300.0,
                             stiffness=1000.0, wall_damping=5.0)
    assert isinstance(one, stabound.Certified) and one == plain
