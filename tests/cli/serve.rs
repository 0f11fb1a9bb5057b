//! `stabound serve`: the explorer's JSON API over plain HTTP on the loopback, against the
//! command line's own outputs for the same device.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use super::common::stdout;

/// A server on a free port that stops itself after a minute; killed when dropped.
struct Server {
    child: Child,
    port: u16,
}

impl Server {
    fn start() -> Self {
        let mut child = Command::new(assert_cmd::cargo::cargo_bin("stabound"))
            .args(["serve", "--port", "0", "--exit-after", "60"])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        // http://127.0.0.1:PORT/
        let port = line
            .trim()
            .trim_end_matches('/')
            .rsplit(':')
            .next()
            .unwrap()
            .parse()
            .unwrap_or_else(|_| panic!("no URL printed: {line:?}"));
        Server { child, port }
    }

    /// `GET path` with this Host header: the status and the body.
    fn get_as(&self, host: &str, path: &str) -> (u16, Vec<u8>) {
        let mut s = TcpStream::connect(("127.0.0.1", self.port)).unwrap();
        s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
        write!(
            s,
            "GET {path} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n"
        )
        .unwrap();
        let mut raw = Vec::new();
        s.read_to_end(&mut raw).unwrap();
        let split = raw.windows(4).position(|w| w == b"\r\n\r\n").unwrap();
        let head = String::from_utf8_lossy(&raw[..split]).to_string();
        let status = head.split(' ').nth(1).unwrap().parse().unwrap();
        let mut body = raw[split + 4..].to_vec();
        if head
            .to_ascii_lowercase()
            .contains("transfer-encoding: chunked")
        {
            body = dechunk(&body);
        }
        (status, body)
    }

    fn get(&self, path: &str) -> (u16, Vec<u8>) {
        self.get_as(&format!("127.0.0.1:{}", self.port), path)
    }

