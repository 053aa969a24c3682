//! The command line parser's own messages quote the user's arguments: they
//! reach the terminal with escape sequences and bidi controls replaced, and
//! the parser's exit codes are kept.

use crate::hostile;

#[test]
fn parser_errors_are_sanitised_and_keep_their_exit_code() {
    let evil = "x\u{1b}]52;c;SGVsbG8=\u{7}\u{202e}gnp.obj\u{1b}[2J";
    for args in [
        vec!["--scene", evil],
        vec!["render", "--out", "x.png", "--shading", evil],
        vec!["render", "--out", "x.png", "a.png", evil],
    ] {
        let o = hostile::relief(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.starts_with("error:"), "{err}");
        assert!(err.contains("gnp.obj"), "{err}");
        assert!(
            !err.chars()
                .any(|c| (c.is_control() && c != '\n') || c == '\u{202e}'),
            "{err}"
        );
        assert!(o.stdout.is_empty());
    }
    let help = hostile::relief(&["render", "--help"]);
    assert_eq!(help.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&help.stdout).contains("Usage: relief render"));
    let version = hostile::relief(&["--version"]);
    assert_eq!(version.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&version.stdout).starts_with("relief "));
}
