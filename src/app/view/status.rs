//! The status line: every mode and the last frame's cost. As the screen
//! narrows, fields take their short form one at a time and the frame cost
//! moves to the line above; then the line wraps onto a second row and a
//! third, as far as the screen's height allows (one row in eight). Only
//! when even that is too little do fields go, those at their default
//! value first, and the line then says how many are not shown
//! (`+N more`); the lighting, the colour depth, auto-rotation and
//! `? help` always stay.

use crate::app::state::{State, plasma_light};
use relief_options::OPTIONS;
use relief_scene::SceneKind;
use relief_scene::camera::REFERENCE_DISTANCE;

/// What always ends the status line.
pub const HELP_HINT: &str = "? help";

/// Between two fields.
const SEP: &str = " │ ";

/// The status line that fits in one row of `width` columns.
pub fn status_line(state: &State, width: usize) -> String {
    status_choice(state, width, 1).0.join("\n")
}

/// The rows the status line takes on a screen of this size (see
/// [`max_rows`]).
pub fn status_rows(state: &State, width: u16, height: u16) -> u16 {
    let rows = status_choice(state, width as usize, max_rows(height))
        .0
        .len();
    rows.max(1) as u16
}

/// The status line may take at most one row in this many of the screen.
const SCREEN_ROWS_PER_STATUS_ROW: u16 = 8;
/// And never more rows than this.
const MAX_STATUS_ROWS: u16 = 3;

/// How many rows the status line may take on a screen `height` rows tall:
/// one row in eight, from one to three.
pub fn max_rows(height: u16) -> u16 {
    (height / SCREEN_ROWS_PER_STATUS_ROW).clamp(1, MAX_STATUS_ROWS)
}

/// The status rows (top to bottom) in `width` columns and at most
/// `max_rows` rows, and whether they carry the frame cost (without it,
/// the view shows the cost on the line above).
pub(super) fn status_choice(state: &State, width: usize, max_rows: u16) -> (Vec<String>, bool) {
    let fields = fields(state);
    for rows in 1..=max_rows.max(1) as usize {
        if let Some(fit) = fit_whole(&fields, width, rows) {
            return fit;
        }
    }
    fit_counted(&fields, width, max_rows.max(1) as usize)
}

/// One field of the status line.
#[derive(Clone, Debug)]
struct Field {
    long: String,
    short: String,
    /// Fields shorten in increasing order of this.
    shorten: u8,
    /// Fields go in increasing order of this (`None`: never).
    drop: Option<u8>,
    /// The frame cost.
    cost: bool,
}

impl Field {
    fn new(
        long: impl Into<String>,
        short: impl Into<String>,
        shorten: u8,
        drop: Option<u8>,
    ) -> Field {
        Field {
            long: long.into(),
            short: short.into(),
            shorten,
            drop,
            cost: false,
        }
    }

    /// A field with one form.
    fn same(text: impl Into<String>, drop: Option<u8>) -> Field {
        let text = text.into();
        Field::new(text.clone(), text, u8::MAX, drop)
    }
}

/// The first drop rank of a field at its default value, and of one that
/// is not: the defaults go first.
const DEFAULT_DROP: u8 = 10;
const CHANGED_DROP: u8 = 40;

/// Drop rank: `rank` among the defaults or among the changed fields.
fn drop_rank(default: bool, rank: u8) -> Option<u8> {
    Some(if default { DEFAULT_DROP } else { CHANGED_DROP } + rank)
}

/// The parts of the line: `fields` with these shortened and these
/// dropped, the count of the dropped ones (`+N more`, the cost aside: it
/// shows above) when `count`, then the hint.
fn parts(fields: &[Field], short: &[bool], dropped: &[bool], count: bool) -> Vec<String> {
    let mut parts: Vec<String> = fields
        .iter()
        .enumerate()
        .filter(|(i, _)| !dropped[*i])
        .map(|(i, f)| if short[i] { &f.short } else { &f.long }.clone())
        .collect();
    let hidden = (0..fields.len())
        .filter(|&i| dropped[i] && !fields[i].cost)
        .count();
    if count && hidden > 0 {
        parts.push(format!("+{hidden} more"));
    }
    parts.push(HELP_HINT.to_string());
    parts
}

