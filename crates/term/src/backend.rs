//! A ratatui backend that writes fewer bytes than the stock crossterm one.
//!
//! ratatui's diff hands over only the cells that changed. The stock backend
//! then re-sends foreground and background together whenever either changed.
//! This one sends only the colour that changed, in one SGR sequence; ignores
//! the foreground of a plain space (it is invisible); draws a half block as
//! `▀` or as the equivalent `▄` with colours swapped, whichever needs fewer
//! colour changes; and moves the cursor with the shortest sequence. Each
//! frame is bracketed by synchronized output (DEC mode 2026) and leaves the
//! terminal in one write through a 1 MiB buffer.

use std::io::{self, BufWriter, Write};

use ratatui::backend::{Backend, ClearType, WindowSize};
use ratatui::buffer::Cell;
use ratatui::layout::{Position, Size};
use ratatui::style::{Color, Modifier};

use super::counting::CountingWriter;

/// Start of a synchronized update: the terminal holds the picture until the end mark.
pub const BEGIN_SYNC: &[u8] = b"\x1b[?2026h";
/// End of a synchronized update.
pub const END_SYNC: &[u8] = b"\x1b[?2026l";
/// Capacity of the output buffer: a full frame fits, so it leaves in one write.
pub const OUT_BUFFER: usize = 1 << 20;

const UPPER_STR: &str = "▀";
const LOWER_STR: &str = "▄";

/// Colours and attributes the terminal currently has.
#[derive(Clone, Copy, PartialEq)]
struct Pen {
    fg: Color,
    bg: Color,
    modifier: Modifier,
}

const RESET_PEN: Pen = Pen {
    fg: Color::Reset,
    bg: Color::Reset,
    modifier: Modifier::empty(),
};

/// The terminal backend of the interactive view (see the module notes).
pub struct SgrBackend<W: Write> {
    out: BufWriter<CountingWriter<W>>,
    /// A fixed size (tests, benchmarks); `None` asks the terminal.
    fixed_size: Option<Size>,
    /// Sizes given one a read, in turn (tests: a terminal resized between
    /// any two reads); empty: `fixed_size` or the terminal's.
    sizes_per_read: Vec<Size>,
    next_size: std::cell::Cell<usize>,
    /// The size one frame is laid out and drawn at (see [`Self::hold_size`]).
    held_size: Option<Size>,
    cursor: Position,
    cursor_hidden: Option<bool>,
    in_frame: bool,
    /// 24-bit colours this close to the current one reuse it (see [`picture_cell`]).
    tolerance: u8,
    frame_start: u64,
    last_frame_bytes: u64,
}

impl<W: Write> SgrBackend<W> {
    /// A backend for the real terminal behind `writer`.
    pub fn new(writer: W) -> Self {
        SgrBackend {
            out: BufWriter::with_capacity(OUT_BUFFER, CountingWriter::new(writer)),
            fixed_size: None,
            sizes_per_read: Vec::new(),
            next_size: std::cell::Cell::new(0),
            held_size: None,
            cursor: Position::ORIGIN,
            cursor_hidden: None,
            in_frame: false,
            tolerance: 0,
            frame_start: 0,
            last_frame_bytes: 0,
        }
    }

    /// A backend with a fixed size, for measuring without a terminal.
    pub fn with_size(writer: W, width: u16, height: u16) -> Self {
        let mut b = SgrBackend::new(writer);
        b.fixed_size = Some(Size::new(width, height));
        b
    }

    /// Changes the fixed size (tests simulating a resize).
    pub fn set_fixed_size(&mut self, width: u16, height: u16) {
        self.fixed_size = Some(Size::new(width, height));
    }

    /// Gives these sizes one a read of [`Backend::size`], in turn and
    /// over again: a terminal resized between any two reads (tests).
    pub fn set_sizes_per_read(&mut self, sizes: &[(u16, u16)]) {
        self.sizes_per_read = sizes.iter().map(|&(w, h)| Size::new(w, h)).collect();
        self.next_size.set(0);
    }

    /// Reads the terminal's size and keeps giving it until
    /// [`Self::release_size`]: a frame laid out at one size is drawn at
    /// that size, though the terminal may be resized meanwhile (ratatui
    /// reads the size again when it draws). The resize's signal brings
    /// the next frame at the new size.
    pub fn hold_size(&mut self) -> io::Result<Size> {
        self.held_size = None;
        let size = self.size()?;
        self.held_size = Some(size);
        Ok(size)
    }

    /// Reads of the size ask the terminal again.
    pub fn release_size(&mut self) {
        self.held_size = None;
    }

