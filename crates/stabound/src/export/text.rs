//! Text meant for a terminal: user-supplied strings (names from a scene file, paths)
//! escaped so that they cannot forge or hide report lines.

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
