"""Certified ``alpha_max`` (`stabound.certify_alpha_max`) and certified lookup tables
(`stabound.table(..., certify=...)`) from Python: byte for byte the certificates of
`stabound amax ... --certify FILE` and `stabound table --conservative --certify FILE` for the
same inputs, with the same numbers; the standalone checker run as
`python -m stabound.verify_certificate FILE` accepts them and rejects a copy with a changed
claim (its CRC made to match again); bad input raises ValueError naming the fix."""

import json
import subprocess
import sys
import zlib

import pytest

import stabound
from stabound import Interval, OneOf
from conftest import rows


def verify(path):
    """The packaged checker on a file: (exit code, stdout, stderr)."""
    p = subprocess.run([sys.executable, "-m", "stabound.verify_certificate", str(path)],
                       capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def tampered(text, path):
    """Writes the certificate with the first hex digit after the point of its first claimed
    `alpha_lo` (or first table node) changed, the CRC computed again."""
    cert = json.loads(text)
    key = '"alpha_lo": "' if '"alpha_lo"' in text else '"alpha": [["'
    start = text.index(key) + len(key)
    dot = text.index(".", start) + 1
    digit = format((int(text[dot], 16) + 4) % 16, "x")
    body = text[:dot] + digit + text[dot + 1:]
    assert body != text and cert
    head = body[: body.rindex('  "crc32"')]
    path.write_text(head + '  "crc32": "%08x"\n}\n' % zlib.crc32(head.encode()))
    return path


def accepted_not_tampered(text, tmp_path, says):
    """The checker accepts the certificate text, saying says, and rejects it tampered."""
    path = tmp_path / "accepted.json"
    path.write_text(text)
    code, out, err = verify(path)
    assert code == 0 and says in out, out + err
    code, _, err = verify(tampered(text, tmp_path / "bad.json"))
    assert code == 1, err


def cli_amax(cli, tmp_path, *args):
    """`stabound amax ARGS --certify FILE`: the certificate and the one CSV row."""
    path = tmp_path / "cli.json"
    code, out, err = cli("amax", *args, "--certify", path)
    assert code == 0, err
    (row,) = rows(out)
    return path.read_text(), {k: float(v) for k, v in row.items()}


def test_paper_loop_is_the_command_lines_certificate(cli, tmp_path):
    path = tmp_path / "py.json"
    c = stabound.certify_alpha_max(0.5, 1.0, beta_min=0.0, beta_max=1.0, path=path)
    text, row = cli_amax(cli, tmp_path, "--delta", "0.5", "--d", "1", "--beta-min", "0",
                         "--beta-max", "1")
    assert c.certificate == text == path.read_text()
    # the same doubles as the command line's CSV (both round-trip exactly)
    assert (c.alpha_max, c.beta_at_max, c.alpha_lo, c.alpha_hi) == (
        row["alpha_max"], row["beta_at_max"], row["alpha_lo_certified"],
        row["alpha_hi_certified"])
    assert c.alpha_lo <= c.alpha_max < c.alpha_hi
    assert c.stiffness is None and c.members == 1 and c.set is None
    # independent of the certificate: alpha_max itself, and a wall above alpha_hi unstable
    assert c.alpha_max == stabound.alpha_max(0.5, 1.0, beta_min=0.0, beta_max=1.0).alpha_max
    assert stabound.check(c.alpha_hi * 1.01, c.beta_at_max, 0.5, 1.0).verdict == "unstable"
    code, out, err = verify(path)
    assert code == 0 and out.startswith("verified"), err
    code, _, err = verify(tampered(text, tmp_path / "bad.json"))
    assert code == 1, err


DEVICE = {"mass": 1.0, "period": 1e-3, "damping": 0.5, "delay_samples": 1.5,
          "wall_damping_min": 0.0, "wall_damping_max": 10.0, "hand_mass": 0.3,
          "hand_damping": 2.0, "hand_stiffness": 300.0, "velocity_filter_cutoff": 30.0}
FLAGS = ["--mass", "1", "--period", "0.001", "--damping", "0.5", "--delay-samples", "1.5",
         "--wall-damping-min", "0", "--wall-damping-max", "10", "--hand-mass", "0.3",
         "--hand-damping", "2", "--hand-stiffness", "300", "--velocity-filter-cutoff", "30"]


def test_loop_with_elements_is_the_command_lines_certificate(cli, tmp_path):
    c = stabound.certify_alpha_max(**DEVICE, always_gripped=True)
    text, row = cli_amax(cli, tmp_path, *FLAGS, "--always-gripped")
    assert c.certificate == text
    assert (c.stiffness, c.wall_damping, c.stiffness_lo, c.stiffness_hi) == (
        row["K_max_N_per_m"], row["B_at_max_Ns_per_m"], row["K_lo_certified_N_per_m"],
        row["K_hi_certified_N_per_m"])
    assert c.stiffness_lo <= c.stiffness < c.stiffness_hi
    assert json.loads(text)["stable_below"]["model"]["elements"] == ["hand", "filter"]
    path = tmp_path / "py.json"
    path.write_text(c.certificate)
    code, out, err = verify(path)
    assert code == 0, err


def test_a_hand_that_can_let_go_is_the_command_lines_set_certificate(cli, tmp_path):
    """The robust alpha_max of the device with and without the hand (the README's
    example), proved for both members."""
    device = {**DEVICE, "damping": 0.0, "delay_samples": 1, "wall_damping_max": 100.0,
              "mass": 0.1, "velocity_filter_cutoff": 50.0}
    c = stabound.certify_alpha_max(**device)
    flags = FLAGS[:]
    for flag, value in [("--mass", "0.1"), ("--damping", "0"), ("--delay-samples", "1"),
                        ("--wall-damping-max", "100"), ("--velocity-filter-cutoff", "50")]:
        flags[flags.index(flag) + 1] = value
    text, row = cli_amax(cli, tmp_path, *flags)
    assert c.certificate == text
    assert json.loads(text)["kind"] == "set"
    assert c.members == 2 and any("let go" in s or "hand" in s for s in c.set)
    assert (c.alpha_lo, c.alpha_hi) == (row["alpha_lo_certified"], row["alpha_hi_certified"])
    # the robust optimum is the package's own robust alpha_max
    assert c.alpha_max == stabound.alpha_max(**{k: v for k, v in device.items()}).alpha_max
    accepted_not_tampered(text, tmp_path, "2 devices")


def test_crossing_limits_are_the_command_lines_certificate_in_pieces(cli, tmp_path):
    """A compliant transmission of 2,000 or 5,000 N/m: the members' limits cross at the
    robust optimum, so the upper end is proved in pieces of the damping range, one member
    each. The command line's certificate, byte for byte; each member's own alpha_max lies
    above alpha_hi (neither alone is unstable there at every damping), while at 101 dampings
    across the range a member is unstable at alpha_hi by check."""
    device = {"mass": 0.1, "period": 1e-3, "damping": 0.0, "delay_samples": 1,
              "handle_mass": 0.02, "transmission_damping": 1.0}
    limits = {"wall_damping_min": 0.0, "wall_damping_max": 100.0}
    c = stabound.certify_alpha_max(**device, **limits,
                                   transmission_stiffness=OneOf(2000.0, 5000.0))
    flags = ["--mass", "0.1", "--period", "0.001", "--damping", "0", "--delay-samples", "1",
             "--handle-mass", "0.02", "--transmission-damping", "1", "--wall-damping-min", "0",
             "--wall-damping-max", "100", "--transmission-stiffness", "one-of:2000,5000"]
    text, row = cli_amax(cli, tmp_path, *flags)
    assert c.certificate == text and c.members == 2
    assert (c.alpha_lo, c.alpha_hi) == (row["alpha_lo_certified"], row["alpha_hi_certified"])
    assert c.alpha_lo <= c.alpha_max < c.alpha_hi <= c.alpha_max * (1 + 1.001e-4)
    pieces = json.loads(text)["pieces"]
    assert len(pieces) >= 2 and {p["member"] for p in pieces} == {0, 1}
    for k in (2000.0, 5000.0):
        own = stabound.alpha_max(**device, **limits, transmission_stiffness=k)
        assert own.stiffness > c.stiffness_hi, k
    for i in range(101):
        assert any(stabound.check(**device, stiffness=c.stiffness_hi, wall_damping=float(i),
                                  transmission_stiffness=k).verdict == "unstable"
                   for k in (2000.0, 5000.0)), i
    accepted_not_tampered(text, tmp_path, "pieces)")


@pytest.mark.parametrize("kwargs, says", [
    ({"delta": 0.5, "d": 1.0, "beta_min": 0.0}, "beta_max="),
    ({"delta": [[0.5, 1.0]], "d": 1.0, "beta_min": 0.0, "beta_max": 1.0}, "1-D array"),
    ({"mass": [0.1, 0.2], "period": 1e-3, "damping": 0.0, "delay_samples": 1,
      "beta_min": 0.0, "beta_max": 1.0}, "one number"),
    ({**DEVICE, "hand_mass": Interval(0.2, 0.3)}, "OneOf"),
    ({"delta": 0.5, "d": 1.0, "beta_min": 0.0, "beta_max": 1.0, "hand_mass": 0.3}, "physical"),
    ({"delta": -0.5, "d": 1.0, "beta_min": 0.0, "beta_max": 1.0}, "delta"),
])
def test_bad_input_to_certify_alpha_max_is_a_value_error(kwargs, says):
    with pytest.raises(ValueError, match=says):
        stabound.certify_alpha_max(**kwargs)


GRID = ([0.5, 0.75, 1.0], [1.0, 2.0])


def test_certified_table_is_the_command_lines(cli, tmp_path):
    path = tmp_path / "py.json"
    t = stabound.table(*GRID, conservative=True, certify=path)
    cli_path = tmp_path / "cli.json"
    code, out, err = cli("table", "--delta", "0.5,0.75,1", "--d", "1,2", "--conservative",
                         "--certify", cli_path)
    assert code == 0, err
    assert t.certificate == cli_path.read_text() == path.read_text()
    assert t.csv == out and t.grown is None
    assert f"by {t.boxes} boxes" in err
    # lowered only where a proof needed it (the conservative table computed apart)
    assert (t.alpha_max <= stabound.table(*GRID, conservative=True).alpha_max).all()
    assert "CERTIFIED" in t.c_header
    assert stabound.table(*GRID, conservative=True, certify=True).certificate == t.certificate
    code, out, err = verify(path)
    assert code == 0 and "4 cells" in out, err
    code, _, err = verify(tampered(t.certificate, tmp_path / "bad.json"))
    assert code == 1, err


def test_a_cell_the_budget_does_not_prove_grows_it_as_the_command_line(cli, tmp_path):
    """A device behind a 30 Hz low-pass (b = 80 to 82 N s/m): no lowering proves the cell
    within 2 boxes, so its budget grows to 8 before a node is lowered."""
    t = stabound.table(mass=0.1, period=1e-3, damping=[80.0, 82.0], delay_samples=[1],
                       velocity_filter_cutoff=30.0, conservative=True, certify=True,
                       certify_boxes=2)
    path = tmp_path / "cli.json"
    code, _, err = cli("table", "--mass", "0.1", "--period", "0.001", "--damping", "80,82",
                       "--delay-samples", "1", "--velocity-filter-cutoff", "30",
                       "--conservative", "--certify-boxes", "2", "--certify", path)
    assert code == 0, err
    assert t.certificate == path.read_text()
    assert t.grown == (1, 8) and "up to 8 boxes a cell" in err
    code, out, err = verify(path)
    assert code == 0, err


@pytest.mark.parametrize("kwargs, says", [
    ({"certify": True}, "conservative=True"),
    ({"conservative": True, "certify": True, "certify_boxes": 0}, "certify_boxes"),
    ({"conservative": True, "certify": True, "certify_boxes": 1.5}, "certify_boxes"),
    ({"conservative": True, "certify_boxes": 16}, "certify=True"),
    ({"conservative": True, "certify": 3}, "path"),
])
def test_bad_certify_arguments_of_table_are_value_errors(kwargs, says):
    with pytest.raises(ValueError, match=says):
        stabound.table(*GRID, **kwargs)


def test_a_table_the_certificate_does_not_cover_is_refused():
    """Interpolated delays are refused by the library, with what is covered."""
    with pytest.raises(ValueError, match="whole delays"):
        stabound.table([0.5, 1.0], [1.0, 1.5], conservative=True, certify=True)
