//! `stabound check --batch`: every wall of a CSV in one process, one output row per wall.

use std::io::Read;
use std::path::Path;

use anyhow::Context;
use rayon::prelude::*;
use stabound::export::report::shown_decided_radius;
use stabound::export::{Cell, Table, csv::CsvWriter, json::to_json_bytes};
use stabound::params::{Delay, Device, Plant, Wall};
use stabound::stability::{Checker, Method, Options, Verdict};

use super::super::UsageError;
use super::super::args::{PHYSICAL_DEVICE, missing};
use super::super::output::Progress;
use super::{Args, Format, verdict_status};

/// The largest batch file read: a million walls at about 60 bytes each.
const MAX_INPUT_BYTES: u64 = 64 << 20;

/// How the file gives its walls.
enum Columns {
    /// `alpha,beta,delta,d`, at these positions.
    Normalized([usize; 4]),
    /// `stiffness_N_per_m,wall_damping_Ns_per_m` on one device.
    Physical([usize; 2], Device),
}

/// The output bytes of a batch, and the exit status `--exit-status` asks for once they are
/// written.
pub fn run(a: &Args, input: &Path) -> anyhow::Result<(Vec<u8>, anyhow::Result<()>)> {
    let given = [
        ("--alpha", a.alpha.is_some()),
        ("--beta", a.beta.is_some()),
        ("--delta", a.delta.is_some()),
        ("--d", a.d.is_some()),
        ("--stiffness", a.stiffness.is_some()),
        ("--wall-damping", a.wall_damping.is_some()),
    ];
    if let Some((flag, _)) = given.iter().find(|(_, v)| *v) {
        return Err(UsageError(format!(
            "--batch reads the walls from the file; drop {flag} (the device may be given by --mass --period --damping --delay|--delay-samples)"
        ))
        .into());
    }
    let label = if input.as_os_str() == "-" {
        "stdin".to_string()
    } else {
        input.display().to_string()
    };
    let text = read_input(input)?;
    // the header is the first line that is not blank; the walls follow it
    let mut body = text.as_str();
    let header = loop {
        let Some((line, rest)) = next_line(body) else {
            return Err(UsageError(format!(
                "{label}: empty; the first line must name the columns (alpha,beta,delta,d or stiffness_N_per_m,wall_damping_Ns_per_m)"
            ))
            .into());
        };
        body = rest;
        if !line.trim().is_empty() {
            break line;
        }
    };
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let columns = columns(a, &names).with_context(|| format!("{label}: line 1"))?;
    let options = Options {
        method: a.method.into(),
        margin: a.margin,
    };
    // Physical walls share one device, so one checker of its loop (with the elements named)
    // serves every row.
    let shared = match &columns {
        Columns::Physical(_, device) => Some(Checker::new(a.elements(device)?, options)?),
        Columns::Normalized(_) if a.names_elements() => {
            return Err(UsageError(
                "loop elements are given in physical units: give the walls as stiffness_N_per_m,wall_damping_Ns_per_m with the device options".into(),
            )
            .into());
        }
        Columns::Normalized(_) => None,
    };
    let job = Job {
        columns: &columns,
        names: &names,
        shared: shared.as_ref(),
        options,
        // `--verdict-only` names the default output; clap refuses it beside `--radius`
        radius: a.radius,
    };
    let mut cols = Vec::new();
    if matches!(columns, Columns::Physical(..)) {
        cols.extend(["stiffness_N_per_m", "wall_damping_Ns_per_m"]);
    }
    cols.extend(["alpha", "beta", "delta", "d", "verdict"]);
    if job.radius {
        cols.push("spectral_radius");
    }
    cols.push("method");

    // Chunks of whole lines, each parsed, checked and formatted on its own (rayon) and then
    // joined in input order: the bytes do not depend on the number of threads.
    let base = text.len() - body.len();
    let chunks = split_lines(body, rayon::current_num_threads());
    let progress = Progress::new(chunks.iter().map(|c| c.2).sum());
    let parts: Vec<Result<Part, Failure>> = chunks
        .par_iter()
        .map(|&(start, chunk, lines)| {
            let start = base + start;
            stabound::cancel::poll().map_err(|e| Failure {
                offset: start,
                error: Fault::Wall(e.into()),
            })?;
            let part = match a.format {
                Format::Text => {
                    let mut w = CsvWriter::without_header(cols.len(), lines);
                    let worst = job.each(start, chunk, |r| r.write(&mut w))?;
                    Part::Csv(w.finish(), worst)
                }
                Format::Json => {
                    let mut rows = Vec::with_capacity(lines);
                    let worst = job.each(start, chunk, |r| rows.push(*r))?;
                    Part::Rows(rows, worst)
                }
            };
            progress.advance(lines);
            Ok(part)
        })
        .collect();
    progress.finish();

    let mut worst = Worst::default();
    let mut bytes = Vec::new();
    let mut table = Table::new(&cols);
    if a.format == Format::Text {
        bytes.reserve(parts.iter().flatten().map(Part::len).sum::<usize>() + 128);
        bytes.extend_from_slice(cols.join(",").as_bytes());
        bytes.push(b'\n');
    }
    for part in parts {
        // the first failing line in input order is the one reported
        let part = part.map_err(|f| {
            let line = 1 + memchr::memchr_iter(b'\n', &text.as_bytes()[..f.offset]).count();
            f.located(&label, line)
        })?;
        match part {
            Part::Csv(b, w) => {
                bytes.extend_from_slice(&b);
                worst.join(w);
            }
            Part::Rows(rows, w) => {
                table.reserve(rows.len());
                for r in &rows {
                    table.push_cells(r.cells());
                }
                worst.join(w);
            }
        }
    }
    if a.format == Format::Json {
        bytes = to_json_bytes(&table);
    }
    let status = if a.exit_status {
        verdict_status(worst.verdicts())
    } else {
        Ok(())
    };
    Ok((bytes, status))
}