/// `parts` wrapped into rows of at most `width` columns, at the
/// separators; `None` when they take more than `rows` rows (or one part
/// is wider than a row).
fn wrap(parts: &[String], width: usize, rows: usize) -> Option<Vec<String>> {
    let mut out: Vec<String> = Vec::new();
    let mut row = String::new();
    for part in parts {
        let len = part.chars().count();
        let used = row.chars().count();
        if used > 0 && used + SEP.chars().count() + len <= width {
            row.push_str(SEP);
            row.push_str(part);
            continue;
        }
        if used > 0 {
            out.push(std::mem::take(&mut row));
        }
        if len > width {
            return None;
        }
        row.push_str(part);
    }
    out.push(row);
    (out.len() <= rows).then_some(out)
}

/// Every field in `rows` rows, shortened one at a time, the frame cost
/// moved to the line above last; `None` when they do not fit.
fn fit_whole(fields: &[Field], width: usize, rows: usize) -> Option<(Vec<String>, bool)> {
    let n = fields.len();
    let mut short = vec![false; n];
    let mut dropped = vec![false; n];
    let mut shorten: Vec<usize> = (0..n)
        .filter(|&i| fields[i].short != fields[i].long)
        .collect();
    shorten.sort_by_key(|&i| fields[i].shorten);
    let mut shorten = shorten.into_iter();
    loop {
        if let Some(lines) = wrap(&parts(fields, &short, &dropped, false), width, rows) {
            let cost = (0..n).any(|i| fields[i].cost && !dropped[i]);
            return Some((lines, cost));
        }
        if let Some(i) = shorten.next() {
            short[i] = true;
        } else if let Some(i) = (0..n).find(|&i| fields[i].cost && !dropped[i]) {
            dropped[i] = true;
        } else {
            return None;
        }
    }
}

/// The fields in their short forms in `rows` rows, dropped one at a time
/// (the defaults first) with their count shown (`+N more`); those dropped
/// before the last come back where they fit, the last dropped first. A
/// screen too narrow even then cuts the text before `? help` with `…`.
fn fit_counted(fields: &[Field], width: usize, rows: usize) -> (Vec<String>, bool) {
    let n = fields.len();
    let short = vec![true; n];
    let mut dropped: Vec<bool> = fields.iter().map(|f| f.cost).collect();
    let mut drop: Vec<usize> = (0..n)
        .filter(|&i| fields[i].drop.is_some() && !fields[i].cost)
        .collect();
    drop.sort_by_key(|&i| fields[i].drop);
    let mut gone = Vec::new();
    let mut drop = drop.into_iter();
    let fits = |dropped: &[bool]| wrap(&parts(fields, &short, dropped, true), width, rows);
    loop {
        if fits(&dropped).is_some() {
            for &i in gone.iter().rev() {
                dropped[i] = false;
                if fits(&dropped).is_none() {
                    dropped[i] = true;
                }
            }
            let cost = (0..n).any(|i| fields[i].cost && !dropped[i]);
            return (fits(&dropped).unwrap_or_default(), cost);
        }
        if let Some(i) = drop.next() {
            dropped[i] = true;
            gone.push(i);
        } else {
            return (
                vec![cut(&parts(fields, &short, &dropped, true), width)],
                false,
            );
        }
    }
}

/// `parts` in one row of `width` columns: the hint stays whole, what is
/// before it is cut and ends with `…`.
fn cut(parts: &[String], width: usize) -> String {
    let hint = HELP_HINT.chars().count();
    if width <= hint + 1 {
        return HELP_HINT.chars().take(width).collect();
    }
    let text = parts[..parts.len() - 1].join(SEP);
    let room = width - hint - 2;
    let kept: String = text.chars().take(room).collect();
    format!("{kept:<room$}… {HELP_HINT}")
}

/// Frame time, frames per second and bytes of the last frame; a preview
/// says "preview" in place of its time. Every figure has a fixed width,
/// so the status line keeps its layout whatever the figures: the form
/// that fits is chosen by the screen width, never by a digit more.
pub fn cost_text(state: &State, compact: bool) -> String {
    let f = &state.frame;
    let ms = f.frame_time.as_secs_f64() * 1e3;
    let ms = if ms < 99.95 {
        format!("{ms:.1}")
    } else {
        format!("{ms:.0}")
    };
    // No rate while idle (or for a lone frame).
    let fps = f.fps.map_or_else(|| "—".to_string(), |r| format!("{r:.0}"));
    if compact {
        let time = if f.preview {
            "preview".to_string()
        } else {
            format!("{ms:>5}ms")
        };
        let bytes = format_bytes(f.bytes).replace(' ', "");
        format!("{time} {fps:>3}fps {bytes:>6}")
    } else {
        let time = if f.preview {
            "preview".to_string()
        } else {
            format!("{ms:>4} ms")
        };
        format!("{time} │ {fps:>3} fps │ {:>7}", format_bytes(f.bytes))
    }
}

