//! `stabound serve`: the explorer, a local web page that draws one device's stable region
//! live, with its K_max, a wall to drag, the wall's verdict, margin and step response, and the
//! passive region; its exports are the bytes the command line writes for the same input.
//!
//! The HTTP server is `tiny_http` (synchronous, a handful of small dependencies): the page
//! is served from the binary, requests are answered by a fixed set of threads, and each
//! computation runs on its own thread under a time limit, at most [`MAX_JOBS`] at once.

mod view;

use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use anyhow::Context;
use serde_json::json;
use tiny_http::{Header, Method, Request, Response, Server};

use super::UsageError;
use view::State;

/// Threads that read requests and answer them: enough for a page's parallel requests and a
/// few clients at once; more wait in the socket's queue.
const WORKERS: usize = 8;

/// Computations running at once; a request beyond them is refused (busy) instead of queued,
/// so that no client can pile up work. Each uses every core itself (rayon).
pub const MAX_JOBS: usize = 4;

/// The longest a computation may take before its request is answered with an error; the
/// computation is cancelled then and stops at its engines' next poll, freeing its place
/// among the [`MAX_JOBS`].
pub const TIME_LIMIT: Duration = Duration::from_secs(20);

/// How long past [`TIME_LIMIT`] a request waits for its cancelled computation to stop
/// before it is answered regardless (a step that does not poll: a long simulation).
const STOP_GRACE: Duration = Duration::from_secs(2);

/// The longest request line (path and query) accepted: a full state is under 1 kB.
const MAX_URL: usize = 4096;

const PAGE: &str = include_str!("serve/index.html");
const SCRIPT: &str = include_str!("serve/app.js");
const STYLE: &str = include_str!("serve/style.css");

/// Serve the explorer on this machine.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// TCP port (0: any free port; the URL printed says which).
    #[arg(long, default_value_t = 8080)]
    port: u16,
    /// Address to listen on. The page answers only requests addressed to localhost,
    /// 127.0.0.1 or [::1] whatever the address.
    #[arg(long, default_value_t = IpAddr::V4(Ipv4Addr::LOCALHOST))]
    bind: IpAddr,
    /// Open the page in the default browser.
    #[arg(long)]
    open: bool,
    /// Stop after this many seconds (for scripts and tests; default: run until interrupted).
    #[arg(long = "exit-after", value_parser = super::args::finite, allow_hyphen_values = true)]
    exit_after: Option<f64>,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let stop_at = match a.exit_after {
        Some(s) if !(s > 0.0 && s <= 1e9) => {
            return Err(
                UsageError(format!("--exit-after {s} must be a number of seconds > 0")).into(),
            );
        }
        Some(s) => Some(Instant::now() + Duration::from_secs_f64(s)),
        None => None,
    };
    let addr = SocketAddr::new(a.bind, a.port);
    let server = Server::http(addr)
        .map_err(|e| anyhow::anyhow!("cannot listen on {addr}: {e}; pick another --port"))?;
    let local = server
        .server_addr()
        .to_ip()
        .context("the server has no IP address")?;
    let url = match local.ip() {
        IpAddr::V6(ip) => format!("http://[{ip}]:{}/", local.port()),
        IpAddr::V4(ip) => format!("http://{ip}:{}/", local.port()),
    };
    {
        use std::io::Write;
        let mut out = std::io::stdout().lock();
        writeln!(out, "{url}")?;
        out.flush()?;
    }
    eprintln!("stabound serve: the explorer is at {url} (Ctrl-C stops it)");
    if a.open {
        open_browser(&url);
    }
    let server = Arc::new(server);
    let jobs = Arc::new(AtomicUsize::new(0));
    let workers: Vec<_> = (0..WORKERS)
        .map(|_| {
            let (server, jobs) = (Arc::clone(&server), Arc::clone(&jobs));
            std::thread::spawn(move || {
                loop {
                    let wait = match stop_at {
                        Some(t) => t.saturating_duration_since(Instant::now()),
                        None => Duration::from_secs(3600),
                    };
                    if stop_at.is_some() && wait.is_zero() {
                        return;
                    }
                    match server.recv_timeout(wait) {
                        Ok(Some(rq)) => handle(rq, &jobs),
                        Ok(None) => {}
                        Err(_) => return,
                    }
                }
            })
        })
        .collect();
    for w in workers {
        let _ = w.join();
    }
    Ok(())
}