/// Lines of walls per chunk at most: enough that a chunk's buffer and its rayon task cost
/// nothing beside its walls (some 60 bytes and a microsecond each at short delays).
const CHUNK_LINES: usize = 2048;

/// The first line of `text` (without its `\n` or `\r\n`) and the rest, as `str::lines`
/// splits them; `None` once `text` is empty.
fn next_line(text: &str) -> Option<(&str, &str)> {
    if text.is_empty() {
        return None;
    }
    let (line, rest) = match memchr::memchr(b'\n', text.as_bytes()) {
        Some(i) => (&text[..i], &text[i + 1..]),
        None => (text, ""),
    };
    Some((line.strip_suffix('\r').unwrap_or(line), rest))
}

/// `text` cut at line ends into chunks of consecutive lines, each with where it starts and
/// its number of lines: at most [`CHUNK_LINES`], and fewer for a short batch so that every one of `threads`
/// gets several chunks (a wall at a long delay takes milliseconds).
fn split_lines(text: &str, threads: usize) -> Vec<(usize, &str, usize)> {
    let ends: Vec<usize> = memchr::memchr_iter(b'\n', text.as_bytes()).collect();
    let lines = ends.len() + 1;
    let per = (lines / (4 * threads.max(1))).clamp(1, CHUNK_LINES);
    let mut chunks = Vec::with_capacity(lines / per + 1);
    let mut start = 0;
    for cut in ends.chunks(per) {
        // the chunk ends after the newline of its last line
        let end = cut.last().map_or(start, |e| e + 1);
        chunks.push((start, &text[start..end], cut.len()));
        start = end;
    }
    if start < text.len() {
        // the last line, without a newline
        chunks.push((start, &text[start..], 1));
    }
    chunks
}

/// `c` without the white space around it (as `str::trim`), at the cost of two byte tests
/// when it has none (a printable ASCII character is never white space).
fn trimmed(c: &str) -> &str {
    match (c.as_bytes().first(), c.as_bytes().last()) {
        (Some(a), Some(b)) if a.is_ascii_graphic() && b.is_ascii_graphic() => c,
        _ => c.trim(),
    }
}

