"""Buzz (quantizers and dry friction) from Python: the same numbers as ``stabound check``."""

import json

import pytest

import stabound

DEVICE = dict(mass=0.1, period=0.001, damping=10.0, delay_samples=1.0,
              stiffness=17000.0, wall_damping=30.0)


def flags(kw):
    return [x for k, v in kw.items() for x in ("--" + k.replace("_", "-"), v)]


@pytest.mark.parametrize("named", [
    dict(encoder_resolution=1e-5),
    dict(encoder_resolution=1e-5, coulomb_friction=0.02, static_friction=0.03),
    dict(force_resolution=0.01, coulomb_friction=0.005),
    dict(encoder_resolution=1e-5, coulomb_friction=0.02, hand_mass=0.02, hand_stiffness=50.0),
])
def test_buzz_matches_cli_json(cli_ok, named):
    # number for number, without an encoder too (continuous readings in a length unit made
    # from the stiffness as given): the JSON texts' numbers are equal, not merely close
    out = json.loads(cli_ok("check", *flags(DEVICE), *flags(named), "--format", "json"))
    got = stabound.buzz(**DEVICE, **named)
    assert got == out["buzz"]


def test_peaks_without_an_encoder_are_bit_for_bit(cli_ok):
    # a force step and friction only, on a stiffness whose round trip through alpha changes
    # its last bit: the peaks printed by both are the same text
    named = dict(force_resolution=0.01, coulomb_friction=0.005)
    for k in (17000.0, 12345.678, 9999.999):
        device = dict(DEVICE, stiffness=k)
        text = cli_ok("check", *flags(device), *flags(named), "--format", "json")
        want = [json.dumps(r["peak_counts"]) for r in json.loads(text)["buzz"]["runs"]]
        got = [json.dumps(r["peak_counts"]) for r in stabound.buzz(**device, **named)["runs"]]
        assert got == want, k


def test_buzz_sustained_on_a_wall_near_the_limit():
    r = stabound.buzz(**DEVICE, encoder_resolution=1e-5)
    assert r["sustained"] and r["peak_counts"] >= 1


def test_quantizers_are_keywords_of_buzz_only():
    with pytest.raises(TypeError, match="buzz"):
        stabound.check(**DEVICE, encoder_resolution=1e-5)
    with pytest.raises(ValueError, match="encoder resolution"):
        stabound.buzz(**DEVICE, encoder_resolution=-1.0)
    with pytest.raises(ValueError, match="name an encoder resolution"):
        stabound.buzz(**DEVICE)
    assert set(stabound._stabound.NONLINEAR_KEYWORDS) == {
        "encoder_resolution", "force_resolution", "coulomb_friction", "static_friction"}