fn open_browser(url: &str) {
    let opener = if cfg!(target_os = "macos") {
        "open"
    } else if cfg!(windows) {
        "explorer"
    } else {
        "xdg-open"
    };
    if let Err(e) = std::process::Command::new(opener).arg(url).spawn() {
        eprintln!("stabound serve: cannot open a browser ({opener}: {e}); open {url} yourself");
    }
}

/// A response: status, content type, body, and a file name for downloads.
struct Answer {
    status: u16,
    kind: &'static str,
    body: Vec<u8>,
    file: Option<&'static str>,
}

impl Answer {
    fn ok(kind: &'static str, body: impl Into<Vec<u8>>) -> Self {
        Self {
            status: 200,
            kind,
            body: body.into(),
            file: None,
        }
    }

    fn error(status: u16, message: &str) -> Self {
        let body = json!({ "error": message }).to_string();
        Self {
            status,
            kind: "application/json",
            body: body.into_bytes(),
            file: None,
        }
    }
}

/// Whether a Host header names this machine: localhost, 127.0.0.1 or [::1], any port. A page
/// of another site that resolves its name to 127.0.0.1 (DNS rebinding) sends its own name.
pub fn local_host(host: &str) -> bool {
    let name = if let Some(rest) = host.strip_prefix('[') {
        match rest.split_once(']') {
            Some((ip, port)) if port.is_empty() || port.starts_with(':') => {
                return ip == "::1" && valid_port(port);
            }
            _ => return false,
        }
    } else {
        match host.split_once(':') {
            Some((name, port)) if valid_port(&format!(":{port}")) => name,
            Some(_) => return false,
            None => host,
        }
    };
    name.eq_ignore_ascii_case("localhost") || name == "127.0.0.1"
}

fn valid_port(p: &str) -> bool {
    p.is_empty()
        || p.strip_prefix(':')
            .is_some_and(|n| n.parse::<u16>().is_ok())
}

fn handle(rq: Request, jobs: &Arc<AtomicUsize>) {
    let answer = answer(&rq, jobs);
    let mut response = Response::from_data(answer.body).with_status_code(answer.status);
    let mut headers = vec![
        ("Content-Type", answer.kind.to_string()),
        ("Cache-Control", "no-store".to_string()),
        ("X-Content-Type-Options", "nosniff".to_string()),
    ];
    if let Some(f) = answer.file {
        headers.push((
            "Content-Disposition",
            format!("attachment; filename=\"{f}\""),
        ));
    }
    for (k, v) in headers {
        if let Ok(h) = Header::from_bytes(k.as_bytes(), v.as_bytes()) {
            response.add_header(h);
        }
    }
    // a client that went away is no failure of the server
    let _ = rq.respond(response);
}

fn answer(rq: &Request, jobs: &Arc<AtomicUsize>) -> Answer {
    let host = rq
        .headers()
        .iter()
        .find(|h| h.field.equiv("Host"))
        .map(|h| h.value.as_str().to_string());
    match host {
        Some(h) if local_host(&h) => {}
        Some(h) => {
            return Answer::error(
                403,
                &format!(
                    "the explorer answers only requests addressed to localhost, 127.0.0.1 or [::1], not '{h}'"
                ),
            );
        }
        None => return Answer::error(400, "the request has no Host header"),
    }
    if rq.url().len() > MAX_URL {
        return Answer::error(414, &format!("the request is longer than {MAX_URL} bytes"));
    }
    if *rq.method() != Method::Get {
        return Answer::error(405, "the explorer answers GET requests only");
    }
    let (path, query) = rq.url().split_once('?').unwrap_or((rq.url(), ""));
    match path {
        "/" | "/index.html" => Answer::ok("text/html; charset=utf-8", PAGE),
        "/app.js" => Answer::ok("text/javascript; charset=utf-8", SCRIPT),
        "/style.css" => Answer::ok("text/css; charset=utf-8", STYLE),
        "/api/params" => Answer::ok("application/json", view::params_json().to_string()),
        "/api/view" => compute(jobs, query.to_string(), |s| {
            Ok(Answer::ok("application/json", s.view()?.to_string()))
        }),
        p if p.starts_with("/api/export/") => {
            let Some(kind) = Export::from_name(&p["/api/export/".len()..]) else {
                return Answer::error(
                    404,
                    "unknown export: csv, svg, png, c, step, scene or report",
                );
            };
            compute(jobs, query.to_string(), move |s| kind.run(s))
        }
        _ => Answer::error(404, &format!("no page at {path}")),
    }
}