    /// The size as the terminal (or the test's setting) has it now.
    fn current_size(&self) -> io::Result<(u16, u16)> {
        if !self.sizes_per_read.is_empty() {
            let i = self.next_size.get();
            self.next_size.set((i + 1) % self.sizes_per_read.len());
            let s = self.sizes_per_read[i];
            return Ok((s.width, s.height));
        }
        match self.fixed_size {
            Some(size) => Ok((size.width, size.height)),
            None => crossterm::terminal::size(),
        }
    }

    /// Lets picture colours within `tolerance` (per channel, of 255) of the
    /// colour already set be drawn with it, saving the bytes of a colour change.
    pub fn set_tolerance(&mut self, tolerance: u8) {
        self.tolerance = tolerance;
    }

    pub fn tolerance(&self) -> u8 {
        self.tolerance
    }

    /// Opens a frame: everything until [`end_frame`](Self::end_frame) is shown at once.
    pub fn begin_frame(&mut self) -> io::Result<()> {
        self.frame_start = self.sent() + self.out.buffer().len() as u64;
        self.in_frame = true;
        self.out.write_all(BEGIN_SYNC)
    }

    /// Closes the frame and sends it; returns the bytes the frame took.
    pub fn end_frame(&mut self) -> io::Result<u64> {
        self.end_frame_then(&[])
    }

    /// Closes the frame, appends `trailer` after the end of the
    /// synchronized update (the pacing query) and sends both in one write;
    /// returns the bytes they took.
    pub fn end_frame_then(&mut self, trailer: &[u8]) -> io::Result<u64> {
        self.out.write_all(END_SYNC)?;
        self.out.write_all(trailer)?;
        self.in_frame = false;
        self.out.flush()?;
        self.last_frame_bytes = self.sent() - self.frame_start;
        Ok(self.last_frame_bytes)
    }

    /// Bytes of the last complete frame.
    pub fn last_frame_bytes(&self) -> u64 {
        self.last_frame_bytes
    }

    /// Bytes handed to the underlying writer so far.
    pub fn sent(&self) -> u64 {
        self.out.get_ref().bytes
    }

    /// `write` calls made on the underlying writer so far.
    pub fn write_calls(&self) -> u64 {
        self.out.get_ref().writes
    }

    /// The underlying writer (tests read what was sent).
    pub fn writer(&self) -> &W {
        &self.out.get_ref().inner
    }

    pub fn writer_mut(&mut self) -> &mut W {
        &mut self.out.get_mut().inner
    }

    /// Writes raw bytes (mode switches); they go out with the next flush.
    pub fn write_raw(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.out.write_all(bytes)
    }

    fn move_to(&mut self, from: Option<Position>, to: Position) -> io::Result<()> {
        match from {
            Some(p) if p.y == to.y && to.x == p.x + 1 => Ok(()),
            Some(p) if p.y == to.y && to.x > p.x + 1 => {
                // Cursor forward: shorter than an absolute move.
                let n = to.x - p.x - 1;
                self.out.write_all(b"\x1b[")?;
                if n > 1 {
                    write_u16(&mut self.out, n)?;
                }
                self.out.write_all(b"C")
            }
            Some(p) if to.y == p.y + 1 && to.x == 0 => self.out.write_all(b"\r\n"),
            _ => {
                self.out.write_all(b"\x1b[")?;
                if to.y > 0 || to.x > 0 {
                    write_u16(&mut self.out, to.y + 1)?;
                    if to.x > 0 {
                        self.out.write_all(b";")?;
                        write_u16(&mut self.out, to.x + 1)?;
                    }
                }
                self.out.write_all(b"H")
            }
        }
    }
}

/// True when `a` can stand for `b`: equal, or both 24-bit and no channel
/// further apart than `tolerance`.
#[inline]
fn near(a: Color, b: Color, tolerance: u8) -> bool {
    match (a, b) {
        (Color::Rgb(r1, g1, b1), Color::Rgb(r2, g2, b2)) => {
            r1.abs_diff(r2) <= tolerance
                && g1.abs_diff(g2) <= tolerance
                && b1.abs_diff(b2) <= tolerance
        }
        _ => a == b,
    }
}

/// Rough bytes of one colour in an SGR sequence.
const COLOR_COST: u32 = 16;

