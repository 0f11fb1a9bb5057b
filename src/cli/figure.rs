//! `stabound figure`: the paper's figures (SVG, PNG or PDF) plus the CSV behind each, and the
//! one place where every subcommand turns a figure output's file name into its format.

use std::path::{Path, PathBuf};
use std::time::Instant;

use rayon::prelude::*;
use stabound::figures::{FIGURES, FigureData, figure};
use stabound::plot::{Figure, FigureStyle, Format};

use super::UsageError;
use super::output::Plan;

/// The format of a figure output file from its extension (`.svg`, `.png`, `.pdf`; none is
/// SVG), checked before any work: an unknown extension is a usage error naming the option.
pub fn format_of(flag: &str, path: &Path) -> Result<Format, UsageError> {
    let shown = stabound::export::text::escape(&path.display().to_string()).into_owned();
    Format::from_path(path).map_err(|e| UsageError(format!("{flag} {shown}: {e}")))
}

/// The format of an optional figure output (`--svg FILE`): [`format_of`] when given.
pub fn option_format(flag: &str, path: Option<&Path>) -> Result<Format, UsageError> {
    path.map_or(Ok(Format::Svg), |p| format_of(flag, p))
}

/// The formats of a list of extensions (`svg,pdf`), without repeats; an unknown one is a
/// usage error naming the option.
pub fn formats_of(flag: &str, extensions: &[String]) -> Result<Vec<Format>, UsageError> {
    let mut formats: Vec<Format> = Vec::new();
    for e in extensions {
        let f = Format::from_extension(e.trim().trim_start_matches('.'))
            .map_err(|err| UsageError(format!("{flag} {e}: {err}")))?;
        if !formats.contains(&f) {
            formats.push(f);
        }
    }
    Ok(formats)
}

/// The bytes of `figure` in `format`.
pub fn render(figure: &Figure, format: Format) -> anyhow::Result<Vec<u8>> {
    Ok(stabound::plot::render(&figure.to_svg()?, format)?)
}

/// Size and font of the drawn figures.
#[derive(Debug, Clone, clap::Args)]
pub struct StyleArgs {
    /// Width of each panel in pixels (1/96 in; PDF pages are 3/4 of it in points).
    #[arg(long, default_value_t = FigureStyle::default().width())]
    width: f64,
    /// Height of each panel in pixels.
    #[arg(long, default_value_t = FigureStyle::default().height())]
    height: f64,
    /// Font size of labels and legends in pixels (tick labels are 7/8 of it); the default
    /// prints at about 8 pt when a panel is scaled to one journal column (3.5 in).
    #[arg(long = "font-size", default_value_t = FigureStyle::default().font_size())]
    font_size: f64,
    /// Lines without markers (colour and dash only).
    #[arg(long = "no-markers")]
    no_markers: bool,
}

impl StyleArgs {
    /// The checked style.
    pub fn style(&self) -> anyhow::Result<FigureStyle> {
        Ok(FigureStyle::new(self.width, self.height, self.font_size)?
            .with_markers(!self.no_markers))
    }
}

/// Size and font of the drawing of a command's `--svg FILE`: each option given replaces the
/// figure's own choice (which grows the canvas for many curves), the others keep it.
#[derive(Debug, Clone, clap::Args)]
pub struct SvgStyleArgs {
    /// With --svg: width of the drawing in pixels (1/96 in; PDF pages are 3/4 of it in
    /// points) [default 480; boundary with more than 6 curves 720].
    #[arg(long, value_parser = super::args::finite, requires = "svg")]
    width: Option<f64>,
    /// With --svg: height of the drawing in pixels [default 360; boundary with more than 6
    /// curves 540].
    #[arg(long, value_parser = super::args::finite, requires = "svg")]
    height: Option<f64>,
    /// With --svg: font size of labels and legends in pixels (tick labels are 7/8 of it).
    #[arg(long = "font-size", value_parser = super::args::finite, requires = "svg")]
    font_size: Option<f64>,
    /// With --svg: lines without markers (colour and dash only).
    #[arg(long = "no-markers", requires = "svg")]
    no_markers: bool,
}

impl SvgStyleArgs {
    /// Checks the given options before any work (with the default style for the others).
    pub fn check(&self) -> anyhow::Result<()> {
        self.apply(Figure::new("", "", "")).map(|_| ())
    }

    /// `figure` with the given options applied, checked by the library's style.
    pub fn apply(&self, mut figure: Figure) -> anyhow::Result<Figure> {
        let s = figure.style;
        figure.style = FigureStyle::new(
            self.width.unwrap_or(s.width()),
            self.height.unwrap_or(s.height()),
            self.font_size.unwrap_or(s.font_size()),
        )?
        .with_markers(s.markers() && !self.no_markers);
        Ok(figure)
    }
}

