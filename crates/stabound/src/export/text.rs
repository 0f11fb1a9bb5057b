//! Text meant for a terminal: user-supplied strings (names from a scene file, paths)
//! escaped so that they cannot forge or hide report lines, and numbers computed from decimal
//! inputs shown as they were typed ([`as_typed`]).

use std::borrow::Cow;

/// `s` with every control character (C0, DEL, C1: newlines, carriage returns, terminal
/// escape sequences) and every bidirectional-text control (U+200E, U+200F, U+202A to
/// U+202E, U+2066 to U+2069) written as a `\u{..}` escape (`\n`, `\r`, `\t` as such), and
/// backslashes doubled, so that the escaped text is one visible line that reads back
/// unambiguously. Text without such characters is returned as it is.
///
/// Every plain-text report of the crate and the command line passes its user-supplied
/// strings through this function.
///
/// ```
/// use stabound::export::text::escape;
/// assert_eq!(escape("table top"), "table top");
/// assert_eq!(escape("w\n  wall \"x\": stable\x1b[2K"), "w\\n  wall \"x\": stable\\u{1b}[2K");
/// ```
pub fn escape(s: &str) -> Cow<'_, str> {
    if !s.chars().any(needs_escape) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        match c {
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if needs_escape(c) => out.push_str(&format!("\\u{{{:x}}}", c as u32)),
            c => out.push(c),
        }
    }
    Cow::Owned(out)
}

/// `s` in double quotes, [`escape`]d and with its own double quotes escaped, so that a name
/// cannot close its quotes early.
///
/// ```
/// use stabound::export::text::quoted;
/// assert_eq!(quoted("table top"), "\"table top\"");
/// assert_eq!(quoted("w\": stable"), "\"w\\\": stable\"");
/// ```
pub fn quoted(s: &str) -> String {
    format!("\"{}\"", escape(s).replace('"', "\\\""))
}

/// `x` as a person would type it: `0.1 * 3` is `0.30000000000000004` in `f64`, and a
/// damping of 55 N s/m normalized (`b T / m`) and scaled back (`delta m / T`) is
/// `54.99999999999999`. The nearest number of at most 15 significant digits replaces `x` when
/// it is within `2 * f64::EPSILON * |x|` of it (at least one ulp, at most two: the rounding
/// of a product and a quotient, or of `start + step * i`), so values that are decimal come
/// out as typed and any other value keeps every digit (1/3 is more than two ulps from
/// `0.333333333333333`).
///
/// ```
/// use stabound::export::text::as_typed;
/// assert_eq!(as_typed(0.1 * 3.0), 0.3);
/// assert_eq!(as_typed(55.0 * 1e-3 / 0.1 * 0.1 / 1e-3), 55.0);
/// assert_eq!(as_typed(1.0 / 3.0), 1.0 / 3.0);
/// ```
pub fn as_typed(x: f64) -> f64 {
    let short: f64 = format!("{x:.14e}").parse().unwrap_or(x);
    let ulp = f64::EPSILON * x.abs().max(f64::MIN_POSITIVE);
    if (short - x).abs() <= 2.0 * ulp {
        short
    } else {
        x
    }
}

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

fn needs_escape(c: char) -> bool {
    c == '\\'
        || c.is_control()
        || matches!(c, '\u{200e}' | '\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_controls_and_keeps_the_rest() {
        assert_eq!(escape("PHANToM-like δ"), "PHANToM-like δ");
        assert_eq!(escape("a\\b"), "a\\\\b");
        assert_eq!(escape("\u{202e}x\u{7f}\u{85}"), "\\u{202e}x\\u{7f}\\u{85}");
        assert!(!escape("x\r\ny\x1b[1A\tz").chars().any(char::is_control));
    }
}
