"""Certified verdicts: `stabound check --certify` and the standalone checker
tools/verify_certificate.py (standard library only).

The certified claims are compared with an independent evaluation in mpmath at 60 digits
(the model's coefficients from the closed forms of docs/MODEL.md sections 2-3, the roots by
mpmath's polyroots), and every field of a certificate is tampered with.
"""

import importlib.util
import json
import math
import random
import re
import subprocess
import sys
import zlib

import pytest

from conftest import ROOT

mpmath = pytest.importorskip("mpmath")

CHECKER = ROOT / "tools" / "verify_certificate.py"
_spec = importlib.util.spec_from_file_location("verify_certificate", CHECKER)
CHECK = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(CHECK)


def verify(path):
    """Runs the checker on a file: (exit code, stdout, stderr)."""
    p = subprocess.run([sys.executable, str(CHECKER), str(path)], capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def certify(cli, tmp_path, alpha, beta, delta, d, *extra):
    """Writes a certificate for one wall: (its text or None when refused, the stderr)."""
    path = tmp_path / "cert.json"
    if path.exists():
        path.unlink()
    code, _, err = cli("check", "--alpha", repr(alpha), "--beta", repr(beta),
                       "--delta", repr(delta), "--d", repr(d), "--certify", path, *extra)
    if code != 0:
        assert code == 1 and not path.exists(), err
        return None, err
    return path.read_text(), err


def roots(alpha, beta, delta, d):
    """The roots of q at 60 digits, from the closed forms (an independent evaluation)."""
    # phi2 = (tau - phi1) / delta cancels about -log10(delta) digits: carry them too
    extra = int(-math.log10(delta)) + 10 if 0 < delta < 1 else 0
    with mpmath.workdps(60 + extra):
        a, b, dl, dd = (mpmath.mpf(x) for x in (alpha, beta, delta, d))
        n = int(math.floor(d))
        eps = dd - n

        def phi(tau):
            if dl == 0:
                return tau, tau**2 / 2
            p1 = -mpmath.expm1(-dl * tau) / dl
            return p1, (tau - p1) / dl

        c = mpmath.exp(-dl)
        p1, _ = phi(mpmath.mpf(1))
        g0v, g0x = phi(1 - eps)
        p1e, p2e = phi(eps)
        g1x = p2e + g0v * p1e
        g1v = mpmath.exp(-dl * (1 - eps)) * p1e
        m2, m1, m0 = g0x, p1 * g0v - c * g0x + g1x, p1 * g1v - c * g1x
        # highest power first: z^(n+2)(z-1)(z-c) + ((a+b) z - b)(m2 z^2 + m1 z + m0)
        top = [mpmath.mpf(1), -(1 + c), c] + [mpmath.mpf(0)] * (n + 2)
        wall = [m2 * (a + b), m1 * (a + b) - b * m2, m0 * (a + b) - b * m1, -b * m0]
        coeffs = top[:]
        for i, w in enumerate(wall):
            coeffs[len(coeffs) - 4 + i] += w
        if eps == 0:
            assert coeffs[-1] == 0
            coeffs = coeffs[:-1]
        return mpmath.polyroots(coeffs, maxsteps=400, extraprec=400)


def check_claim(text, alpha, beta, delta, d):
    """The certified claim agrees with the roots at 60 digits."""
    claim = json.loads(text)["claim"]
    rs = [abs(r) for r in roots(alpha, beta, delta, d)]
    rho = max(rs)
    if claim["verdict"] == "stable":
        assert rho < 1, (alpha, beta, delta, d, rho)
    elif claim["verdict"] == "unstable":
        assert sum(r > 1 for r in rs) == claim["outside"], (alpha, beta, delta, d, rs)
    else:
        assert abs(rho - 1) < float.fromhex(claim["eps"]), (alpha, beta, delta, d, rho)
    return claim["verdict"], rho


def test_random_walls_are_certified_and_agree(cli, tmp_path):
    """Seeded random walls on plants from no damping to heavy damping and delays up to 20
    samples: every certificate is accepted by the checker and its claim agrees with the
    independent roots; walls whose spectral radius is farther than 1e-9 from 1 are decided
    (stable or unstable, never refused)."""
    rng = random.Random(7)
    seen = set()
    for _ in range(40):
        delta = rng.choice([0.0, 1e-12, 1e-6, rng.uniform(0, 3), rng.uniform(3, 40)])
        d = rng.choice([0.0, 1.0, 0.3, 2.5, 7.75, rng.uniform(0, 20)])
        alpha, beta = rng.uniform(0, 2), rng.uniform(-1, 2)
        text, err = certify(cli, tmp_path, alpha, beta, delta, d)
        rho = max(abs(r) for r in roots(alpha, beta, delta, d))
        if text is None:
            assert abs(rho - 1) < 1e-9, (alpha, beta, delta, d, rho, err)
            continue
        assert verify(tmp_path / "cert.json")[0] == 0
        verdict, rho = check_claim(text, alpha, beta, delta, d)
        if abs(rho - 1) > 1e-9:
            assert verdict != "marginal", (alpha, beta, delta, d, rho)
        seen.add(verdict)
    assert seen >= {"stable", "unstable"}


@pytest.mark.parametrize("alpha,beta,delta,d", [
    (1e300, 0.0, 0.5, 1.0),        # a huge wall
    (-1e300, 1e300, 0.0, 2.5),     # huge and negative
    (0.1, 0.3, 1e-300, 1.0),       # delta near 0
    (0.1, 0.3, 5e-324, 0.5),       # the smallest positive delta
    (1e-3, 0.05, 1e9, 3.0),        # the largest delta: exp(-delta) underflows
    (2.0, 0.5, 800.0, 0.25),       # exp(-delta) below the smallest double
    (0.003, 0.2, 0.5, 30.0),       # a long delay
    (0.01, 0.2, 0.5, 25.5),        # a long fractional delay
    (0.3, 0.4, 0.0, 1e-300 + 1),   # d = 1 exactly (1 + 1e-300 rounds to 1)
    (0.1, 0.3, 0.5, 2.0 ** -1074), # the smallest positive fractional delay
    (0.0, 0.3, 0.5, 1.0),          # alpha = 0: z = 1 is a root, marginal
    (1e-6, -0.49, 0.5, 1.0),       # near the double-root corner (beta -> -delta, alpha -> 0)
    (12 - 8 * math.sqrt(2), 2 * math.sqrt(2) - 2, 0.0, 0.0),  # the published corner
])
def test_extreme_walls(cli, tmp_path, alpha, beta, delta, d):
    """Extreme inputs: certified (or refused only within 1e-9 of the circle), accepted by the
    checker, and in agreement with the 60-digit roots."""
    text, err = certify(cli, tmp_path, alpha, beta, delta, d)
    if text is None:
        rho = max(abs(r) for r in roots(alpha, beta, delta, d))
        assert abs(rho - 1) < 1e-9, err
        return
    code, out, err = verify(tmp_path / "cert.json")
    assert code == 0, err
    if abs(alpha) < 1e100:
        check_claim(text, alpha, beta, delta, d)
    else:
        assert json.loads(text)["claim"]["verdict"] == "unstable"


def chex(v):
    """v in the certificate's hex form (C99 %a, trailing zeros dropped)."""
    mant, exp = v.hex().split("p")
    if "." in mant:
        mant = mant.rstrip("0").rstrip(".")
    return mant + "p" + exp


def recrc(text):
    """The text with its CRC-32 recomputed: a deliberate edit, not a corruption."""
    head = text[: text.rindex('  "crc32"')]
    return head + '  "crc32": "%08x"\n}\n' % zlib.crc32(head.encode())


def rejected(text):
    """Whether the checker (loaded in this process, for speed) rejects the text."""
    try:
        CHECK.verify(CHECK.load(text.encode()))
    except CHECK.Reject:
        return True
    return False


@pytest.fixture
def certificates(cli, tmp_path):
    """A stable, an unstable and a marginal certificate."""
    out = {}
    for name, wall in [("stable", (0.1, 0.3, 0.5, 1.5)), ("unstable", (3.0, 0.3, 0.5, 1.0)),
                       ("marginal", (0.0, 0.3, 0.5, 1.0))]:
        text, err = certify(cli, tmp_path, *wall)
        assert text is not None, err
        assert json.loads(text)["claim"]["verdict"] == name
        out[name] = text
    return out


def test_every_changed_digit_is_rejected(certificates):
    """Each digit of each value (hex floats, counts, the degree, the CRC) changed in turn."""
    for text in certificates.values():
        assert not rejected(text)
        values = list(re.finditer(r'"(0x|-0x)[^"]*"|: (\d+)|"crc32": "[0-9a-f]+"', text))
        assert len(values) > 20
        for m in values:
            for pos in range(m.start(), m.end()):
                ch = text[pos]
                if ch in "0123456789abcdef" and text[pos - 1: pos + 1] != "0x":
                    new = "1" if ch != "1" else "2"
                    assert rejected(text[:pos] + new + text[pos + 1:]), (m.group(), pos)


def test_edits_that_break_the_proof_are_rejected(certificates):
    """With the CRC recomputed, every edit that makes the claim unproven is still rejected:
    the checker recomputes the enclosures and replays the recursion."""
    st, un, ma = certificates["stable"], certificates["unstable"], certificates["marginal"]
    swap = [
        (st, '"verdict": "stable"', '"verdict": "unstable", "outside": 1'),
        (un, '"verdict": "unstable", "outside": ', '"verdict": "stable", "x": '),
        (ma, '"verdict": "marginal", "eps": "0x1.12e0be826d695p-30"',
         '"verdict": "stable"'),
        (st, '"alpha": "0x1.999999999999ap-4"', '"alpha": "0x1.999999999999ap-2"'),
        (st, '"delta": "0x1p-1"', '"delta": "0x1p+1"'),
        (st, '"d": "0x1.8p+0"', '"d": "0x1p+0"'),
        (un, '"outside": 2}', '"outside": 3}'),
    ]
    for text, old, new in swap:
        assert old in text, old
        assert rejected(recrc(text.replace(old, new, 1))), (old, new)
    # each coefficient and each reflection: radius set to 0, midpoint moved by 1e-6
    data = json.loads(st)
    for kind in ["coefficients", "reflections"]:
        balls = data["coefficients"] if kind == "coefficients" else data["recursions"][0][kind]
        for b in balls:
            old = '{"mid": "%s", "rad": "%s"}' % (b["mid"], b["rad"])
            mid = float.fromhex(b["mid"])
            if mid in (0.0, 1.0):
                continue  # the exact leading 1 (and a 0): a zero radius still proves it
            moved = chex(mid + 1e-6 * max(abs(mid), 1e-3))
            for new in ['{"mid": "%s", "rad": "0x0p+0"}' % b["mid"],
                        '{"mid": "%s", "rad": "%s"}' % (moved, b["rad"])]:
                edited = st.replace(old, new, 1)
                if edited != st:
                    assert rejected(recrc(edited)), (kind, old, new)


def test_module_entry_point(tmp_path, certificates):
    """`python -m stabound.verify_certificate` runs the same checker."""
    try:
        import stabound  # noqa: F401  (the package's __init__ loads the compiled module)
    except ImportError:
        pytest.skip("the stabound package is not built (maturin develop)")
    path = tmp_path / "c.json"
    path.write_text(certificates["stable"])
    p = subprocess.run([sys.executable, "-m", "stabound.verify_certificate", str(path)],
                       capture_output=True, text=True)
    assert p.returncode == 0 and p.stdout.startswith("verified: stable"), p.stderr


def test_huge_wall_by_coefficient_bound(cli, tmp_path):
    """A huge wall is proven unstable by one coefficient above its binomial bound; naming a
    coefficient that is not above it (the leading 1) is rejected."""
    text, err = certify(cli, tmp_path, 1e300, 0.0, 0.0, 0.0)
    assert text is not None, err
    claim = json.loads(text)["claim"]
    assert claim == {"verdict": "unstable", "coefficient_above_binomial": 1}
    assert not rejected(text)
    assert rejected(recrc(text.replace('"coefficient_above_binomial": 1',
                                       '"coefficient_above_binomial": 3')))
    assert rejected(recrc(text.replace('"alpha": "0x1.7e43c8800759cp+996"', '"alpha": "0x1p+0"')))


def test_the_format_and_kind_are_checked(certificates):
    """A certificate of the earlier format (its version 1 header, the rest as written) is
    refused with a message that says to write it again; a changed version or an unknown or
    mismatched kind is refused too."""
    st = certificates["stable"]
    head = '"certificate": "stabound certificate 2",\n  "kind": "stability",'
    assert head in st and not rejected(st)
    old = recrc(st.replace(head, '"certificate": "stabound stability certificate 1",'))
    with pytest.raises(CHECK.Reject, match="format 1.*write it again"):
        CHECK.verify(CHECK.load(old.encode()))
    for new in ['"certificate": "stabound certificate 3",\n  "kind": "stability",',
                '"certificate": "stabound certificate 2",\n  "kind": "box",',
                '"certificate": "stabound certificate 2",\n  "kind": "wall",',
                '"certificate": "stabound certificate 2",']:
        assert rejected(recrc(st.replace(head, new))), new
