//! Text from outside (file names, error messages) made safe to print on a terminal.

use std::path::Path;

/// Replaces every control character (C0, DEL, C1) by `?`, so no escape
/// sequence the user did not type ever reaches the terminal; bidirectional
/// controls too, so `x\u{202e}gnp.obj` cannot pass for `xjbo.png`.
pub fn clean(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_control() || is_bidi_control(c) {
                '?'
            } else {
                c
            }
        })
        .collect()
}

/// Like [`clean`] but keeps line breaks, for messages of several lines
/// (the command line parser's usage errors).
pub fn clean_lines(text: &str) -> String {
    text.split('\n').map(clean).collect::<Vec<_>>().join("\n")
}

/// The characters that reorder the text around them: embeddings and
/// overrides (U+202A..202E), isolates (U+2066..2069), marks (U+200E, U+200F,
/// U+061C).
fn is_bidi_control(c: char) -> bool {
    matches!(c, '\u{202A}'..='\u{202E}' | '\u{2066}'..='\u{2069}' | '\u{200E}' | '\u{200F}' | '\u{061C}')
}

/// A path for display: lossy UTF-8, control characters replaced.
pub fn display_path(path: &Path) -> String {
    clean(&path.to_string_lossy())
}

/// What an I/O error says, in plain words for a message: the system's
/// sentence without its "(os error N)" and starting in lower case ("no space
/// left on device"), control characters replaced.
pub fn io_reason(e: &std::io::Error) -> String {
    let text = e.to_string();
    let plain = match text.rfind(" (os error ") {
        Some(at) if text.ends_with(')') => &text[..at],
        _ => &text,
    };
    let mut chars = plain.chars();
    let first = chars.next().map(|c| c.to_lowercase().collect::<String>());
    clean(&(first.unwrap_or_default() + chars.as_str()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn io_errors_in_plain_words() {
        let os = |code| std::io::Error::from_raw_os_error(code);
        assert_eq!(io_reason(&os(libc::ENOSPC)), "no space left on device");
        assert_eq!(io_reason(&os(libc::EPIPE)), "broken pipe");
        assert_eq!(io_reason(&os(libc::ENOENT)), "no such file or directory");
        let own = std::io::Error::other("Bad\x1b[31m data");
        assert_eq!(io_reason(&own), "bad?[31m data");
    }

    #[test]
    fn escape_sequences_are_neutralised() {
        assert_eq!(clean("a\x1b[31mb\x07c\u{9b}d\ne"), "a?[31mb?c?d?e");
        assert_eq!(clean("brique.png"), "brique.png");
    }

    #[test]
    fn bidi_controls_are_neutralised() {
        assert_eq!(clean("x\u{202e}gnp.obj"), "x?gnp.obj");
        for c in [
            '\u{202A}', '\u{202D}', '\u{2066}', '\u{2069}', '\u{200E}', '\u{200F}', '\u{061C}',
        ] {
            assert_eq!(clean(&format!("a{c}b")), "a?b", "{:?}", c);
        }
        // Letters of right-to-left scripts stay.
        assert_eq!(clean("שלום.png"), "שלום.png");
        assert_eq!(clean_lines("a\x1b]52;c;x\x07\nb\r"), "a?]52;c;x?\nb?");
    }
}
