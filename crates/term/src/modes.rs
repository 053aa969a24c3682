//! The terminal's private modes (DECSET/DECRST) as a value: each app mode
//! says which set it wants, and only the difference from what the terminal
//! has is written. Leaving a mode therefore puts back what it changed.
//!
//! Mouse reporting is one setting with three levels (1000 buttons, 1002
//! drags, 1003 every motion), and terminals disagree on how their resets
//! combine: xterm, tmux and kitty keep one level, so resetting any of
//! them switches reporting off; others (WezTerm, Alacritty) keep one flag
//! per number. [`TermModes::change_to`] writes bytes that end in the same
//! modes under both readings, and [`TermModes::after`] decodes bytes under
//! either, so tests can check it.

/// How much mouse input the terminal reports, each level including the
/// ones below it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum MouseReports {
    Off,
    /// 1000: presses, releases and the wheel.
    Buttons,
    /// 1002: also motion while a button is held (drags).
    Drags,
    /// 1003: every motion (the plasma's light follows the pointer).
    Motion,
}

impl MouseReports {
    /// The levels that are switched on, lowest first, with their numbers.
    const LEVELS: [(MouseReports, u16); 3] = [
        (MouseReports::Buttons, 1000),
        (MouseReports::Drags, 1002),
        (MouseReports::Motion, 1003),
    ];
}

/// How a terminal combines mouse-mode resets (see the module comment).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MouseSemantics {
    /// One level: setting a number replaces it, resetting any clears it.
    OneLevel,
    /// One flag per number; the highest flag set decides.
    Flags,
}

/// The private modes relief sets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TermModes {
    /// 1049.
    pub alternate_screen: bool,
    /// 25 reset.
    pub cursor_hidden: bool,
    pub mouse: MouseReports,
    /// 1006: mouse coordinates as decimal numbers (no 223-column limit).
    pub sgr_mouse: bool,
    /// 2004: pasted text arrives marked as such.
    pub bracketed_paste: bool,
}

impl TermModes {
    /// A terminal as a shell leaves it.
    pub const SHELL: TermModes = TermModes {
        alternate_screen: false,
        cursor_hidden: false,
        mouse: MouseReports::Off,
        sgr_mouse: false,
        bracketed_paste: false,
    };

    /// What the app runs in: its own screen, no cursor, SGR mouse reports
    /// at `mouse`, bracketed paste.
    pub const fn app(mouse: MouseReports) -> TermModes {
        TermModes {
            alternate_screen: true,
            cursor_hidden: true,
            mouse,
            sgr_mouse: true,
            bracketed_paste: true,
        }
    }

    /// Appends to `out` the DECSET/DECRST sequences that take a terminal in
    /// `self` to `to` (nothing when they are equal). Modes are switched on
    /// in the order alternate screen, cursor, mouse, SGR, paste, and off in
    /// the reverse order.
    pub fn change_to(&self, to: &TermModes, out: &mut Vec<u8>) {
        // Per switch: its number, whether the app's side of it is on, and
        // whether the app's side is set (h) or reset (l).
        let switches = |m: &TermModes| {
            [
                (1049, m.alternate_screen, true),
                (25, m.cursor_hidden, false),
                (1006, m.sgr_mouse, true),
                (2004, m.bracketed_paste, true),
            ]
        };
        let (from, goal) = (switches(self), switches(to));
        let mut seq: Vec<(u16, bool)> = Vec::new();
        let switch = |seq: &mut Vec<(u16, bool)>, i: usize, on: bool| {
            let (n, was, set) = from[i];
            if was != on && goal[i].1 == on {
                seq.push((n, if on { set } else { !set }));
            }
        };
        for i in [3, 2] {
            switch(&mut seq, i, false);
        }
        // Mouse: resets of the levels no longer wanted (highest first),
        // then, as a reset may have cleared every level, all wanted levels
        // again; without a reset only the new ones.
        let mut reset = false;
        for &(level, n) in MouseReports::LEVELS.iter().rev() {
            if level <= self.mouse && level > to.mouse {
                seq.push((n, false));
                reset = true;
            }
        }
        for i in [1, 0] {
            switch(&mut seq, i, false);
        }
        for i in [0, 1] {
            switch(&mut seq, i, true);
        }
        for &(level, n) in MouseReports::LEVELS.iter() {
            if level <= to.mouse && (reset || level > self.mouse) {
                seq.push((n, true));
            }
        }
        for i in [2, 3] {
            switch(&mut seq, i, true);
        }
        for (n, set) in seq {
            out.extend_from_slice(format!("\x1b[?{n}{}", if set { 'h' } else { 'l' }).as_bytes());
        }
    }