/// What is shown: the model, the shadow scene or the plasma.
fn scene_label(state: &State, short: bool) -> String {
    match state.scene {
        SceneKind::Cube if short => state.model.label(),
        SceneKind::Cube => format!("model {}", state.model.label()),
        SceneKind::Shadow => "shadow".into(),
        SceneKind::Plasma => "plasma".into(),
    }
}

/// Whether each light keys `1`–`4` switch in this view is on.
fn all_lights_on(state: &State) -> bool {
    let count = state.light_names().len();
    state.light_on[..count].iter().all(|&on| on)
}

/// The lights: all on, all off, or which are off (`l`, `1`–`4`).
fn lights_text(state: &State, short: bool) -> String {
    if !state.settings.lights {
        return "lights off".into();
    }
    if all_lights_on(state) {
        return "lights on".into();
    }
    let names = state.light_names();
    let lights = &state.light_on[..names.len()];
    if short {
        let keys: String = (lights.iter().enumerate())
            .map(|(i, &on)| if on { char::from(b'1' + i as u8) } else { '·' })
            .collect();
        return format!("lights {keys}");
    }
    let off: Vec<&str> = (names.iter().zip(lights))
        .filter(|(_, on)| !**on)
        .map(|(name, _)| name.as_str())
        .collect();
    format!("lights on ({} off)", off.join(", "))
}

/// The plasma's own fields: its normal mode and where the light is.
fn plasma_fields(state: &State) -> Vec<Field> {
    let light = match state.pointer {
        Some(_) => {
            let (x, y) = plasma_light(state.pointer, 0, 0);
            format!("light {x:.0},{y:.0}")
        }
        None => "light centre".into(),
    };
    let normal = state.plasma_normal.label();
    let brief = normal.split(' ').next().unwrap_or(normal);
    vec![
        Field::same("plasma", None),
        Field::new(normal, brief, 2, Some(3)),
        Field::same(light, Some(2)),
        Field::new(depth_text(state), short_depth(state), 3, None),
        cost_field(state),
    ]
}

/// The frame cost: dropped first (the line above shows it then).
fn cost_field(state: &State) -> Field {
    Field {
        cost: true,
        ..Field::new(cost_text(state, false), cost_text(state, true), 30, Some(0))
    }
}

/// Places of the fields the option table does not declare, among the
/// options' (each entry's `Status::at`).
const SCENE_AT: u8 = 10;
const LIGHTS_AT: u8 = 11;
const DEPTH_AT: u8 = 13;
const HEIGHTS_AT: u8 = 14;
const DISTANCE_AT: u8 = 18;
const COST_AT: u8 = 19;
const AUTO_AT: u8 = 20;
const CLIP_AT: u8 = 21;

/// The status fields of the option table's entries that show now, each
/// with its place.
fn option_fields(state: &State) -> Vec<(u8, Field)> {
    let ctx = state.ctx();
    let mut f = Vec::new();
    for opt in OPTIONS {
        let Some(st) = &opt.status else { continue };
        if st.shown.is_some_and(|shown| !shown(&ctx)) {
            continue;
        }
        let long = (st.long)(&ctx);
        let short = st.short.map_or_else(|| long.clone(), |short| short(&ctx));
        let at_default = st
            .at_default
            .map_or_else(|| opt.is_default(&state.settings), |d| d(&ctx));
        let drop = st.drop.and_then(|rank| drop_rank(at_default, rank));
        f.push((st.at, Field::new(long, short, st.shorten, drop)));
    }
    f
}