/// How to draw a picture cell whose upper pixel is `upper` and lower pixel
/// `lower`: `▀`, `▄` with the colours swapped, or a space — whichever needs
/// the fewest bytes given the current pen. A colour within `tolerance` of
/// the pen's is drawn with the pen's (every displayed colour stays within
/// `tolerance` of the true one). Returns the symbol, the foreground to set
/// (`None`: any) and the background.
#[inline]
fn picture_cell(
    upper: Color,
    lower: Color,
    pen: &Pen,
    tolerance: u8,
) -> (&'static str, Option<Color>, Color) {
    let pick = |want: Color, have: Color| {
        if near(want, have, tolerance) {
            (have, 0)
        } else {
            (want, COLOR_COST)
        }
    };
    // A space: both pixels near one background colour.
    let space = if near(upper, lower, tolerance) {
        let (bg, cost) = if near(upper, pen.bg, tolerance) && near(lower, pen.bg, tolerance) {
            (pen.bg, 0)
        } else {
            (lower, COLOR_COST)
        };
        Some((cost + 1, bg))
    } else {
        None
    };
    let (up_fg, c1) = pick(upper, pen.fg);
    let (up_bg, c2) = pick(lower, pen.bg);
    let (lo_fg, c3) = pick(lower, pen.fg);
    let (lo_bg, c4) = pick(upper, pen.bg);
    let upper_cost = c1 + c2 + 3;
    let lower_cost = c3 + c4 + 3;
    match space {
        Some((cost, bg)) if cost <= upper_cost.min(lower_cost) => (" ", None, bg),
        _ if lower_cost < upper_cost => (LOWER_STR, Some(lo_fg), lo_bg),
        _ => (UPPER_STR, Some(up_fg), up_bg),
    }
}

