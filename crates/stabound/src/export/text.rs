//! Text meant for a terminal: user-supplied strings (names from a scene file, paths)
//! escaped so that they cannot forge or hide report lines, and numbers computed from decimal
//! inputs shown as they were typed ([`as_typed`]).

use std::borrow::Cow;

pub use crate::shown::{Shown, numbers_shown};

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
