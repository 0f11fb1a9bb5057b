"""Certified ``alpha_max`` over a grid (`stabound.certify_alpha_max` with arrays): one
certificate holding every row, byte for byte the one `stabound amax ... --certify FILE`
writes for the same grid, whose rows (d outer, delta inner; a device's delays outer,
dampings inner) are the command line's CSV rows, in its order; the standalone checker
accepts it, and each row's enclosure holds that row's own `alpha_max`."""

import subprocess
import sys

import numpy as np

import stabound
from conftest import rows


def cli_amax(cli, tmp_path, *args):
    """`stabound amax ARGS --certify FILE`: the certificate and the CSV rows."""
    path = tmp_path / "cli.json"
    code, out, err = cli("amax", *args, "--certify", path)
    assert code == 0, err
    return path.read_text(), [{k: float(v) for k, v in r.items()} for r in rows(out)]


def verified(text, tmp_path, count):
    """The packaged checker accepts the certificate text as `count` rows."""
    path = tmp_path / "py.json"
    path.write_text(text)
    p = subprocess.run([sys.executable, "-m", "stabound.verify_certificate", str(path)],
                       capture_output=True, text=True)
    assert p.returncode == 0 and p.stdout.startswith(f"verified: {count} rows"), p.stderr


def test_a_normalized_grid_is_the_command_lines_certificate(cli, tmp_path):
    deltas, ds = [0.0, 0.5], [1.0, 2.0]
    limits = {"beta_min": 0.0, "beta_max": 1.0}
    c = stabound.certify_alpha_max(deltas, ds, **limits)
    text, table = cli_amax(cli, tmp_path, "--delta", "0,0.5", "--d", "1,2", "--beta-min",
                           "0", "--beta-max", "1")
    assert c.certificate == text
    for f in (c.alpha_max, c.beta_at_max, c.alpha_lo, c.alpha_hi):
        assert isinstance(f, np.ndarray) and f.shape == (len(ds), len(deltas))
    assert c.stiffness is None and c.members == 1
    for k, row in enumerate(table):
        i, j = divmod(k, len(deltas))
        assert (row["delta"], row["d"]) == (deltas[j], ds[i])
        # the same doubles as the command line's CSV (both round-trip exactly)
        assert (c.alpha_max[i, j], c.beta_at_max[i, j], c.alpha_lo[i, j],
                c.alpha_hi[i, j]) == (row["alpha_max"], row["beta_at_max"],
                                      row["alpha_lo_certified"], row["alpha_hi_certified"])
        own = stabound.alpha_max(deltas[j], ds[i], **limits).alpha_max
        assert c.alpha_lo[i, j] <= own < c.alpha_hi[i, j]
    verified(c.certificate, tmp_path, 4)


def test_a_devices_dampings_and_delays_are_the_command_lines_certificate(cli, tmp_path):
    device = {"mass": 0.1, "period": 1e-3}
    limits = {"wall_damping_min": 0.0, "wall_damping_max": 100.0}
    dampings, delays = [0.0, 2.0], [1, 2]
    c = stabound.certify_alpha_max(**device, **limits, damping=dampings,
                                   delay_samples=delays)
    text, table = cli_amax(cli, tmp_path, "--mass", "0.1", "--period", "0.001", "--damping",
                           "0,2", "--delay-samples", "1,2", "--wall-damping-min", "0",
                           "--wall-damping-max", "100")
    assert c.certificate == text
    assert c.stiffness.shape == c.stiffness_lo.shape == (len(delays), len(dampings))
    for k, row in enumerate(table):
        i, j = divmod(k, len(dampings))
        assert row["damping_Ns_per_m"] == dampings[j]
        assert (c.stiffness[i, j], c.wall_damping[i, j], c.stiffness_lo[i, j],
                c.stiffness_hi[i, j]) == (row["K_max_N_per_m"], row["B_at_max_Ns_per_m"],
                                          row["K_lo_certified_N_per_m"],
                                          row["K_hi_certified_N_per_m"])
        own = stabound.alpha_max(**device, **limits, damping=dampings[j],
                                 delay_samples=delays[i]).stiffness
        assert c.stiffness_lo[i, j] <= own < c.stiffness_hi[i, j]
    verified(c.certificate, tmp_path, 4)


def test_one_delay_gives_the_dampings_axis_only(cli, tmp_path):
    """A delay given as one number has no axis: the result is 1-D over the dampings, the
    certificate still the command line's for that one-delay grid."""
    c = stabound.certify_alpha_max(mass=0.1, period=1e-3, damping=[0.0, 2.0],
                                   delay_samples=1, wall_damping_min=0.0,
                                   wall_damping_max=100.0)
    text, table = cli_amax(cli, tmp_path, "--mass", "0.1", "--period", "0.001", "--damping",
                           "0,2", "--delay-samples", "1", "--wall-damping-min", "0",
                           "--wall-damping-max", "100")
    assert c.certificate == text and c.alpha_max.shape == (2,)
    assert c.alpha_lo.tolist() == [r["alpha_lo_certified"] for r in table]
    verified(c.certificate, tmp_path, 2)
