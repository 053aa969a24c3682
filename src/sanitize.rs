//! Text from outside (file names, error messages) made safe to print on a terminal.

use std::path::Path;

/// Replaces every control character (C0, DEL, C1) by `?`, so no escape
/// sequence the user did not type ever reaches the terminal.
pub fn clean(text: &str) -> String {
    text.chars()
        .map(|c| if c.is_control() { '?' } else { c })
        .collect()
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
}