/// Runs `work` on the state of `query` on threads of its own, at most [`MAX_JOBS`] at once,
/// cancelled at [`TIME_LIMIT`] (the other computations go on) and answered by then; an error
/// becomes a JSON message (400 for bad input).
fn compute<F>(jobs: &Arc<AtomicUsize>, query: String, work: F) -> Answer
where
    F: FnOnce(&State) -> anyhow::Result<Answer> + Send + 'static,
{
    if jobs.fetch_add(1, Ordering::SeqCst) >= MAX_JOBS {
        jobs.fetch_sub(1, Ordering::SeqCst);
        return Answer::error(
            503,
            &format!("the explorer is busy ({MAX_JOBS} computations running); try again"),
        );
    }
    let (tx, rx) = mpsc::channel();
    let counter = Arc::clone(jobs);
    let spawned = std::thread::Builder::new().spawn(move || {
        // its own threads: a computation past its limit stops without stopping the others,
        // and the others' parallel work never waits behind its
        let limit = stabound::Cancel::with_time_limit(TIME_LIMIT);
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            limit
                .scope_on_own_threads(0, || {
                    State::parse(&query)
                        .map_err(anyhow::Error::from)
                        .and_then(|s| work(&s))
                })
                .map_err(anyhow::Error::from)
                .and_then(|r| r)
        }));
        counter.fetch_sub(1, Ordering::SeqCst);
        let _ = tx.send(result);
    });
    if spawned.is_err() {
        jobs.fetch_sub(1, Ordering::SeqCst);
        return Answer::error(503, "the explorer cannot start a thread; try again");
    }
    let too_long = || {
        Answer::error(
            503,
            &format!(
                "the computation takes longer than {} s: choose a shorter delay or fewer elements",
                TIME_LIMIT.as_secs()
            ),
        )
    };
    match rx.recv_timeout(TIME_LIMIT + STOP_GRACE) {
        Ok(Ok(Ok(answer))) => answer,
        Ok(Ok(Err(err)))
            if err.chain().any(|c| {
                matches!(
                    c.downcast_ref::<stabound::Error>(),
                    Some(stabound::Error::Cancelled { .. })
                )
            }) =>
        {
            too_long()
        }
        Ok(Ok(Err(err))) => {
            let message = format!("{err:#}").replace('\n', " ");
            let bad_input = err.chain().any(|c| {
                c.downcast_ref::<UsageError>().is_some()
                    || matches!(
                        c.downcast_ref::<stabound::Error>(),
                        Some(
                            stabound::Error::InvalidParameter { .. }
                                | stabound::Error::InvalidRequest(_)
                                | stabound::Error::Request(_)
                        )
                    )
            });
            Answer::error(if bad_input { 400 } else { 500 }, &message)
        }
        Ok(Err(_)) => Answer::error(500, "the computation failed unexpectedly"),
        Err(_) => too_long(),
    }
}

/// The exports: each is the output of one command line for the page's state.
#[derive(Debug, Clone, Copy)]
enum Export {
    /// `stabound boundary ... -o FILE` (CSV).
    Csv,
    /// `stabound boundary ... --svg FILE` (SVG, or PNG for a `.png` file).
    Svg,
    Png,
    /// `stabound table ... --format c`.
    C,
    /// `stabound step ... --stiffness K --wall-damping B` (CSV).
    Step,
    /// The scene file of the device and wall.
    Scene,
    /// `stabound scene FILE --format json`.
    Report,
}

impl Export {
    fn from_name(name: &str) -> Option<Self> {
        Some(match name {
            "csv" => Self::Csv,
            "svg" => Self::Svg,
            "png" => Self::Png,
            "c" => Self::C,
            "step" => Self::Step,
            "scene" => Self::Scene,
            "report" => Self::Report,
            _ => return None,
        })
    }

