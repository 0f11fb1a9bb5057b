"""End-to-end tests of `stabound serve` in headless Chromium: the page's numbers, drawings and
exports against the command line's for the same device."""

import csv
import http.client
import io
import json
import os
import statistics
import tempfile
import threading
import time
import urllib.error
import urllib.parse
import urllib.request

import pytest

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


def click(d, css):
    """Clicks a control and waits until the page has drawn the new state."""
    before = d.execute_script("return window.explorer.seq")
    d.find_element("css selector", css).click()
    end = time.time() + 60
    while time.time() < end:
        if d.execute_script("return window.explorer.seq > arguments[0] && window.explorer.idle", before):
            return
        time.sleep(0.005)
    raise AssertionError(f"no redraw after clicking {css}")


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
    click(d, "input[data-element=VelocityFilter]")  # its first-order low-pass at 100 Hz
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


LATENCY_DEVICES = {
    "first-order filter": "velocity_filter_cutoff=100&damping=2",
    "transmission with dampers, second-order filter": "velocity_filter_cutoff=100&velocity_filter_order=2"
    "&damping=4&handle_mass=0.03&transmission_stiffness=200000&transmission_damping=5"
    "&motor_damping=2.5&handle_damping=1.5",
}


@pytest.mark.parametrize("name", list(LATENCY_DEVICES))
def test_latency_of_slider_moves(page, shots, name):
    """Measures (never asserts) the time from a slider move to the redrawn page, 100 moves of
    the delay (d <= 10) with a velocity filter; written for the performance page."""
    d = page(LATENCY_DEVICES[name])
    d.execute_script("window.explorer.latencies.length = 0; window.explorer.fetches.length = 0")
    for i in range(100):
        move(d, "delay", (i * 379) % 1001)  # 0 to 10 samples, in 1/20 steps
    ms = d.execute_script("return window.explorer.latencies")
    server = d.execute_script("return window.explorer.fetches.slice(-arguments[0])", len(ms))
    assert len(ms) >= 100
    load = os.getloadavg()[0]
    line = (
        f"{name}: median {statistics.median(ms):.1f} ms, worst {max(ms):.1f} ms over {len(ms)} moves;"
        f" of which the request (server and JSON): median {statistics.median(server):.1f} ms,"
        f" worst {max(server):.1f} ms; load average {load:.1f}"
    )
    print("slider latency:", line)
    with open(os.path.join(shots, "latency.txt"), "a") as f:
        f.write(line + "\n")
    d.save_screenshot(os.path.join(shots, "latency-last.png"))


def element_list(url):
    return json.loads(urllib.request.urlopen(url + "api/params").read())["params"]


def test_every_element_parameter_has_a_control(page, url):
    """The page's element controls are built from the library's element list: every
    parameter (the command line's element flags) has its box, switch, field or choice."""
    d = page()
    params = element_list(url)
    help_text = cli("amax", "--help").decode()
    keywords = {p["keyword"] for p in params}
    # the list served is the command line's: each flag is in its help, the dampers and
    # the filter's order among them
    assert {"motor_damping", "handle_damping", "velocity_filter_order"} <= keywords
    for p in params:
        assert "--" + p["flag"] in help_text, p["flag"]
        box = d.find_element("id", p["element"])
        assert box.find_element("css selector", "input[data-element=%s]" % p["element"])
        assert box.find_element("id", "use-" + p["keyword"])
        control = box.find_element("id", p["keyword"])
        assert control.tag_name == ("select" if p["accepts"]["kind"] == "choice" else "input")


def named_loop(d):
    """Switches on the transmission with a handle-side damper and the velocity filter as a
    second-order low-pass, by the page's controls, on a device with damping to share."""
    move(d, "damping", 80)  # 4 N s/m
    move(d, "delay", 200)  # 2 samples
    click(d, "input[data-element=Transmission]")
    click(d, "#use-handle_damping")
    move(d, "handle_damping", 30)  # 1.5 N s/m
    click(d, "#use-motor_damping")
    move(d, "motor_damping", 50)  # 2.5 N s/m
    click(d, "input[data-element=VelocityFilter]")
    click(d, "#use-velocity_filter_order")
    move(d, "velocity_filter_order", 1000)  # 2
    args = flags(d)
    for f, v in [("--handle-damping", "1.5"), ("--motor-damping", "2.5"), ("--velocity-filter-order", "2"),
                 ("--velocity-filter-cutoff", "100"), ("--handle-mass", "0.03")]:
        assert args[args.index(f) + 1] == v, args
    return args


