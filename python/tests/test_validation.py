"""Bad input: ValueError with the library's message (the same text the command line prints
after `error: `), numerical failures as StaboundError, and never a panic."""

import json
import math

import numpy as np
import pytest

import stabound


def cli_message(cli, *args):
    code, out, err = cli(*args)
    assert code == 2, (out, err)
    last = err.strip().splitlines()[-1]
    assert last.startswith("error: "), err
    msg = last[len("error: "):]
    # the command line names its flag in front of the library's message ("--tol: ...")
    if msg.startswith("--") and ": " in msg:
        msg = msg.split(": ", 1)[1]
    return msg


def test_value_errors_carry_the_library_message(cli):
    cases = [
        (lambda: stabound.check(0.1, 0.3, -1.0, 1.0),
         ("check", "--alpha", 0.1, "--beta", 0.3, "--delta", -1, "--d", 1)),
        (lambda: stabound.check(0.1, 0.3, 0.5, 501.0),
         ("check", "--alpha", 0.1, "--beta", 0.3, "--delta", 0.5, "--d", 501)),
        (lambda: stabound.check(0.1, 0.3, 0.5, 1.0, marginal_band=0.7),
         ("check", "--alpha", 0.1, "--beta", 0.3, "--delta", 0.5, "--d", 1, "--marginal-band", 0.7)),
        (lambda: stabound.alpha_max(0.0, 0.0, theta_tol=1.0),
         ("amax", "--delta", 0, "--d", 0, "--theta-tol", 1)),
        (lambda: stabound.alpha_max(0.0, 0.0, beta_min=2.0, beta_max=1.0),
         ("amax", "--delta", 0, "--d", 0, "--beta-min", 2, "--beta-max", 1)),
        (lambda: stabound.alpha_max(mass=-1.0, period=0.001, damping=0.0, delay=0.0),
         ("amax", "--mass", -1, "--period", 0.001, "--damping", 0, "--delay", 0)),
        (lambda: stabound.table([0.0, 1.0, 0.5], [0.0]),
         None),
        (lambda: stabound.step(mass=1.0, period=0.001, damping=0.0, delay_samples=1, stiffness=1e4, duration=-1.0),
         ("step", "--mass", 1, "--period", 0.001, "--damping", 0, "--delay-samples", 1, "--stiffness", 1e4, "--duration=-1")),
    ]
    for call, args in cases:
        with pytest.raises(ValueError) as e:
            call()
        assert str(e.value)
        if args is not None:
            assert str(e.value) == cli_message(cli, *args)


def test_nan_and_infinity_are_refused():
    for bad in (math.nan, math.inf, -math.inf):
        with pytest.raises(ValueError, match="invalid alpha"):
            stabound.check(bad, 0.3, 0.5, 1.0)
        with pytest.raises(ValueError, match="invalid delta"):
            stabound.alpha_max(bad, 0.0)
    # one bad element in an array names that element's value
    with pytest.raises(ValueError, match=r"invalid d = -2"):
        stabound.check([0.1, 0.1, 0.1], 0.3, 0.5, [1.0, -2.0, -3.0])