    /// The modes of a terminal in `self` after it reads `bytes`, its mouse
    /// resets combined as `semantics` says. Only `ESC [ ? n… h|l` with the
    /// numbers above count; a sequence may carry several numbers (`;`).
    pub fn after(&self, bytes: &[u8], semantics: MouseSemantics) -> TermModes {
        let mut modes = *self;
        // Flags semantics: which of 1000, 1002, 1003 are set.
        let mut flags = [false; 3];
        for (i, &(level, _)) in MouseReports::LEVELS.iter().enumerate() {
            flags[i] = level <= self.mouse;
        }
        let mut i = 0;
        while let Some(at) = find(&bytes[i..], b"\x1b[?") {
            let start = i + at + 3;
            let end = match bytes[start..]
                .iter()
                .position(|b| !(b.is_ascii_digit() || *b == b';'))
            {
                Some(len) => start + len,
                None => break,
            };
            i = end;
            let set = match bytes[end] {
                b'h' => true,
                b'l' => false,
                _ => continue,
            };
            let params = std::str::from_utf8(&bytes[start..end]).unwrap_or("");
            for n in params.split(';').filter_map(|p| p.parse::<u16>().ok()) {
                match n {
                    1049 => modes.alternate_screen = set,
                    25 => modes.cursor_hidden = !set,
                    1006 => modes.sgr_mouse = set,
                    2004 => modes.bracketed_paste = set,
                    _ => {
                        let Some(k) = MouseReports::LEVELS.iter().position(|&(_, m)| m == n) else {
                            continue;
                        };
                        match semantics {
                            MouseSemantics::OneLevel => {
                                modes.mouse = if set {
                                    MouseReports::LEVELS[k].0
                                } else {
                                    MouseReports::Off
                                };
                            }
                            MouseSemantics::Flags => {
                                flags[k] = set;
                                modes.mouse = MouseReports::LEVELS
                                    .iter()
                                    .zip(flags)
                                    .filter(|(_, on)| *on)
                                    .map(|(&(level, _), _)| level)
                                    .max()
                                    .unwrap_or(MouseReports::Off);
                            }
                        }
                    }
                }
            }
        }
        modes
    }
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::guard::{RESTORE, SETUP};

    const SEMANTICS: [MouseSemantics; 2] = [MouseSemantics::OneLevel, MouseSemantics::Flags];
    const MICE: [MouseReports; 4] = [
        MouseReports::Off,
        MouseReports::Buttons,
        MouseReports::Drags,
        MouseReports::Motion,
    ];

    /// Every combination of the modes: 2⁴ switches × 4 mouse levels.
    fn all() -> Vec<TermModes> {
        let mut v = Vec::new();
        for bits in 0..16u8 {
            for mouse in MICE {
                v.push(TermModes {
                    alternate_screen: bits & 1 != 0,
                    cursor_hidden: bits & 2 != 0,
                    mouse,
                    sgr_mouse: bits & 4 != 0,
                    bracketed_paste: bits & 8 != 0,
                });
            }
        }
        v
    }

    #[test]
    fn every_change_ends_in_the_wanted_modes_under_both_readings() {
        for from in all() {
            for to in all() {
                let mut out = Vec::new();
                from.change_to(&to, &mut out);
                if from == to {
                    assert!(out.is_empty(), "{from:?}");
                }
                for s in SEMANTICS {
                    assert_eq!(from.after(&out, s), to, "{from:?} → {to:?} ({s:?})");
                }
            }
        }
    }

    #[test]
    fn leaving_all_motion_puts_drags_back() {
        let mut out = Vec::new();
        TermModes::app(MouseReports::Motion)
            .change_to(&TermModes::app(MouseReports::Drags), &mut out);
        assert_eq!(out, b"\x1b[?1003l\x1b[?1000h\x1b[?1002h");
        out.clear();
        TermModes::app(MouseReports::Drags)
            .change_to(&TermModes::app(MouseReports::Motion), &mut out);
        assert_eq!(out, b"\x1b[?1003h");
    }

    #[test]
    fn the_guard_sets_up_the_app_and_restores_the_shell_from_any_level() {
        let app = TermModes::app(MouseReports::Drags);
        // The guard's constants are the change written out once.
        let mut setup = Vec::new();
        TermModes::SHELL.change_to(&app, &mut setup);
        assert!(
            SETUP.starts_with(&setup),
            "{:?}",
            String::from_utf8_lossy(SETUP)
        );
        for s in SEMANTICS {
            assert_eq!(TermModes::SHELL.after(SETUP, s), app);
            for mouse in MICE {
                assert_eq!(TermModes::app(mouse).after(RESTORE, s), TermModes::SHELL);
            }
        }
    }

    #[test]
    fn several_numbers_in_one_sequence_count() {
        let m = TermModes::SHELL.after(
            b"x\x1b[?1049;1000;1006hy\x1b[?25l",
            MouseSemantics::OneLevel,
        );
        assert_eq!(
            m,
            TermModes {
                alternate_screen: true,
                cursor_hidden: true,
                mouse: MouseReports::Buttons,
                sgr_mouse: true,
                bracketed_paste: false,
            }
        );
    }
}