def test_dampers_and_second_order_filter_match_the_command_line(page, shots):
    d = page()
    args = named_loop(d)
    assert d.find_element("id", "error").is_displayed() is False
    k, b = amax(*args)
    assert (value(d, "kmax"), value(d, "kmax-b")) == (k, b)
    k0, b0 = amax(*args, "--wall-damping-min", "0")
    assert (value(d, "kmax-pos"), value(d, "kmax-pos-b")) == (k0, b0)
    # the drawn region is the command line's boundary, thinned
    vertices = boundary_vertices(args)
    drawn = d.execute_script("return window.explorer.view.region")
    assert len(drawn) > 100
    assert all((x, y) in vertices for x, y in drawn)
    # the drawing keeps vertices 1/1500 of the extent apart (as the command line's drawings)
    right = max(x for x, _ in vertices)
    assert right - right / 1500 <= max(x for x, _ in drawn) <= right
    # the wall's verdict and spectral radius are `check`'s
    state = d.execute_script("return window.explorer.state")
    check = json.loads(cli("check", *args, "--stiffness", repr(state["stiffness"]),
                           "--wall-damping", repr(state["wall_damping"]), "--format", "json",
                           "--radius"))
    assert d.find_element("id", "verdict").text == check["verdict"]
    assert value(d, "radius") == check["spectral_radius"]
    # the passive region is not modelled for a transmission: the page says so
    assert "passive region" in d.find_element("id", "passive-note").text
    d.save_screenshot(os.path.join(shots, "damper-order2.png"))


def test_exports_with_dampers_and_second_order_filter(page):
    d = page()
    args = named_loop(d)
    state = d.execute_script("return window.explorer.state")
    wall = ["--stiffness", repr(state["stiffness"]), "--wall-damping", repr(state["wall_damping"])]

    def fetch(name):
        return urllib.request.urlopen(d.find_element("id", "export-" + name).get_attribute("href")).read()

    assert fetch("csv") == cli("boundary", *args)
    assert fetch("c") == cli("table", *args, "--format", "c")
    assert fetch("step") == cli("step", *args, *wall)
    with tempfile.TemporaryDirectory() as t:
        for kind in ["svg", "png"]:
            out = os.path.join(t, "b." + kind)
            cli("boundary", *args, "-o", os.path.join(t, "b.csv"), "--svg", out)
            assert fetch(kind) == open(out, "rb").read(), kind
        scene = os.path.join(t, "scene.toml")
        text = fetch("scene")
        for key in [b"handle_damping_Ns_per_m = 1.5", b"motor_damping_Ns_per_m = 2.5", b"velocity_filter_order = 2"]:
            assert key in text, text
        with open(scene, "wb") as f:
            f.write(text)
        report = cli("scene", scene, "--format", "json")
        assert fetch("report") == report
        walls = json.loads(report)["devices"][0]["walls"][0]
        assert value(d, "radius") == walls["spectral_radius"]


def test_an_element_out_of_range_from_the_page_gets_the_librarys_message(page, shots):
    d = page()
    click(d, "input[data-element=Transmission]")
    click(d, "#use-handle_damping")
    field = d.find_element("id", "handle_damping")
    field.clear()
    field.send_keys("3\n")  # more than the device's damping, 0
    d.execute_script("arguments[0].dispatchEvent(new Event('change'))", field)
    wait_idle(d)
    err = d.find_element("id", "error")
    assert err.is_displayed()
    assert "handle damping" in err.text and "cannot exceed" in err.text, err.text
    # the last drawing stays, faded: it is not the state in the controls
    assert d.execute_script("return document.body.dataset.status") == "error"
    assert d.execute_script("return getComputedStyle(document.getElementById('plane-box')).opacity") == "0.35"
    d.save_screenshot(os.path.join(shots, "bad-damper.png"))


def get(url, path, host=None, timeout=60):
    """(status, JSON error or body, seconds) of a hand-made GET request."""
    u = urllib.parse.urlparse(url)
    c = http.client.HTTPConnection(u.hostname, u.port, timeout=timeout)
    t0 = time.time()
    c.request("GET", path, headers={"Host": host or u.netloc})
    r = c.getresponse()
    body = r.read()
    took = time.time() - t0
    c.close()
    if r.headers.get("Content-Type") == "application/json" and r.status != 200:
        return r.status, json.loads(body)["error"], took
    return r.status, body, took


# the view's: the numbers it shows in physical units would not be finite (the command line's
# exports write such a device's normalized columns and leave the physical ones empty)
BAD_VIEWS = [
    ("mass=1e308", "not a finite number"),
    ("period=1e-300", "closer in scale"),
]