    /// The command line (after `stabound`) that writes this export into `dir`, its file name
    /// and its content type.
    pub fn command(self, s: &State, dir: &str) -> (Vec<String>, &'static str, &'static str) {
        let out = |f: &str| format!("{dir}/{f}");
        let mut args: Vec<String> = Vec::new();
        let (file, kind) = match self {
            Self::Csv => {
                args.push("boundary".into());
                args.extend(s.device_flags());
                args.extend(["-o".into(), out("boundary.csv")]);
                ("boundary.csv", "text/csv")
            }
            Self::Svg | Self::Png => {
                let (file, kind) = match self {
                    Self::Png => ("boundary.png", "image/png"),
                    _ => ("boundary.svg", "image/svg+xml"),
                };
                args.push("boundary".into());
                args.extend(s.device_flags());
                args.extend(["-o".into(), out("boundary.csv")]);
                args.extend(["--svg".into(), out(file)]);
                (file, kind)
            }
            Self::C => {
                args.push("table".into());
                args.extend(s.device_flags());
                args.extend(["--format".into(), "c".into(), "-o".into(), out("table.h")]);
                ("table.h", "text/x-c")
            }
            Self::Step => {
                args.push("step".into());
                args.extend(s.device_flags());
                args.extend(s.wall_flags());
                args.extend(["-o".into(), out("step.csv")]);
                ("step.csv", "text/csv")
            }
            Self::Scene => ("scene.toml", "application/toml"),
            Self::Report => {
                args.extend(["scene".into(), out("scene.toml"), "--format".into()]);
                args.extend(["json".into(), "-o".into(), out("report.json")]);
                ("report.json", "application/json")
            }
        };
        (args, file, kind)
    }

    fn run(self, s: &State) -> anyhow::Result<Answer> {
        // the library reads the scene first: a bad value is refused with its message
        s.scene()?;
        let dir = tempfile::tempdir().context("cannot make a temporary directory")?;
        let path = dir.path().to_string_lossy().into_owned();
        let toml = s.scene_toml();
        std::fs::write(dir.path().join("scene.toml"), &toml)?;
        let (args, file, kind) = self.command(s, &path);
        if !args.is_empty() {
            super::run_args(std::iter::once("stabound".to_string()).chain(args))?;
        }
        let body = std::fs::read(dir.path().join(file))?;
        Ok(Answer {
            status: 200,
            kind,
            body,
            file: Some(file),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hosts() {
        for ok in [
            "localhost",
            "localhost:8080",
            "LOCALHOST:1",
            "127.0.0.1",
            "127.0.0.1:65535",
            "[::1]",
            "[::1]:80",
        ] {
            assert!(local_host(ok), "{ok}");
        }
        for bad in [
            "evil.example",
            "evil.example:8080",
            "localhost.evil.example",
            "127.0.0.1.nip.io",
            "127.0.0.2",
            "[::2]:80",
            "[::1]x",
            "localhost:99999",
            "localhost:80:80",
            "",
        ] {
            assert!(!local_host(bad), "{bad}");
        }
    }

    #[test]
    fn states() {
        assert!(State::parse("mass=0.1&delay=2").is_ok());
        for bad in [
            "mass=abc",
            "mass=inf",
            "nope=1",
            "delay=1000",
            "encoder=belt",
            "mass=",
            "mass=1&mass=2",
            "velocity_filter_order=two",
        ] {
            assert!(State::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn every_element_parameter_reaches_the_flags_and_the_scene() {
        let s = State::parse(
            "damping=4&handle_mass=0.03&transmission_stiffness=2e5&motor_damping=2.5&handle_damping=1.5&encoder=handle&velocity_filter_cutoff=150&velocity_filter_order=2",
        )
        .unwrap();
        let flags = s.device_flags().join(" ");
        for f in [
            "--motor-damping 2.5",
            "--handle-damping 1.5",
            "--encoder handle",
            "--velocity-filter-order 2",
        ] {
            assert!(flags.contains(f), "{flags}");
        }
        let scene = s.scene().unwrap();
        let e = &scene.devices[0].elements;
        assert_eq!((e.motor_damping, e.handle_damping), (Some(2.5), Some(1.5)));
        assert_eq!(e.velocity_filter_order, Some(2));
        // every parameter of the list is described to the page
        let described = view::params_json()["params"].as_array().unwrap().len();
        assert_eq!(described, stabound::elements::list::PARAMS.len());
    }
}
