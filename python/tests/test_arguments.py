"""Arguments: numbers are floats or ints (or arrays of them), nothing is coerced silently,
arrays broadcast as numpy broadcasts them, and a bad array entry is named by its index."""

import math

import numpy as np
import pytest

import stabound
from test_validation import cli_message


@pytest.mark.parametrize("bad", [
    "0.1",
    b"0.1",
    ["0.1", "0.2"],
    True,
    np.array(["2020-01-01", "2020-01-02"], dtype="datetime64[D]"),
    np.datetime64("2020-01-01"),
    np.array([1, 2], dtype="timedelta64[s]"),
    np.ma.masked_array([0.1, 0.2], mask=[False, True]),
    np.array([0.1, None], dtype=object),
    np.array([0.1 + 0j]),
    np.array([True, False]),
])
def test_what_is_not_a_number_is_refused(bad):
    with pytest.raises(TypeError, match="invalid alpha"):
        stabound.check(bad, 0.3, 0.5, 1.0)
    with pytest.raises(TypeError, match="invalid damping"):
        stabound.alpha_max(mass=1.0, period=1e-3, damping=bad, delay_samples=1)


def test_a_masked_array_is_refused_even_without_masked_entries():
    # its data would be read, ignoring the mask: refused whatever the mask holds
    with pytest.raises(TypeError, match="masked"):
        stabound.check(np.ma.masked_array([0.1, 0.2]), 0.3, 0.5, 1.0)


@pytest.mark.parametrize("call", [
    lambda n: stabound.check(mass=0.1, period=1e-3, damping=0.0, delay_samples=1, stiffness=1e3,
                             wall_damping=1.0, velocity_filter_samples=n),
    lambda n: stabound.passivity(1.0, 1, velocity_filter_samples=n),
    lambda n: stabound.passivity(1.0, 1, columns=n),
    lambda n: stabound.step(mass=0.1, period=1e-3, damping=0.0, delay_samples=1, stiffness=1e3,
                            points_per_period=n),
])
def test_whole_numbers_are_not_rounded(call):
    for bad in (2.5, 2.0, True):
        with pytest.raises(ValueError, match="whole number"):
            call(bad)
    call(np.int64(2))  # an integer of numpy's is one


def test_ints_and_int_arrays_are_numbers():
    f = stabound.check([0.0, 1.0], [0.0, 0.5], 1.0, 1.0)
    i = stabound.check(np.array([0, 1]), np.array([0.0, 0.5]), 1, 1)
    assert f.spectral_radius.tolist() == i.spectral_radius.tolist()
    assert stabound.alpha_max(0, 1) == stabound.alpha_max(0.0, 1.0)
    assert stabound.alpha_max(np.float32(0.5), 1.0) == stabound.alpha_max(0.5, 1.0)


def test_broadcasting_matches_element_by_element_calls():
    a = np.array([0.05, 0.2, 0.6])[:, None]
    b = np.array([-0.1, 0.0, 0.3, 1.0])[None, :]
    r = stabound.check(a, b, 0.5, [1.0, 2.0, 2.5, 0.0])
    assert r.spectral_radius.shape == (3, 4)
    for i in range(3):
        for j in range(4):
            one = stabound.check(float(a[i, 0]), float(b[0, j]), 0.5, [1.0, 2.0, 2.5, 0.0][j])
            assert r.spectral_radius[i, j] == one.spectral_radius
            assert r.verdict[i, j] == one.verdict and r.method[i, j] == one.method
    m = stabound.alpha_max(mass=[[0.1], [1.0]], period=1e-3, damping=[0.0, 5.0, 50.0],
                           delay_samples=1)
    assert m.stiffness.shape == (2, 3)
    for i, mass in enumerate((0.1, 1.0)):
        for j, b in enumerate((0.0, 5.0, 50.0)):
            one = stabound.alpha_max(mass=mass, period=1e-3, damping=b, delay_samples=1)
            assert (m.alpha_max[i, j], m.stiffness[i, j]) == (one.alpha_max, one.stiffness)


def test_a_bad_entry_is_named_by_its_index():
    with pytest.raises(ValueError, match=r"^alpha\[1\]: invalid alpha = NaN"):
        stabound.check([0.1, math.nan, 0.2], 0.3, 0.5, 1.0)
    with pytest.raises(ValueError, match=r"^alpha\[1, 0\]: invalid alpha = NaN"):
        stabound.check(np.array([[0.1], [math.nan]]), [0.3, 0.4], 0.5, 1.0)
    with pytest.raises(ValueError, match=r"^damping\[3\]: invalid damping = NaN"):
        stabound.alpha_max(mass=1.0, period=1e-3, damping=[0.0, 1.0, 2.0, math.nan],
                           delay_samples=1)
    with pytest.raises(ValueError, match=r"^delay_samples\[2\]: invalid delay = -1"):
        stabound.normalize(mass=1.0, period=1e-3, damping=0.0, delay_samples=[0, 1, -1])
    with pytest.raises(ValueError, match=r"^d\[1\]: invalid d = 600"):
        stabound.alpha_max([0.0, 0.1], [1.0, 600.0])
    with pytest.raises(ValueError, match=r"^damping\[1\]: invalid damping = -1"):
        stabound.step(mass=0.1, period=1e-3, damping=[0.0, -1.0], delay_samples=1, stiffness=1e3)
    # a scalar at fault has no index: the message is the library's (and the command line's)
    with pytest.raises(ValueError, match=r"^invalid delta = -1"):
        stabound.check([0.1, 0.2], 0.3, -1.0, 1.0)


def test_overflowing_physical_results_are_refused_as_the_command_line_refuses_them(cli, tmp_path):
    dev = dict(mass=1e300, period=1e-12, damping=0.0, delay_samples=1)
    with pytest.raises(ValueError, match="not a finite number") as e:
        stabound.alpha_max(**dev)
    assert str(e.value) == cli_message(cli, "amax", "--mass", 1e300, "--period", 1e-12,
                                       "--damping", 0, "--delay-samples", 1)
    with pytest.raises(ValueError, match="not a finite number") as e:
        stabound.table(mass=1e300, period=1e-12, damping=[0.0, 1.0], delay_samples=[1])
    header = tmp_path / "t.h"
    code, _, err = cli("table", "--mass", 1e300, "--period", 1e-12, "--damping", "0,1",
                       "--delay-samples", 1, "--format", "c", "-o", header)
    assert code == 2 and not header.exists(), err
    # the same device at a sane scale gives finite numbers
    ok = stabound.alpha_max(mass=1.0, period=1e-3, damping=0.0, delay_samples=1)
    assert math.isfinite(ok.stiffness)


def test_an_unstable_step_response_warns_as_the_command_line_does(cli):
    run = dict(mass=0.1, period=1e-3, damping=0.0, delay_samples=1, stiffness=1e5, duration=20.0)
    with pytest.warns(RuntimeWarning, match="is unstable .* does not settle") as w:
        r = stabound.step(**run)
    assert r.verdict == "unstable" and not np.isfinite(r.position).all()
    _, _, err = cli("step", "--mass", 0.1, "--period", 1e-3, "--damping", 0, "--delay-samples", 1,
                    "--stiffness", 1e5, "--duration", 20, "--format", "summary")
    assert "warning: " + str(w[0].message) in err