/// The plant of the last wall (the bits of delta and d) and the checker kept for a run of
/// walls on one plant.
type Plants = (Option<(u64, u64)>, Option<((u64, u64), Checker)>);

/// What every chunk of a batch shares.
struct Job<'a> {
    columns: &'a Columns,
    /// The header's column names.
    names: &'a [&'a str],
    /// The one checker of physical walls (on one device).
    shared: Option<&'a Checker>,
    options: Options,
    /// Whether the spectral radius is computed and printed.
    radius: bool,
}

/// One wall's output row.
#[derive(Clone, Copy)]
struct Row {
    /// The stiffness and wall damping as given (physical walls).
    given: Option<[f64; 2]>,
    params: [f64; 4],
    verdict: Verdict,
    method: Method,
    radius: Option<f64>,
}

impl Row {
    /// Its cells, in the columns' order.
    fn cells(&self) -> impl Iterator<Item = Cell> {
        let given = self.given.into_iter().flatten().map(Cell::Num);
        let [alpha, beta, delta, d] = self.params;
        given
            .chain([alpha, beta, delta, d].map(Cell::Num))
            .chain([Cell::Static(self.verdict.name())])
            .chain(self.radius.map(Cell::Num))
            .chain([Cell::Static(self.method.name())])
    }

    /// Writes it as one CSV row, as [`to_csv_bytes`](stabound::export::csv::to_csv_bytes)
    /// writes [`Row::cells`].
    fn write(&self, w: &mut CsvWriter) {
        for v in self.given.into_iter().flatten() {
            w.num(v);
        }
        for v in self.params {
            w.num(v);
        }
        w.text(self.verdict.name());
        if let Some(r) = self.radius {
            w.num(r);
        }
        w.text(self.method.name());
    }
}

/// The worst verdicts of a run of walls (for `--exit-status`).
#[derive(Default, Clone, Copy)]
struct Worst {
    marginal: bool,
    unstable: bool,
}

impl Worst {
    fn add(&mut self, v: Verdict) {
        self.marginal |= v == Verdict::Marginal;
        self.unstable |= v == Verdict::Unstable;
    }

    fn join(&mut self, o: Worst) {
        self.marginal |= o.marginal;
        self.unstable |= o.unstable;
    }

    /// One verdict of each kind seen.
    fn verdicts(self) -> impl Iterator<Item = Verdict> {
        [
            (self.unstable, Verdict::Unstable),
            (self.marginal, Verdict::Marginal),
        ]
        .into_iter()
        .filter_map(|(seen, v)| seen.then_some(v))
    }
}

/// A chunk's output: CSV rows, or the rows themselves (for JSON).
enum Part {
    Csv(Vec<u8>, Worst),
    Rows(Vec<Row>, Worst),
}

impl Part {
    /// The length of its CSV bytes (none for rows).
    fn len(&self) -> usize {
        match self {
            Part::Csv(b, _) => b.len(),
            Part::Rows(..) => 0,
        }
    }
}

/// The error of a line, and the byte of the input text where the line starts.
struct Failure {
    offset: usize,
    error: Fault,
}

enum Fault {
    /// The line itself is malformed (what is wrong with it).
    Usage(String),
    /// The library refused its wall.
    Wall(anyhow::Error),
}

impl Failure {
    /// The error, naming the input and the line (1-based, in the whole file) where it is.
    fn located(self, label: &str, line: usize) -> anyhow::Error {
        match self.error {
            Fault::Usage(what) => UsageError(format!("{label}: line {line}: {what}")).into(),
            Fault::Wall(e) => e.context(format!("{label}: line {line}")),
        }
    }
}

