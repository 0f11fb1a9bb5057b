"""Loop elements through Python: the same verdicts and radii, bit for bit, as the command
line's `check` with the element flags, and the same refusals."""

import json

import numpy as np
import pytest

import stabound

DEVICE = dict(mass=0.1, period=1e-3, damping=0.0, delay_samples=1)
CLI_DEVICE = ["--mass", 0.1, "--period", 0.001, "--damping", 0, "--delay-samples", 1]

CASES = [
    (dict(velocity_filter_cutoff=3.18), ["--velocity-filter-cutoff", 3.18]),
    (dict(velocity_filter_samples=4), ["--velocity-filter-samples", 4]),
    (dict(hand_mass=0.2, hand_damping=2.0, hand_stiffness=300.0),
     ["--hand-mass", 0.2, "--hand-damping", 2, "--hand-stiffness", 300]),
    (dict(handle_mass=0.03, transmission_stiffness=2e5, transmission_damping=5.0, encoder="handle"),
     ["--handle-mass", 0.03, "--transmission-stiffness", 200000, "--transmission-damping", 5,
      "--encoder", "handle"]),
    (dict(actuator_time_constant=2e-4), ["--actuator-time-constant", 0.0002]),
]


@pytest.mark.parametrize("kw,flags", CASES)
def test_elements_match_the_command_line(cli_ok, kw, flags):
    walls = [(2000.0, 10.0), (10800.0, 42.5), (60000.0, 5.0)]
    r = stabound.check(**DEVICE, stiffness=[k for k, _ in walls],
                       wall_damping=[b for _, b in walls], **kw)
    for i, (k, b) in enumerate(walls):
        v = json.loads(cli_ok("check", *CLI_DEVICE, "--stiffness", k, "--wall-damping", b,
                              *flags, "--format", "json"))
        assert r.verdict[i] == v["verdict"], (kw, k, b)
        assert r.spectral_radius[i] == v["spectral_radius"], (kw, k, b)


def test_the_filter_lag_example():
    # paper Section VIII: the 75 % wall is stable without the filter and not with 50 ms lag
    plain = stabound.check(**DEVICE, stiffness=10800.0, wall_damping=42.5)
    lagged = stabound.check(**DEVICE, stiffness=10800.0, wall_damping=42.5,
                            velocity_filter_cutoff=3.18)
    assert (plain.verdict, lagged.verdict) == ("stable", "unstable")


def test_element_refusals():
    with pytest.raises(ValueError, match="physical units"):
        stabound.check(0.1, 0.3, 0.5, 1.0, velocity_filter_cutoff=30.0)
    with pytest.raises(ValueError, match="Nyquist"):
        stabound.check(**DEVICE, stiffness=1e3, wall_damping=1.0, velocity_filter_cutoff=600.0)
    with pytest.raises(ValueError, match="both the handle mass and the coupling stiffness"):
        stabound.check(**DEVICE, stiffness=1e3, wall_damping=1.0, handle_mass=0.03)
    with pytest.raises(ValueError, match="one number"):
        stabound.check(mass=[0.1, 0.2], period=1e-3, damping=0.0, delay_samples=1,
                       stiffness=1e3, wall_damping=1.0, hand_mass=0.1)
    with pytest.raises(ValueError, match="encoder"):
        stabound.check(**DEVICE, stiffness=1e3, wall_damping=1.0, handle_mass=0.03,
                       transmission_stiffness=1e5, encoder="middle")
    assert np.isscalar(stabound.check(**DEVICE, stiffness=1e3, wall_damping=1.0,
                                      hand_mass=0.1).spectral_radius)