/// Writes `n` in decimal without formatting machinery.
fn write_u16(out: &mut impl Write, n: u16) -> io::Result<()> {
    let mut digits = [0u8; 5];
    let mut i = digits.len();
    let mut n = n;
    loop {
        i -= 1;
        digits[i] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    out.write_all(&digits[i..])
}

/// Collects SGR parameters into one `ESC [ … m` sequence.
struct Sgr {
    bytes: [u8; 64],
    len: usize,
}

impl Sgr {
    fn new() -> Self {
        Sgr {
            bytes: [0; 64],
            len: 0,
        }
    }

    fn push_byte(&mut self, b: u8) {
        self.bytes[self.len] = b;
        self.len += 1;
    }

    fn param_start(&mut self) {
        if self.len > 0 {
            self.push_byte(b';');
        }
    }

    fn number(&mut self, n: u8) {
        if n >= 100 {
            self.push_byte(b'0' + n / 100);
        }
        if n >= 10 {
            self.push_byte(b'0' + (n / 10) % 10);
        }
        self.push_byte(b'0' + n % 10);
    }

    fn code(&mut self, n: u8) {
        self.param_start();
        self.number(n);
    }

    /// A colour; `base` is 30 for the foreground and 40 for the background.
    fn color(&mut self, color: Color, base: u8) {
        self.param_start();
        match color {
            Color::Reset => self.number(base + 9),
            Color::Black => self.number(base),
            Color::Red => self.number(base + 1),
            Color::Green => self.number(base + 2),
            Color::Yellow => self.number(base + 3),
            Color::Blue => self.number(base + 4),
            Color::Magenta => self.number(base + 5),
            Color::Cyan => self.number(base + 6),
            Color::Gray => self.number(base + 7),
            Color::DarkGray => self.number(base + 60),
            Color::LightRed => self.number(base + 61),
            Color::LightGreen => self.number(base + 62),
            Color::LightYellow => self.number(base + 63),
            Color::LightBlue => self.number(base + 64),
            Color::LightMagenta => self.number(base + 65),
            Color::LightCyan => self.number(base + 66),
            Color::White => self.number(base + 67),
            Color::Indexed(i) => {
                self.number(base + 8);
                self.bytes[self.len..self.len + 3].copy_from_slice(b";5;");
                self.len += 3;
                self.number(i);
            }
            Color::Rgb(r, g, b) => {
                self.number(base + 8);
                self.bytes[self.len..self.len + 3].copy_from_slice(b";2;");
                self.len += 3;
                self.number(r);
                self.push_byte(b';');
                self.number(g);
                self.push_byte(b';');
                self.number(b);
            }
        }
    }

    fn modifiers(&mut self, m: Modifier) {
        const CODES: [(Modifier, u8); 8] = [
            (Modifier::BOLD, 1),
            (Modifier::DIM, 2),
            (Modifier::ITALIC, 3),
            (Modifier::UNDERLINED, 4),
            (Modifier::SLOW_BLINK, 5),
            (Modifier::RAPID_BLINK, 6),
            (Modifier::REVERSED, 7),
            (Modifier::CROSSED_OUT, 9),
        ];
        for (flag, code) in CODES {
            if m.contains(flag) {
                self.code(code);
            }
        }
        if m.contains(Modifier::HIDDEN) {
            self.code(8);
        }
    }

    fn write_to(&self, out: &mut impl Write) -> io::Result<()> {
        if self.len == 0 {
            return Ok(());
        }
        out.write_all(b"\x1b[")?;
        out.write_all(&self.bytes[..self.len])?;
        out.write_all(b"m")
    }
}

impl<W: Write> Backend for SgrBackend<W> {
    type Error = io::Error;

    fn draw<'a, I>(&mut self, content: I) -> io::Result<()>
    where
        I: Iterator<Item = (u16, u16, &'a Cell)>,
    {
        // Every draw ends with a reset, so each one starts from the default pen.
        let mut pen = RESET_PEN;
        let mut last: Option<Position> = None;
        let mut wrote = false;
        for (x, y, cell) in content {
            let to = Position { x, y };
            self.move_to(last, to)?;
            last = Some(to);
            wrote = true;

            let mut sgr = Sgr::new();
            if cell.modifier != pen.modifier {
                // Attributes are switched off all at once; colours go with them.
                sgr.code(0);
                sgr.modifiers(cell.modifier);
                pen = Pen {
                    modifier: cell.modifier,
                    ..RESET_PEN
                };
            }
            let plain = cell.modifier.is_empty();
            let symbol = cell.symbol();
            let (symbol, fg, bg) = if plain && (symbol == UPPER_STR || symbol == " ") {
                let upper = if symbol == " " { cell.bg } else { cell.fg };
                picture_cell(upper, cell.bg, &pen, self.tolerance)
            } else {
                (symbol, Some(cell.fg), cell.bg)
            };
            if let Some(fg) = fg
                && fg != pen.fg
            {
                sgr.color(fg, 30);
                pen.fg = fg;
            }
            if bg != pen.bg {
                sgr.color(bg, 40);
                pen.bg = bg;
            }
            sgr.write_to(&mut self.out)?;
            self.out.write_all(symbol.as_bytes())?;
            if !symbol.is_ascii()
                && symbol != UPPER_STR
                && symbol != LOWER_STR
                && !symbol
                    .chars()
                    .next()
                    .is_some_and(super::symbols::is_block_glyph)
            {
                // Width unknown (a wide character?): the next cell gets an absolute move.
                last = None;
            }
        }
        if wrote {
            if pen != RESET_PEN {
                self.out.write_all(b"\x1b[0m")?;
            }
            if let Some(p) = last {
                self.cursor = Position { x: p.x + 1, y: p.y };
            }
        }
        Ok(())
    }

    fn hide_cursor(&mut self) -> io::Result<()> {
        if self.cursor_hidden != Some(true) {
            self.out.write_all(b"\x1b[?25l")?;
            self.cursor_hidden = Some(true);
        }
        Ok(())
    }

    fn show_cursor(&mut self) -> io::Result<()> {
        if self.cursor_hidden != Some(false) {
            self.out.write_all(b"\x1b[?25h")?;
            self.cursor_hidden = Some(false);
        }
        Ok(())
    }

    fn get_cursor_position(&mut self) -> io::Result<Position> {
        Ok(self.cursor)
    }

    fn set_cursor_position<P: Into<Position>>(&mut self, position: P) -> io::Result<()> {
        let to = position.into();
        self.move_to(None, to)?;
        self.cursor = to;
        Ok(())
    }

    fn clear(&mut self) -> io::Result<()> {
        self.clear_region(ClearType::All)
    }

    fn clear_region(&mut self, clear_type: ClearType) -> io::Result<()> {
        let seq: &[u8] = match clear_type {
            ClearType::All => b"\x1b[2J",
            ClearType::AfterCursor => b"\x1b[J",
            ClearType::BeforeCursor => b"\x1b[1J",
            ClearType::CurrentLine => b"\x1b[2K",
            ClearType::UntilNewLine => b"\x1b[K",
        };
        self.out.write_all(seq)
    }

    fn size(&self) -> io::Result<Size> {
        if let Some(size) = self.held_size {
            return Ok(size);
        }
        let (w, h) = self.current_size()?;
        // A huge reported size draws in the top-left corner: the cell
        // buffers and the frame stay within the memory budget.
        Ok(Size::new(
            w.min(relief_core::budget::MAX_VIEW_COLUMNS),
            h.min(relief_core::budget::MAX_VIEW_ROWS),
        ))
    }

    fn window_size(&mut self) -> io::Result<WindowSize> {
        let columns_rows = self.size()?;
        Ok(WindowSize {
            columns_rows,
            pixels: Size::new(0, 0),
        })
    }

    fn flush(&mut self) -> io::Result<()> {
        // Inside a frame everything waits for end_frame: one write per frame.
        if self.in_frame {
            Ok(())
        } else {
            self.out.flush()
        }
    }
}