impl Job<'_> {
    /// Every wall of `chunk` (whole lines starting at byte `start` of the input text)
    /// checked and handed to `emit` in order; blank lines are skipped. The worst verdicts
    /// seen, or the first line's failure.
    fn each(
        &self,
        start: usize,
        chunk: &str,
        mut emit: impl FnMut(&Row),
    ) -> Result<Worst, Failure> {
        let mut last = (None, None);
        let mut worst = Worst::default();
        let mut rest = chunk;
        while let Some((line, next)) = next_line(rest) {
            let offset = start + (chunk.len() - rest.len());
            rest = next;
            if trimmed(line).is_empty() {
                continue;
            }
            let row = self
                .row(line, &mut last)
                .map_err(|error| Failure { offset, error })?;
            worst.add(row.verdict);
            emit(&row);
        }
        Ok(worst)
    }

    /// The row of one line; `last` holds the plant of the wall before it (as the bits of
    /// delta and d) and the checker of the last plant seen twice in a row.
    fn row(&self, line: &str, last: &mut Plants) -> Result<Row, Fault> {
        // the header has two or four fields (`columns`)
        let mut cells = [""; 4];
        let mut n = 0;
        let mut from = 0;
        let commas = memchr::memchr_iter(b',', line.as_bytes());
        for end in commas.chain([line.len()]) {
            if let Some(c) = cells.get_mut(n) {
                *c = &line[from..end];
            }
            from = end + 1;
            n += 1;
        }
        if n != self.names.len() {
            return Err(Fault::Usage(format!(
                "{n} fields where the header has {}",
                self.names.len()
            )));
        }
        let mut v = [0.0; 4];
        for ((x, c), name) in v.iter_mut().zip(cells).zip(self.names) {
            let c = trimmed(c);
            *x = c
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| Fault::Usage(format!("{name} = {c:?} is not a finite number")))?;
        }
        let wall = |e: stabound::Error| Fault::Wall(e.into());
        let (given, params, (plant, wall_)) = match self.columns {
            Columns::Normalized([ia, ib, ix, id]) => {
                let p = [v[*ia], v[*ib], v[*ix], v[*id]];
                // the checks of `Normalized::new`, in its order, made once
                let plant = Plant::new(p[2], p[3]).map_err(wall)?;
                (None, p, (plant, Wall::new(p[0], p[1]).map_err(wall)?))
            }
            Columns::Physical([ik, ib], device) => {
                let n = device.normalize(v[*ik], v[*ib]).map_err(wall)?;
                let p = [n.alpha(), n.beta(), n.delta(), n.d()];
                (Some([v[*ik], v[*ib]]), p, n.split().map_err(wall)?)
            }
        };
        // A checker depends only on the plant, so consecutive walls on one plant share one.
        // It is kept from the second wall of a run on: moving a checker into the cache costs
        // more than a tenth of a short wall, which a file of all different plants would pay.
        let key = (plant.delta().to_bits(), plant.d().to_bits());
        let repeated = last.0.replace(key) == Some(key);
        let own;
        let checker = match (self.shared, &last.1) {
            (Some(checker), _) => checker,
            (None, Some((k, c))) if *k == key => c,
            (None, _) if repeated => {
                let c = Checker::new(plant, self.options).map_err(wall)?;
                &last.1.insert((key, c)).1
            }
            (None, _) => {
                own = Checker::new(plant, self.options).map_err(wall)?;
                &own
            }
        };
        // the radius (from the roots: most of the time at long delays) only when printed
        let (verdict, method, radius) = if self.radius {
            let (d, radius) = checker.decide_with_radius(&wall_).map_err(wall)?;
            let shown = shown_decided_radius(d.verdict, d.reason, radius, self.options.margin);
            (d.verdict, d.method, Some(shown))
        } else {
            let d = checker.decide(&wall_).map_err(wall)?;
            (d.verdict, d.method, None)
        };
        Ok(Row {
            given,
            params,
            verdict,
            method,
            radius,
        })
    }
}
/// Reads the whole batch input (a file or `-` for stdin), at most [`MAX_INPUT_BYTES`].
fn read_input(input: &Path) -> anyhow::Result<String> {
    let mut bytes = Vec::new();
    let limit = MAX_INPUT_BYTES + 1;
    if input.as_os_str() == "-" {
        std::io::stdin()
            .lock()
            .take(limit)
            .read_to_end(&mut bytes)
            .context("reading the walls from stdin")?;
    } else {
        let meta = std::fs::metadata(input)
            .map_err(|e| UsageError(format!("cannot read {}: {e}", input.display())))?;
        if !meta.is_file() {
            return Err(UsageError(format!(
                "{} is not a regular file; give a CSV file or - for stdin",
                input.display()
            ))
            .into());
        }
        std::fs::File::open(input)
            .and_then(|f| f.take(limit).read_to_end(&mut bytes))
            .map_err(|e| UsageError(format!("cannot read {}: {e}", input.display())))?;
    }
    if bytes.len() as u64 > MAX_INPUT_BYTES {
        return Err(UsageError(format!(
            "{} is larger than {} MiB; split it into several batches",
            input.display(),
            MAX_INPUT_BYTES >> 20
        ))
        .into());
    }
    String::from_utf8(bytes)
        .map_err(|_| UsageError(format!("{} is not UTF-8 text", input.display())).into())
}

