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

/// Why an input or output operation failed, in plain words: the system's
/// text without its "(os error N)" code, control characters replaced.
pub fn io_reason(e: &std::io::Error) -> String {
    use std::io::ErrorKind as K;
    let words = match e.kind() {
        K::NotFound => "no such file",
        K::PermissionDenied => "permission denied",
        K::IsADirectory => "it is a directory",
        K::NotADirectory => "a part of its path is not a directory",
        K::StorageFull => "no space left on the device",
        K::BrokenPipe => "the reader closed the pipe",
        K::UnexpectedEof => "it ends too early",
        K::InvalidFilename => "the name is too long or not valid",
        _ => {
            let text = e.to_string();
            let plain = match text.find(" (os error ") {
                Some(at) => &text[..at],
                None => &text,
            };
            return clean(plain);
        }
    };
    words.into()
}

/// A path for display: lossy UTF-8, control characters replaced.
pub fn display_path(path: &Path) -> String {
    clean(&path.to_string_lossy())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escape_sequences_are_neutralised() {
        assert_eq!(clean("a\x1b[31mb\x07c\u{9b}d\ne"), "a?[31mb?c?d?e");
        assert_eq!(clean("brique.png"), "brique.png");
    }

    #[test]
    fn io_reasons_have_no_error_codes() {
        use std::io::{Error, ErrorKind};
        assert_eq!(io_reason(&Error::from(ErrorKind::NotFound)), "no such file");
        assert_eq!(io_reason(&Error::from_raw_os_error(2)), "no such file");
        assert_eq!(
            io_reason(&Error::from_raw_os_error(28)),
            "no space left on the device"
        );
        // EIO: the system's words without the code.
        let eio = io_reason(&Error::from_raw_os_error(5));
        assert!(!eio.contains("os error") && !eio.is_empty(), "{eio}");
        assert_eq!(io_reason(&Error::other("bad\x1b[31m")), "bad?[31m");
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