BAD_REQUESTS = [
    # huge sizes
    ("delay=1e9", "more than the 100"),
    ("velocity_filter_samples=100000000000000000000000", "not a whole number"),
    ("velocity_filter_samples=100000", "at most"),
    ("x=" + "9" * 5000, "longer than"),
    # not numbers
    ("mass=nan", "not a finite number"),
    ("damping=inf", "not a finite number"),
    ("hand_mass=NaN", "not a finite number"),
    ("stiffness=1e999", "not a finite number"),
    # out of range
    ("mass=-1", "greater than 0"),
    ("hand_damping=-2", "0 or more"),
    ("velocity_filter_cutoff=100&velocity_filter_order=3", "at most 2"),
    ("velocity_filter_cutoff=600&velocity_filter_order=2", "Nyquist"),
    ("damping=1&handle_mass=0.03&transmission_stiffness=2e5&handle_damping=2", "cannot exceed"),
    ("encoder=belt&handle_mass=0.03&transmission_stiffness=2e5", "'motor', 'handle'"),
    # missing or contradictory fields
    ("mass=", "no value"),
    ("mass", "no value"),
    ("handle_mass=0.03", "needs both the handle mass and the coupling stiffness"),
    ("velocity_filter_order=2", "needs its cutoff"),
    ("velocity_filter_cutoff=100&velocity_filter_samples=3", "not both"),
    ("mass=0.1&mass=0.2", "named twice"),
    # what the explorer does not take: tolerances, sizes of grids
    ("tolerance=1e-300", "unknown key 'tolerance'"),
    ("points=100000000", "unknown key 'points'"),
    ("mass=%zz", "bad escape"),
]


def test_hand_made_bad_requests_get_the_librarys_message(url):
    tried = [("/api/view?", q, e) for q, e in BAD_REQUESTS + BAD_VIEWS]
    tried += [("/api/export/" + kind + "?", q, e) for q, e in BAD_REQUESTS for kind in ["csv", "scene"]]
    for path, query, expected in tried:
        status, msg, took = get(url, path + query)
        assert 400 <= status < 500, (path, query, status, msg)
        assert expected in msg, (path, query, msg)
        assert took < 30, (path, query, took)
    for path, status_expected, expected in [
        ("/api/export/pdf", 404, "unknown export"),
        ("/nothing", 404, "no page"),
    ]:
        status, msg, _ = get(url, path)
        assert (status, expected in msg) == (status_expected, True), (path, status, msg)
    # the longest delay with every element: answered (numbers, the library's refusal or its
    # numerical failure, with its message) within the server's time limit of 20 s, never a
    # hang
    heavy = ("delay=100&velocity_filter_cutoff=100&velocity_filter_order=2&hand_mass=0.2&hand_damping=1"
             "&hand_stiffness=50&handle_mass=0.03&transmission_stiffness=2e5&actuator_time_constant=2e-4")
    status, msg, took = get(url, "/api/view?" + heavy)
    assert status in (200, 400, 500, 503) and took < 30, (status, msg, took)
    if status != 200:
        assert msg, status
    # a foreign Host (DNS rebinding) is refused on the API as on the page
    status, msg, _ = get(url, "/api/view?mass=0.1", host="rebind.example:80")
    assert status == 403 and "localhost" in msg, msg
    # and the server still answers
    status, body, _ = get(url, "/api/view?mass=0.1")
    assert status == 200 and json.loads(body)["kmax"]["K_max"] == amax(*PAPER)[0]


def test_concurrent_clients_are_answered(url):
    """Several clients at once, each its own device: each gets its own device's numbers (the
    command line's), and a burst beyond the computations allowed at once is answered, busy or
    not, never dropped."""
    devices = [(m, d) for m in ("0.1", "0.2") for d in ("1", "2")]
    expected = {dev: amax("--mass", dev[0], "--period", "0.001", "--damping", "1", "--delay-samples", dev[1])
                for dev in devices}
    results, errors = [], []

    def client(dev, rounds):
        try:
            for _ in range(rounds):
                status, body, _ = get(url, f"/api/view?mass={dev[0]}&damping=1&delay={dev[1]}")
                results.append((dev, status, body))
        except Exception as e:  # noqa: BLE001 - reported below
            errors.append(repr(e))

    # as many clients as computations run at once: every request is answered with its numbers
    threads = [threading.Thread(target=client, args=(dev, 5)) for dev in devices]
    for t in threads:
        t.start()
    for t in threads:
        t.join(120)
    assert not errors, errors
    assert len(results) == 5 * len(devices)
    for dev, status, body in results:
        assert status == 200, (dev, status, body)
        k = json.loads(body)["kmax"]
        assert (k["K_max"], k["B"]) == expected[dev], dev
    # a burst of 16 at once: each answered, the numbers or "busy" (HTTP 503), none lost
    results.clear()
    threads = [threading.Thread(target=client, args=(devices[i % 4], 1)) for i in range(16)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(120)
    assert not errors, errors
    assert len(results) == 16
    for dev, status, body in results:
        if status == 503:
            assert "busy" in body, body
        else:
            assert status == 200, (dev, status, body)
            assert json.loads(body)["kmax"]["K_max"] == expected[dev][0]
    assert any(status == 200 for _, status, _ in results)