    fn json(&self, path: &str) -> (u16, serde_json::Value) {
        let (status, body) = self.get(path);
        (status, serde_json::from_slice(&body).unwrap())
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn dechunk(mut b: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    loop {
        let end = b.windows(2).position(|w| w == b"\r\n").unwrap();
        let n = usize::from_str_radix(std::str::from_utf8(&b[..end]).unwrap().trim(), 16).unwrap();
        if n == 0 {
            return out;
        }
        out.extend_from_slice(&b[end + 2..end + 2 + n]);
        b = &b[end + 4 + n..];
    }
}

const DEVICE: [&str; 8] = [
    "--mass",
    "0.1",
    "--period",
    "0.001",
    "--damping",
    "2",
    "--delay-samples",
    "3",
];
const QUERY: &str = "mass=0.1&period=0.001&damping=2&delay=3&velocity_filter_cutoff=100";

/// The last row of `stabound amax` CSV output: (K_max, B).
fn amax_cli(extra: &[&str]) -> (f64, f64) {
    let out = String::from_utf8(stdout(&[&["amax"], &DEVICE[..], extra].concat())).unwrap();
    let row: Vec<f64> = out
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    (row[5], row[6])
}

#[test]
fn view_numbers_are_the_command_lines() {
    let server = Server::start();
    let (status, v) = server.json("/api/view");
    assert_eq!(status, 200);
    // the paper's Section VIII device by default
    let want = amax_cli_default();
    assert_eq!(v["kmax"]["K_max"].as_f64().unwrap(), want);
    assert_eq!(want.round(), 14447.0);

    let (status, v) = server.json(&format!("/api/view?{QUERY}"));
    assert_eq!(status, 200, "{v}");
    let filter = ["--velocity-filter-cutoff", "100"];
    let (k, b) = amax_cli(&filter);
    assert_eq!(v["kmax"]["K_max"].as_f64().unwrap(), k);
    assert_eq!(v["kmax"]["B"].as_f64().unwrap(), b);
    let margin = String::from_utf8(stdout(
        &[&["amax"], &DEVICE[..], &filter, &["--margin", "0.75"]].concat(),
    ))
    .unwrap();
    let (header, rows) = super::common::csv(margin.as_bytes());
    let at = header
        .split(',')
        .position(|c| c == "K_margin_N_per_m")
        .unwrap();
    let k_margin: f64 = rows[0][at].parse().unwrap();
    assert_eq!(v["margin_wall"]["stiffness"].as_f64().unwrap(), k_margin);
    let (k0, b0) = amax_cli(&[&filter[..], &["--wall-damping-min", "0"]].concat());
    assert_eq!(v["kmax_positive_damping"]["K_max"].as_f64().unwrap(), k0);
    assert_eq!(v["kmax_positive_damping"]["B"].as_f64().unwrap(), b0);
    // the drawn region's rightmost point is the boundary's, within the thinning of 1/1500 of
    // the drawing's extent
    let (header, rows) =
        super::common::csv(&stdout(&[&["boundary"], &DEVICE[..], &filter].concat()));
    let col = header
        .split(',')
        .position(|c| c == "stiffness_N_per_m")
        .unwrap();
    let k_cli = rows
        .iter()
        .map(|r| r[col].parse::<f64>().unwrap())
        .fold(f64::MIN, f64::max);
    let k_page = v["region"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p[0].as_f64().unwrap())
        .fold(f64::MIN, f64::max);
    assert!((k_page - k_cli).abs() <= k_cli / 1500.0, "{k_page} {k_cli}");
    assert_eq!(v["region_vertices"].as_u64().unwrap() as usize, rows.len());
}

fn amax_cli_default() -> f64 {
    let out = String::from_utf8(stdout(&[
        "amax",
        "--mass",
        "0.1",
        "--period",
        "0.001",
        "--damping",
        "0",
        "--delay-samples",
        "1",
    ]))
    .unwrap();
    out.lines()
        .nth(1)
        .unwrap()
        .split(',')
        .nth(5)
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn exports_are_the_command_lines_bytes() {
    let server = Server::start();
    let filter = ["--velocity-filter-cutoff", "100"];
    let (status, csv) = server.get(&format!("/api/export/csv?{QUERY}"));
    assert_eq!(status, 200);
    assert_eq!(csv, stdout(&[&["boundary"], &DEVICE[..], &filter].concat()));
    let (status, header) = server.get(&format!("/api/export/c?{QUERY}"));
    assert_eq!(status, 200);
    assert_eq!(
        header,
        stdout(&[&["table"], &DEVICE[..], &filter, &["--format", "c"]].concat())
    );
    let wall = ["--stiffness", "10800", "--wall-damping", "42.5"];
    let (status, step) = server.get(&format!("/api/export/step?{QUERY}"));
    assert_eq!(status, 200);
    assert_eq!(
        step,
        stdout(&[&["step"], &DEVICE[..], &filter, &wall].concat())
    );
    // the scene file, checked by the command line, gives the page's wall numbers
    let (status, scene) = server.get(&format!("/api/export/scene?{QUERY}"));
    assert_eq!(status, 200);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, &scene).unwrap();
    let report: serde_json::Value = serde_json::from_slice(&stdout(&[
        "scene",
        path.to_str().unwrap(),
        "--format",
        "json",
    ]))
    .unwrap();
    let (_, v) = server.json(&format!("/api/view?{QUERY}"));
    assert_eq!(report["devices"][0]["walls"][0], v["wall"]);
}

#[test]
fn bad_requests_get_clear_errors() {
    let server = Server::start();
    for (path, status, needle) in [
        ("/api/view?mass=-1", 400, "mass_kg"),
        ("/api/view?mass=abc", 400, "not a number"),
        ("/api/view?colour=red", 400, "unknown key 'colour'"),
        ("/api/view?delay=1e6", 400, "delay"),
        ("/api/view?velocity_filter_cutoff=1e6", 400, "cutoff"),
        ("/api/export/pdf", 404, "unknown export"),
        ("/nothing", 404, "no page"),
    ] {
        let (got, v) = server.json(path);
        assert_eq!(got, status, "{path}: {v}");
        let msg = v["error"].as_str().unwrap();
        assert!(msg.contains(needle), "{path}: {msg}");
    }
    // a name other than this machine's (DNS rebinding) is refused
    let (status, body) = server.get_as("evil.example:8080", "/api/view");
    assert_eq!(status, 403);
    assert!(String::from_utf8_lossy(&body).contains("localhost"));
    // and the server still answers
    assert_eq!(server.get("/").0, 200);
}

#[test]
fn concurrent_clients_are_answered_and_the_server_stops_itself() {
    let mut child = Command::new(assert_cmd::cargo::cargo_bin("stabound"))
        .args(["serve", "--port", "0", "--exit-after", "5"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let port: u16 = line
        .trim()
        .trim_end_matches('/')
        .rsplit(':')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let server = Server { child, port };
    let answers: Vec<u16> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..3)
            .map(|i| {
                let server = &server;
                s.spawn(move || server.get(&format!("/api/view?delay={}", i + 1)).0)
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    // each answered: computed, or refused as busy with a message
    assert!(answers.iter().all(|&s| s == 200 || s == 503), "{answers:?}");
    assert!(answers.contains(&200));
    let mut server = server;
    let start = Instant::now();
    let status = loop {
        if let Some(st) = server.child.try_wait().unwrap() {
            break st;
        }
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "the server did not stop"
        );
        std::thread::sleep(Duration::from_millis(100));
    };
    assert!(status.success());
}
