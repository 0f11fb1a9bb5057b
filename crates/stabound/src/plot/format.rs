//! Output formats of a figure, chosen by file extension: SVG (always), PNG (feature
//! `raster`: resvg and tiny-skia) and PDF (feature `pdf`: svg2pdf), both with the DejaVu
//! Sans font embedded in the crate, so that no system library or font is used.

use std::path::Path;

use crate::error::{Error, Result};

/// A figure file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Format {
    /// SVG 1.1 text, as written by [`super::Figure::to_svg`].
    Svg,
    /// PNG, one pixel per SVG pixel (feature `raster`).
    Png,
    /// PDF 1.7 with vector paths and the font embedded (feature `pdf`).
    Pdf,
}

impl Format {
    /// Every format, in the order of [`Format::EXTENSIONS`].
    pub const ALL: [Format; 3] = [Format::Svg, Format::Png, Format::Pdf];

    /// The accepted file extensions, as a message names them.
    pub const EXTENSIONS: &'static str = ".svg, .png or .pdf";

    /// The file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Svg => "svg",
            Format::Png => "png",
            Format::Pdf => "pdf",
        }
    }

    /// The format of an extension (without the dot, any case).
    pub fn from_extension(ext: &str) -> Result<Format> {
        Format::ALL
            .into_iter()
            .find(|f| f.extension().eq_ignore_ascii_case(ext))
            .ok_or_else(|| {
                Error::InvalidRequest(format!(
                    "a figure file named '.{ext}' has no known format: name it {} (the format follows the extension)",
                    Format::EXTENSIONS
                ))
            })
    }

    /// The format of a file by its extension: `.svg`, `.png` or `.pdf` (any case); a name
    /// without an extension (`/dev/stdout`, `plot`) is SVG. Any other extension is
    /// [`Error::InvalidRequest`].
    ///
    /// ```
    /// use stabound::plot::Format;
    /// use std::path::Path;
    ///
    /// assert_eq!(Format::from_path(Path::new("fig.PDF"))?, Format::Pdf);
    /// assert_eq!(Format::from_path(Path::new("/dev/stdout"))?, Format::Svg);
    /// assert!(Format::from_path(Path::new("fig.jpg")).is_err());
    /// # Ok::<(), stabound::Error>(())
    /// ```
    pub fn from_path(path: &Path) -> Result<Format> {
        match path.extension() {
            None => Ok(Format::Svg),
            Some(ext) => Format::from_extension(&ext.to_string_lossy()),
        }
    }

    /// Whether this build of the crate writes the format (PNG needs the feature `raster`,
    /// PDF the feature `pdf`).
    pub fn is_available(self) -> bool {
        match self {
            Format::Svg => true,
            Format::Png => cfg!(feature = "raster"),
            Format::Pdf => cfg!(feature = "pdf"),
        }
    }
}

/// An SVG document (as [`super::Figure::to_svg`] writes it) in `format`: the text itself for
/// SVG; for PNG, rendered by resvg at one pixel per SVG pixel on an opaque white
/// background; for PDF, converted by svg2pdf with the SVG's size at 96 pixels per inch
/// (480 px is 5 in), text as embedded DejaVu Sans.
///
/// A format whose feature is not compiled in, or an SVG that does not parse, is an
/// [`Error::InvalidRequest`]; a document too large to rasterize is [`Error::Numerical`].
pub fn render(svg: &str, format: Format) -> Result<Vec<u8>> {
    match format {
        Format::Svg => Ok(svg.as_bytes().to_vec()),
        Format::Png => png(svg),
        Format::Pdf => pdf(svg),
    }
}

#[cfg(any(feature = "raster", feature = "pdf"))]
fn tree(svg: &str) -> Result<usvg::Tree> {
    use std::sync::{Arc, OnceLock};
    static FONTS: OnceLock<Arc<usvg::fontdb::Database>> = OnceLock::new();
    let fonts = FONTS.get_or_init(|| {
        let mut db = usvg::fontdb::Database::new();
        db.load_font_data(include_bytes!("../../fonts/DejaVuSans.ttf").to_vec());
        db.set_sans_serif_family("DejaVu Sans");
        Arc::new(db)
    });
    let options = usvg::Options {
        font_family: "DejaVu Sans".into(),
        fontdb: fonts.clone(),
        ..usvg::Options::default()
    };
    usvg::Tree::from_str(svg, &options)
        .map_err(|e| Error::InvalidRequest(format!("the figure is not a valid SVG document: {e}")))
}

#[cfg(feature = "raster")]
fn png(svg: &str) -> Result<Vec<u8>> {
    use resvg::tiny_skia;
    let tree = tree(svg)?;
    let size = tree.size().to_int_size();
    let mut pixmap = tiny_skia::Pixmap::new(size.width(), size.height()).ok_or_else(|| {
        Error::Numerical(format!(
            "a figure of {} x {} pixels cannot be rasterized: give a smaller size",
            size.width(),
            size.height()
        ))
    })?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        tiny_skia::Transform::identity(),
        &mut pixmap.as_mut(),
    );
    pixmap
        .encode_png()
        .map_err(|e| Error::Numerical(format!("encoding the figure as PNG failed: {e}")))
}

#[cfg(not(feature = "raster"))]
fn png(_svg: &str) -> Result<Vec<u8>> {
    Err(Error::InvalidRequest(
        "PNG figures need the crate's `raster` feature: enable it, or write .svg".into(),
    ))
}

#[cfg(feature = "pdf")]
fn pdf(svg: &str) -> Result<Vec<u8>> {
    let tree = tree(svg)?;
    svg2pdf::to_pdf(
        &tree,
        svg2pdf::ConversionOptions::default(),
        svg2pdf::PageOptions { dpi: 96.0 },
    )
    .map_err(|e| Error::Numerical(format!("converting the figure to PDF failed: {e}")))
}

#[cfg(not(feature = "pdf"))]
fn pdf(_svg: &str) -> Result<Vec<u8>> {
    Err(Error::InvalidRequest(
        "PDF figures need the crate's `pdf` feature: enable it, or write .svg".into(),
    ))
}
