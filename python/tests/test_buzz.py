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
    out = json.loads(cli_ok("check", *flags(DEVICE), *flags(named), "--format", "json"))
    got = stabound.buzz(**DEVICE, **named)
    if "encoder_resolution" in named:
        # whole counts: equal
        assert got == out["buzz"]
        return
    # without an encoder the readings are continuous: the extension and the command line
    # were seen to differ in the last bits (2e-14 relative) of a peak
    assert got["sustained"] == out["buzz"]["sustained"]
    for g, w in zip(got["runs"], out["buzz"]["runs"]):
        assert (g["outcome"], g["period_samples"]) == (w["outcome"], w["period_samples"])
        assert abs(g["peak_counts"] - w["peak_counts"]) <= 1e-12 * max(1.0, abs(w["peak_counts"]))


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