/// Which columns hold the walls, and the device for physical ones.
fn columns(a: &Args, names: &[&str]) -> anyhow::Result<Columns> {
    let find = |want: &str| names.iter().position(|n| *n == want);
    let known = [
        "alpha",
        "beta",
        "delta",
        "d",
        "stiffness_N_per_m",
        "wall_damping_Ns_per_m",
    ];
    if let Some(n) = names.iter().find(|n| !known.contains(n)) {
        return Err(UsageError(format!(
            "unknown column {n:?}; the header names alpha,beta,delta,d or stiffness_N_per_m,wall_damping_Ns_per_m"
        ))
        .into());
    }
    if let (Some(k), Some(b)) = (find("stiffness_N_per_m"), find("wall_damping_Ns_per_m")) {
        if names.len() != 2 {
            return Err(UsageError(
                "give the walls either as alpha,beta,delta,d or as stiffness_N_per_m,wall_damping_Ns_per_m, not both".into(),
            )
            .into());
        }
        let delay = match (a.delay(), a.delay_samples()) {
            (Some(s), None) => Some(Delay::Seconds(s)),
            (None, Some(n)) => Some(Delay::Samples(n)),
            _ => None,
        };
        let (Some(m), Some(t), Some(damping), Some(delay)) =
            (a.mass(), a.period, a.damping(), delay)
        else {
            let device = [
                ("--mass", a.mass().is_some()),
                ("--period", a.period.is_some()),
                ("--damping", a.damping().is_some()),
                ("--delay|--delay-samples", delay.is_some()),
            ];
            return Err(missing(
                &device,
                &format!("walls in physical units need the device: {PHYSICAL_DEVICE}"),
            )
            .into());
        };
        let device = Device::new(m, t, damping, delay)?;
        device.plant()?;
        return Ok(Columns::Physical([k, b], device));
    }
    let missing: Vec<&str> = ["alpha", "beta", "delta", "d"]
        .into_iter()
        .filter(|n| find(n).is_none())
        .collect();
    if !missing.is_empty() || names.len() != 4 {
        return Err(UsageError(format!(
            "the header lacks {}; name alpha,beta,delta,d (or stiffness_N_per_m,wall_damping_Ns_per_m)",
            missing.join(", ")
        ))
        .into());
    }
    if [
        a.mass(),
        a.period,
        a.damping(),
        a.delay(),
        a.delay_samples(),
    ]
    .iter()
    .any(Option::is_some)
    {
        return Err(UsageError(
            "normalized walls carry their own delta and d; drop the device options".into(),
        )
        .into());
    }
    let at = |n| find(n).unwrap_or(0);
    Ok(Columns::Normalized([
        at("alpha"),
        at("beta"),
        at("delta"),
        at("d"),
    ]))
}
