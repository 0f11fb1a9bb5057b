"""End-to-end tests of `stabound serve` in headless Chromium: the page's numbers, drawings and
exports against the command line's for the same device."""

import csv
import http.client
import io
import json
import os
import statistics
import tempfile
import time
import urllib.error
import urllib.parse
import urllib.request

from selenium.webdriver.common.action_chains import ActionChains

from conftest import cli, wait_idle

PAPER = ["--mass", "0.1", "--period", "0.001", "--damping", "0", "--delay-samples", "1"]


def value(d, id_):
    return float(d.find_element("id", id_).get_attribute("data-value"))


def amax(*args):
    rows = list(csv.DictReader(io.StringIO(cli("amax", *args).decode())))
    return float(rows[0]["K_max_N_per_m"]), float(rows[0]["B_at_max_Ns_per_m"])


def flags(d):
    """The command-line flags of the page's state (its query string)."""
    q = urllib.parse.parse_qsl(d.execute_script("return location.search.slice(1)"))
    out = []
    for k, v in q:
        if k in ("stiffness", "wall_damping"):
            continue
        name = {"delay": "delay-samples"}.get(k, k.replace("_", "-"))
        out += ["--" + name, v]
    return out


def move(d, key, position):
    """Moves a slider (0..1000) as a user would: value, then an input event."""
    before = d.execute_script("return window.explorer.seq")
    d.execute_script(
        "const s = document.getElementById(arguments[0] + '-slider');"
        "s.value = arguments[1]; s.dispatchEvent(new Event('input'));",
        key,
        position,
    )
    end = time.time() + 60
    while time.time() < end:
        if d.execute_script("return window.explorer.seq > arguments[0] && window.explorer.idle", before):
            return
        time.sleep(0.005)
    raise AssertionError(f"no redraw after moving {key}")


def test_load_shows_the_papers_kmax(page, shots):
    d = page()
    k, b = amax(*PAPER)
    assert value(d, "kmax") == k
    assert value(d, "kmax-b") == b
    assert d.find_element("id", "kmax").text == "14,447 N/m"
    k0, _ = amax(*PAPER, "--wall-damping-min", "0")
    assert value(d, "kmax-pos") == k0
    assert d.find_element("id", "verdict").text == "stable"
    d.save_screenshot(os.path.join(shots, "load.png"))


def boundary_vertices(args):
    rows = csv.DictReader(io.StringIO(cli("boundary", *args).decode()))
    return {(float(r["stiffness_N_per_m"]), float(r["wall_damping_Ns_per_m"])) for r in rows}


def test_sliders_redraw_the_command_lines_boundary(page, shots):
    d = page()
    d.find_element("id", "filter-kind").send_keys("first")  # first-order low-pass
    wait_idle(d)
    move(d, "delay", 300)  # 3 samples
    move(d, "damping", 100)  # 5 N s/m
    args = flags(d)
    assert "--velocity-filter-cutoff" in args and "3" in args, args
    vertices = boundary_vertices(args)
    drawn = d.execute_script("return window.explorer.view.region")
    # every drawn point is a vertex of the command line's boundary, and the rightmost is its
    assert len(drawn) > 100
    assert all((k, b) in vertices for k, b in drawn)
    assert max(k for k, _ in drawn) == max(k for k, _ in vertices)
    # the path drawn has one segment per point
    path = d.find_element("id", "region").get_attribute("d")
    assert path.count("L") == len(drawn) - 1
    k, _ = amax(*args)
    assert value(d, "kmax") == k
    d.save_screenshot(os.path.join(shots, "filter-delay3.png"))