/// Every field of the status line, in order, with the ranks in which they
/// shorten and go.
fn fields(state: &State) -> Vec<Field> {
    if state.scene == SceneKind::Plasma {
        return plasma_fields(state);
    }
    let s = &state.settings;
    let mut f = option_fields(state);
    f.push((
        SCENE_AT,
        Field::new(
            scene_label(state, false),
            scene_label(state, true),
            6,
            drop_rank(false, 20),
        ),
    ));
    f.push((
        LIGHTS_AT,
        Field::new(
            lights_text(state, false),
            lights_text(state, true),
            7,
            drop_rank(s.lights && all_lights_on(state), 10),
        ),
    ));
    f.push((
        DEPTH_AT,
        Field::new(depth_text(state), short_depth(state), 20, None),
    ));
    if let Some(h) = heights_text(state, false) {
        let short = heights_text(state, true).unwrap_or_default();
        f.push((HEIGHTS_AT, Field::new(h, short, 8, drop_rank(false, 1))));
    }
    // The zoom shows once it leaves the reference view.
    if state.distance != REFERENCE_DISTANCE {
        let d = format_distance(state.distance);
        f.push((
            DISTANCE_AT,
            Field::new(
                format!("distance {d}"),
                format!("dist {d}"),
                12,
                drop_rank(false, 4),
            ),
        ));
    }
    f.push((COST_AT, cost_field(state)));
    if state.auto_rotate {
        f.push((AUTO_AT, Field::same("auto", None)));
    }
    if let Some(clip) = clip_field(&state.playback) {
        f.push((CLIP_AT, clip));
    }
    if let Some(k) = state.camera {
        let long = format!("camera {}/{}", k + 1, state.cameras);
        f.push((CLIP_AT, Field::new(long, format!("cam {}", k + 1), 9, None)));
    }
    // Stable: fields of one place keep their order.
    f.sort_by_key(|(at, _)| *at);
    f.into_iter().map(|(_, field)| field).collect()
}

/// An animated model's clip: which of how many, its name, and ▶ while it
/// plays or ‖ when paused (keys `A` `C` `,` `.`).
fn clip_field(p: &crate::app::state::Playback) -> Option<Field> {
    let (name, _) = p.clips.get(p.clip)?;
    let mark = if p.playing { "▶" } else { "‖" };
    let name: String = relief_core::sanitize::clean(name)
        .chars()
        .take(16)
        .collect();
    let long = format!("clip {}/{} {name} {mark}", p.clip + 1, p.clips.len());
    Some(Field::new(
        long,
        format!("clip {mark}"),
        9,
        drop_rank(false, 30),
    ))
}

/// Where the heights come from, when another texture of the list gives
/// them (texture panel, `H`): its name, cut to a few words.
fn heights_text(state: &State, short: bool) -> Option<String> {
    let label = state.textures.listing.heights_label()?;
    let label = label.strip_suffix(" (built-in)").unwrap_or(label);
    let max = if short { 12 } else { 24 };
    let n = label.chars().count();
    let cut: String = if n > max {
        let tail: String = label.chars().skip(n - (max - 1)).collect();
        format!("…{tail}")
    } else {
        label.to_string()
    };
    Some(if short {
        format!("H:{cut}")
    } else {
        format!("heights {cut}")
    })
}

/// Dithering (`--dither`) changes the picture in 256 and 16 colours only.
fn dithered(state: &State) -> bool {
    state.dither && state.depth != relief_term::ColorDepth::Truecolor
}

/// The colour depth, "dithered" when dithering shows, and the symbol set
/// when it is not half blocks.
fn depth_text(state: &State) -> String {
    let depth = if dithered(state) {
        format!("{} dithered", state.depth.label())
    } else {
        state.depth.label().to_string()
    };
    with_symbols(state, depth)
}

fn with_symbols(state: &State, depth: String) -> String {
    // Pixel images: the format instead of the depth and glyphs.
    let format = state.output.format();
    if format.is_pixels() {
        return format.name().to_string();
    }
    match state.symbols {
        relief_term::Symbols::Half => depth,
        s => format!("{depth} {}", s.name()),
    }
}

fn short_depth(state: &State) -> String {
    let depth = match state.depth {
        relief_term::ColorDepth::Truecolor => "24b",
        relief_term::ColorDepth::Palette256 => "256c",
        relief_term::ColorDepth::Palette16 => "16c",
    };
    let depth = if dithered(state) {
        format!("{depth}+dith")
    } else {
        depth.to_string()
    };
    with_symbols(state, depth)
}

/// The camera distance with one decimal.
fn format_distance(d: f32) -> String {
    format!("{d:.1}")
}

/// Bytes as the status line shows them: three significant digits, at
/// most 7 characters below 1 GB.
pub fn format_bytes(n: u64) -> String {
    let three = |v: f64, unit: &str| {
        if v < 9.995 {
            format!("{v:.2} {unit}")
        } else if v < 99.95 {
            format!("{v:.1} {unit}")
        } else {
            format!("{v:.0} {unit}")
        }
    };
    if n < 1000 {
        format!("{n} B")
    } else if n < 999_500 {
        three(n as f64 / 1e3, "kB")
    } else {
        three(n as f64 / 1e6, "MB")
    }
}
