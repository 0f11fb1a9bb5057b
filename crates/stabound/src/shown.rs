//! Numbers as messages show them ([`Shown`], [`numbers_shown`]): below the error type,
//! whose messages show their numbers so; the text module of the exports
//! ([`crate::export::text`]) re-exports them beside its other text.

use std::borrow::Cow;

/// A number as messages show it: the shortest digits that read back to the same `f64`
/// (Rust's `{}`), in exponent form outside `[1e-5, 1e16)` so that `5e-324` and `1e300` do
/// not print hundreds of zeros.
///
/// ```
/// use stabound::export::text::Shown;
/// assert_eq!(Shown(0.1).to_string(), "0.1");
/// assert_eq!(Shown(-1e-300).to_string(), "-1e-300");
/// assert_eq!(Shown(5e-324).to_string(), "5e-324");
/// assert_eq!(Shown(1e300).to_string(), "1e300");
/// assert_eq!(Shown(123456.75).to_string(), "123456.75");
/// assert_eq!(Shown(f64::NAN).to_string(), "NaN");
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shown(pub f64);

impl std::fmt::Display for Shown {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = self.0.abs();
        // exact comparisons: a zero and the non-finite values print plainly
        if a == 0.0 || !a.is_finite() || (1e-5..1e16).contains(&a) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

/// `s` with every number of more than 21 characters that an `f64` printed with `{}` wrote
/// (hundreds of zeros for `1e-300`) rewritten as [`Shown`] writes it, the same value in
/// exponent form. A run of digits that does not read back to the same text is left as it
/// is, so no digit is lost; shorter numbers are never touched.
///
/// ```
/// use stabound::export::text::numbers_shown;
/// let long = format!("invalid d = {}: a whole number of samples", 1e300);
/// assert_eq!(numbers_shown(&long), "invalid d = 1e300: a whole number of samples");
/// let small = format!("tol = -{}.", 1e-300);
/// assert_eq!(numbers_shown(&small), "tol = -1e-300.");
/// assert_eq!(numbers_shown("alpha = 0.19999999999999998"), "alpha = 0.19999999999999998");
/// let dots = format!("e.g. ... {}", 1e30);
/// assert_eq!(numbers_shown(&dots), "e.g. ... 1e30");
/// ```
pub fn numbers_shown(s: &str) -> Cow<'_, str> {
    /// Longer than any `f64` Rust writes with `{}` in `[1e-5, 1e16)`, sign aside.
    const LONG: usize = 21;
    let is_num = |c: char| c.is_ascii_digit() || c == '.';
    if !s.split(|c: char| !is_num(c)).any(|run| run.len() > LONG) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len());
    let mut rest = s;
    while let Some(start) = rest.find(is_num) {
        out.push_str(&rest[..start]);
        let tail = &rest[start..];
        let len = tail.find(|c: char| !is_num(c)).unwrap_or(tail.len());
        // a sentence's full stop is no part of the number (a run of dots alone is kept whole)
        let run = match tail[..len].trim_end_matches('.') {
            "" => &tail[..len],
            r => r,
        };
        match run.parse::<f64>() {
            Ok(v) if run.len() > LONG && format!("{v}") == run => {
                out.push_str(&Shown(v).to_string());
            }
            _ => out.push_str(run),
        }
        rest = &tail[run.len()..];
    }
    out.push_str(rest);
    Cow::Owned(out)
}
