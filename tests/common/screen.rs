//! A model of the terminal screen that replays what relief writes, shared
//! by the test crates that check the bytes on the wire.
#![allow(dead_code)] // each crate uses part of it

use ratatui::style::Color;

/// A terminal screen that understands what the backend emits: cursor
/// moves, the cursor saved and restored (ESC 7, ESC 8), colours, clears.
/// A strict screen panics on anything else, so a test sees every new kind
/// of output; a lenient one passes over it.
pub struct Screen {
    strict: bool,
    saved: (usize, usize),
    w: usize,
    h: usize,
    cells: Vec<(char, Color, Color)>,
    x: usize,
    y: usize,
    fg: Color,
    bg: Color,
}

impl Screen {
    pub fn new(w: usize, h: usize) -> Self {
        Screen {
            strict: true,
            saved: (0, 0),
            w,
            h,
            cells: vec![(' ', Color::Reset, Color::Reset); w * h],
            x: 0,
            y: 0,
            fg: Color::Reset,
            bg: Color::Reset,
        }
    }

    /// A screen that passes over sequences and attributes it does not know
    /// and drops text past its edges.
    pub fn lenient(w: usize, h: usize) -> Self {
        Screen {
            strict: false,
            ..Screen::new(w, h)
        }
    }

    fn params(p: &str) -> Vec<u16> {
        p.split(';').map(|n| n.parse().unwrap_or(0)).collect()
    }

    fn sgr(&mut self, p: &[u16]) {
        let mut i = 0;
        while i < p.len() {
            let extended = |i: &mut usize| -> Color {
                match p[*i + 1] {
                    5 => {
                        *i += 2;
                        Color::Indexed(p[*i] as u8)
                    }
                    2 => {
                        *i += 4;
                        Color::Rgb(p[*i - 2] as u8, p[*i - 1] as u8, p[*i] as u8)
                    }
                    other => panic!("bad extended colour {other}"),
                }
            };
            let named = |n: u16| -> Color {
                const N: [Color; 16] = [
                    Color::Black,
                    Color::Red,
                    Color::Green,
                    Color::Yellow,
                    Color::Blue,
                    Color::Magenta,
                    Color::Cyan,
                    Color::Gray,
                    Color::DarkGray,
                    Color::LightRed,
                    Color::LightGreen,
                    Color::LightYellow,
                    Color::LightBlue,
                    Color::LightMagenta,
                    Color::LightCyan,
                    Color::White,
                ];
                N[n as usize]
            };
            match p[i] {
                0 => {
                    self.fg = Color::Reset;
                    self.bg = Color::Reset;
                }
                1..=9 => {}
                n @ 30..=37 => self.fg = named(n - 30),
                38 => self.fg = extended(&mut i),
                39 => self.fg = Color::Reset,
                n @ 40..=47 => self.bg = named(n - 40),
                48 => self.bg = extended(&mut i),
                49 => self.bg = Color::Reset,
                n @ 90..=97 => self.fg = named(n - 90 + 8),
                n @ 100..=107 => self.bg = named(n - 100 + 8),
                n => assert!(!self.strict, "unexpected SGR {n}"),
            }
            i += 1;
        }
    }

    pub fn feed(&mut self, bytes: &[u8]) {
        let text = std::str::from_utf8(bytes).expect("output is UTF-8");
        let mut chars = text.chars().peekable();
        while let Some(c) = chars.next() {
            match c {
                '\x1b' => {
                    match chars.next() {
                        Some('[') => {}
                        Some('7') => {
                            self.saved = (self.x, self.y);
                            continue;
                        }
                        Some('8') => {
                            (self.x, self.y) = self.saved;
                            continue;
                        }
                        other => panic!("unexpected escape {other:?}"),
                    }
                    let mut params = String::new();
                    let fin = loop {
                        let c = chars.next().expect("complete sequence");
                        if ('\x40'..='\x7e').contains(&c) {
                            break c;
                        }
                        params.push(c);
                    };
                    if params.starts_with('?') {
                        continue; // mode switches
                    }
                    let p = Self::params(&params);
                    match fin {
                        'H' => {
                            self.y = p.first().copied().unwrap_or(1).max(1) as usize - 1;
                            self.x = p.get(1).copied().unwrap_or(1).max(1) as usize - 1;
                        }
                        'C' => self.x += p.first().copied().unwrap_or(1).max(1) as usize,
                        'J' if params == "2" => {
                            let bg = self.bg;
                            self.cells.fill((' ', Color::Reset, bg));
                        }
                        'm' => self.sgr(&p),
                        other => assert!(!self.strict, "unexpected CSI {params}{other}"),
                    }
                }
                '\r' => self.x = 0,
                '\n' => self.y += 1,
                c => {
                    let inside = self.x < self.w && self.y < self.h;
                    assert!(inside || !self.strict, "write outside the screen");
                    if inside {
                        self.cells[self.y * self.w + self.x] = (c, self.fg, self.bg);
                    }
                    self.x += 1;
                }
            }
        }
    }

    /// What a cell shows: (upper colour, lower colour) for blocks and spaces,
    /// or the character with its colours for text.
    pub fn seen(&self, x: usize, y: usize) -> (char, Color, Color) {
        let (c, fg, bg) = self.cells[y * self.w + x];
        match c {
            '▀' => ('■', fg, bg),
            '▄' => ('■', bg, fg),
            ' ' => ('■', bg, bg),
            c => (c, fg, bg),
        }
    }

    /// The characters on screen, row by row.
    pub fn rows(&self) -> Vec<String> {
        self.cells
            .chunks(self.w)
            .map(|row| row.iter().map(|c| c.0).collect())
            .collect()
    }
}