/// Writes DIR/figNN.svg (or .png, .pdf) and DIR/figNN.csv for one of the paper's figures
/// (5 to 11) or all.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Figure number (5, 6, 7, 8, 9, 10, 11) or `all`.
    which: String,
    /// Directory to write into (created if missing).
    #[arg(short = 'o', long = "output-dir", default_value = ".")]
    out: PathBuf,
    /// File extensions of the drawings, one file per extension: svg, png, pdf (a list, e.g.
    /// `svg,pdf`); the format follows the extension.
    #[arg(long = "extension", value_delimiter = ',', default_value = "svg")]
    extensions: Vec<String>,
    #[command(flatten)]
    style: StyleArgs,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let numbers: Vec<u32> = if a.which.eq_ignore_ascii_case("all") {
        FIGURES.to_vec()
    } else {
        let n: u32 = a.which.trim().parse().map_err(|_| {
            UsageError(format!(
                "'{}' is not a figure; give one of 5, 6, 7, 8, 9, 10, 11 or all",
                a.which
            ))
        })?;
        if !FIGURES.contains(&n) {
            return Err(UsageError(format!(
                "the paper has no figure {n} with data; give one of 5, 6, 7, 8, 9, 10, 11 or all"
            ))
            .into());
        }
        vec![n]
    };
    let formats = formats_of("--extension", &a.extensions)?;
    let style = a.style.style()?;
    output_dir("--output-dir", &a.out)?;
    let names: Vec<String> = numbers.iter().map(|n| format!("fig{n:02}")).collect();
    let (paths, slots, mut out) = plan_figures(&a.out, &names, &formats, "--output-dir")?;
    let start = Instant::now();
    // Figures are independent; compute them in parallel, collect in order.
    let data: Vec<FigureData> = numbers
        .par_iter()
        .map(|&n| figure(n).map(|fd| fd.with_style(style)))
        .collect::<stabound::Result<_>>()?;
    for (fd, name) in data.iter().zip(&names) {
        if &fd.name != name {
            anyhow::bail!("figure {name} is named {}", fd.name);
        }
    }
    write_figures(&mut out, &data, &formats, &slots)?;
    out.finish()?;
    report(&paths);
    eprintln!(
        "{} figure(s) in {:.2} s",
        data.len(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

/// The directory of a figure command's outputs: an existing one, or created now, before any
/// work; anything else is a usage error naming the option.
pub fn output_dir(flag: &str, dir: &Path) -> Result<(), UsageError> {
    let shown = stabound::export::text::escape(&dir.display().to_string()).into_owned();
    if dir.exists() && !dir.is_dir() {
        return Err(UsageError(format!(
            "{flag} {shown}: is not a directory; give a directory (created if missing)"
        )));
    }
    std::fs::create_dir_all(dir)
        .map_err(|e| UsageError(format!("{flag} {shown}: cannot create the directory ({e})")))
}

/// The output slots of figures `names` in `dir`: per figure one drawing per format and the
/// CSV, checked together before any work.
pub type Slots = Vec<(Vec<super::output::Slot>, super::output::Slot)>;

/// Plans DIR/NAME.EXT for every format and DIR/NAME.csv for each name; returns the paths (for
/// the report), the slots and the checked outputs.
pub fn plan_figures(
    dir: &Path,
    names: &[String],
    formats: &[Format],
    flag: &'static str,
) -> anyhow::Result<(Vec<PathBuf>, Slots, super::output::Outputs)> {
    let per = formats.len() + 1;
    let paths: Vec<PathBuf> = names
        .iter()
        .flat_map(|name| {
            formats
                .iter()
                .map(move |f| dir.join(format!("{name}.{}", f.extension())))
                .chain(std::iter::once(dir.join(format!("{name}.csv"))))
        })
        .collect();
    let mut outputs = Plan::new();
    let all: Vec<super::output::Slot> = paths.iter().map(|p| outputs.file(flag, p)).collect();
    let out = outputs.check()?;
    let slots = all
        .chunks(per)
        .map(|c| (c[..per - 1].to_vec(), c[per - 1]))
        .collect();
    Ok((paths, slots, out))
}

/// Writes every figure's drawings and CSV into the slots of [`plan_figures`].
pub fn write_figures(
    out: &mut super::output::Outputs,
    data: &[FigureData],
    formats: &[Format],
    slots: &Slots,
) -> anyhow::Result<()> {
    for (fd, (drawings, csv)) in data.iter().zip(slots) {
        let svg = fd.to_svg()?;
        for (f, slot) in formats.iter().zip(drawings) {
            out.write(*slot, &stabound::plot::render(&svg, *f)?)?;
        }
        out.write(*csv, fd.to_csv().as_bytes())?;
    }
    Ok(())
}

/// Names every written file on stderr.
pub fn report(paths: &[PathBuf]) {
    for p in paths {
        eprintln!(
            "wrote {}",
            stabound::export::text::escape(&p.display().to_string())
        );
    }
}