def test_drag_the_wall(page, shots):
    d = page()
    marker = d.find_element("id", "wall-marker")
    before = d.execute_script("return window.explorer.seq")
    # drag far right: past K_max, unstable
    ActionChains(d).click_and_hold(marker).move_by_offset(150, 0).pause(0.2).move_by_offset(30, 0).release().perform()
    wait_idle(d)
    assert d.execute_script("return window.explorer.seq") > before
    state = d.execute_script("return window.explorer.state")
    k, b = state["stiffness"], state["wall_damping"]
    assert k > 14447, state
    check = json.loads(cli("check", *PAPER, "--stiffness", repr(k), "--wall-damping", repr(b), "--format", "json"))
    assert d.find_element("id", "verdict").text == check["verdict"] == "unstable"
    # the wall's numbers are those of the command line's scene report for the exported scene
    scene = urllib.request.urlopen(d.find_element("id", "export-scene").get_attribute("href")).read()
    with tempfile.TemporaryDirectory() as t:
        path = os.path.join(t, "scene.toml")
        with open(path, "wb") as f:
            f.write(scene)
        report = json.loads(cli("scene", path, "--format", "json"))
    wall = report["devices"][0]["walls"][0]
    assert (wall["stiffness_N_per_m"], wall["wall_damping_Ns_per_m"]) == (k, b)
    assert value(d, "radius") == wall["spectral_radius"]
    assert value(d, "margin") == wall["stiffness_margin"]
    d.save_screenshot(os.path.join(shots, "wall-dragged.png"))


def test_exports_are_the_command_lines_bytes(page):
    d = page("damping=3&delay=2&velocity_filter_samples=3&stiffness=4000&wall_damping=15")
    args = flags(d)

    def fetch(name):
        return urllib.request.urlopen(d.find_element("id", "export-" + name).get_attribute("href")).read()

    assert fetch("csv") == cli("boundary", *args)
    assert fetch("c") == cli("table", *args, "--format", "c")
    assert fetch("step") == cli("step", *args, "--stiffness", "4000", "--wall-damping", "15")
    with tempfile.TemporaryDirectory() as t:
        svg = os.path.join(t, "b.svg")
        cli("boundary", *args, "-o", os.path.join(t, "b.csv"), "--svg", svg)
        assert fetch("svg") == open(svg, "rb").read()
        png = os.path.join(t, "b.png")
        cli("boundary", *args, "-o", os.path.join(t, "b.csv"), "--svg", png)
        assert fetch("png") == open(png, "rb").read()
        scene = os.path.join(t, "scene.toml")
        with open(scene, "wb") as f:
            f.write(fetch("scene"))
        assert fetch("report") == cli("scene", scene, "--format", "json")


def test_bad_input_gets_a_clear_message(page, url, shots):
    d = page()
    field = d.find_element("id", "mass")
    field.clear()
    field.send_keys("-1\n")
    d.execute_script("arguments[0].dispatchEvent(new Event('change'))", field)
    wait_idle(d)
    err = d.find_element("id", "error")
    assert err.is_displayed()
    assert "mass_kg" in err.text and "greater than 0" in err.text, err.text
    d.save_screenshot(os.path.join(shots, "bad-input.png"))
    # a hand-made request
    try:
        urllib.request.urlopen(url + "api/view?period=0&delay=banana")
        raise AssertionError("accepted")
    except urllib.error.HTTPError as e:
        assert e.code == 400
        msg = json.loads(e.read())["error"]
        assert "delay" in msg and "not a number" in msg, msg


def test_a_foreign_host_is_refused(url):
    u = urllib.parse.urlparse(url)
    c = http.client.HTTPConnection(u.hostname, u.port, timeout=30)
    c.request("GET", "/", headers={"Host": "attacker.example"})
    r = c.getresponse()
    assert r.status == 403
    assert "localhost" in json.loads(r.read())["error"]


def test_latency_of_slider_moves(page, shots):
    """Measures (never asserts) the time from a slider move to the redrawn page, 100 moves of
    the delay (d <= 10) with a first-order velocity filter; written for the performance page."""
    d = page("velocity_filter_cutoff=100&damping=2")
    d.execute_script("window.explorer.latencies.length = 0; window.explorer.fetches.length = 0")
    for i in range(100):
        move(d, "delay", (i * 379) % 1001)  # 0 to 10 samples, in 1/20 steps
    ms = d.execute_script("return window.explorer.latencies")
    server = d.execute_script("return window.explorer.fetches.slice(-arguments[0])", len(ms))
    assert len(ms) >= 100
    line = (
        f"median {statistics.median(ms):.1f} ms, worst {max(ms):.1f} ms over {len(ms)} moves;"
        f" of which the request (server and JSON): median {statistics.median(server):.1f} ms,"
        f" worst {max(server):.1f} ms"
    )
    print("slider latency:", line)
    with open(os.path.join(shots, "latency.txt"), "w") as f:
        f.write(line + "\n")
    d.save_screenshot(os.path.join(shots, "latency-last.png"))