def test_usage_errors():
    with pytest.raises(ValueError, match="missing delta"):
        stabound.check(0.1, 0.3)
    with pytest.raises(ValueError, match="not both"):
        stabound.check(0.1, 0.3, 0.5, 1.0, mass=1.0)
    with pytest.raises(ValueError, match="missing stiffness="):
        stabound.check(mass=1.0, period=0.001, damping=0.0, delay=0.0, wall_damping=1.0)
    with pytest.raises(ValueError, match="delay= or delay_samples=, not both"):
        stabound.alpha_max(mass=1.0, period=0.001, damping=0.0, delay=0.0, delay_samples=0)
    with pytest.raises(ValueError, match="'schur-cohn'"):
        stabound.check(0.1, 0.3, 0.5, 1.0, method="jury")
    with pytest.raises(ValueError, match="'exact' or 'bisect'"):
        stabound.boundary(0.0, 0.0, method="grid")
    with pytest.raises(ValueError, match="tol"):
        stabound.boundary(0.0, 0.0, tol=1.0)
    with pytest.raises(ValueError, match="curves"):
        stabound.boundary(np.zeros(40), np.zeros(30))
    with pytest.raises(ValueError, match="cannot be broadcast|shape mismatch"):
        stabound.check([0.1, 0.2], 0.3, [0.5, 0.5, 0.5], 1.0)
    with pytest.raises(ValueError, match="stiffness= K or margin= F"):
        stabound.step(mass=1.0, period=0.001, damping=0.0, delay_samples=1)
    with pytest.raises(ValueError, match="at least 1"):
        stabound.step(mass=1.0, period=0.001, damping=0.0, delay_samples=1, stiffness=1e4, points_per_period=-3)
    with pytest.raises(ValueError, match="analyze takes one wall"):
        stabound.analyze([0.1, 0.2], 0.3, 0.5, 1.0)
    with pytest.raises(TypeError):
        stabound.scene(42)


def test_scene_errors(tmp_path, cli):
    with pytest.raises(ValueError, match="cannot read scene"):
        stabound.scene(tmp_path / "missing.toml")
    bad = {"device": [{"mass_kg": 1.0, "period_s": 0.001, "damping_Ns_per_m": 0.0,
                       "delay_samples": 1, "mass": 2.0, "wall": []}]}
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(bad))
    with pytest.raises(ValueError) as from_dict:
        stabound.scene(bad)
    with pytest.raises(ValueError) as from_file:
        stabound.scene(path)
    assert str(from_file.value) == cli_message(cli, "scene", path)
    assert str(from_dict.value).replace("<dict>", str(path)) == str(from_file.value)


def test_error_types():
    assert issubclass(stabound.StaboundError, RuntimeError)
    assert stabound.StaboundError.__module__ == "stabound"


def test_extreme_inputs_never_panic():
    # every call either returns or raises an ordinary exception; a Rust panic would raise
    # pyo3's PanicException, a BaseException that this `except Exception` does not catch
    values = [0.0, -0.0, 1e-300, 1e-12, 0.5, 3.7, 1e3, 1e9, 1e300, -1e-300, -5.0]
    for v in values:
        for call in (
            lambda: stabound.check(v, v, abs(v), min(abs(v), 500.0)),
            lambda: stabound.check(v, -v, 0.0, 0.0, method="argument-principle"),
            lambda: stabound.alpha_max(min(abs(v), 1e9), min(abs(v), 8.0), theta_tol=1e-6),
            lambda: stabound.normalize(mass=v, period=abs(v), damping=abs(v), delay=v, stiffness=v),
        ):
            try:
                call()
            except (ValueError, stabound.StaboundError):
                pass


def test_delta_beta_plane_errors(cli):
    with pytest.raises(ValueError) as e:
        stabound.boundary(plane="delta-beta", alpha=-1.0, d=0.0)
    assert str(e.value).startswith("invalid alpha= -1")
    with pytest.raises(ValueError, match="missing alpha="):
        stabound.boundary(plane="delta-beta", d=0.0)
    with pytest.raises(ValueError, match="axis range"):
        stabound.boundary(plane="delta-beta", alpha=0.5, d=0.0, delta=[1.0, 1.0])
    with pytest.raises(ValueError, match="method='exact'"):
        stabound.boundary(plane="delta-beta", alpha=0.5, d=0.0, method="exact")
    with pytest.raises(ValueError, match="alpha= belongs"):
        stabound.boundary(0.0, 0.0, alpha=0.5)
    with pytest.raises(ValueError, match="invalid plane"):
        stabound.boundary(0.0, 0.0, plane="alpha-delta")
    with pytest.raises(ValueError) as e:
        stabound.boundary(plane="delta-beta", alpha=0.5, d=[0.0, 600.0])
    assert str(e.value) == cli_message(cli, "boundary", "--plane", "delta-beta", "--alpha", 0.5, "--d", "0,600")
