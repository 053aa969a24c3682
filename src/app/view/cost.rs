//! The cost panel (key `k`): what the last frames cost, stage by stage.
//!
//! The renderer reports plan and raster+shade time in `FrameStats`; the event
//! loop adds the time to encode the frame into terminal bytes (ratatui's diff
//! and the SGR backend filling its buffer) and to write them out.

use std::time::Duration;

use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::Line;
use ratatui::widgets::{Block, Borders, Paragraph, Sparkline, Widget, Wrap};

use crate::app::frame_cost::CostHistory;
use relief_core::stats::Counters;
use relief_term::hold::HoldBy;
use relief_term::pacing::{Answers, LinkInfo};

/// The stages that did work in a frame, with their counts: whatever is off
/// (or cannot show) reads as absent here.
pub fn active_stages(c: &Counters) -> Vec<String> {
    [
        ("triangles", c.triangles_drawn),
        ("clipped", c.triangles_clipped),
        ("pixels", c.pixels_shaded),
        ("texture", c.texture_samples),
        ("bump", c.bump_evals),
        ("lights", c.light_evals),
        ("specular", c.specular_evals),
        ("environment", c.env_lookups),
        ("depth", c.depth_tests),
        ("mip builds", c.mip_builds),
        ("normal maps", c.normal_map_builds),
        ("shadow texels", c.shadow_texels),
        ("shadow lookups", c.shadow_lookups),
        ("frame lines", c.frame_lines),
        ("non-finite", c.nonfinite),
    ]
    .into_iter()
    .filter(|&(_, n)| n > 0)
    .map(|(name, n)| format!("{name} {}", count(n)))
    .collect()
}

/// 950, 12.3k, 4.56M.
fn count(n: u64) -> String {
    match n {
        0..1_000 => n.to_string(),
        1_000..1_000_000 => format!("{:.1}k", n as f64 / 1e3),
        _ => format!("{:.2}M", n as f64 / 1e6),
    }
}

fn ms(d: Duration) -> String {
    format!("{:7.2} ms", d.as_secs_f64() * 1e3)
}

/// The panel's text lines: a line per stage (last frame and mean), the total.
pub fn stage_lines(history: &CostHistory) -> Vec<String> {
    let (Some(last), Some(mean)) = (history.last(), history.mean()) else {
        return vec!["no frame yet".into()];
    };
    let mut lines = vec![format!(
        "{:<13}{:>10}  {:>10}",
        "stage",
        "last",
        format!("mean {}", history.len())
    )];
    for (name, l, m) in [
        ("plan", last.plan, mean.plan),
        ("raster+shade", last.raster, mean.raster),
        ("encode", last.encode, mean.encode),
        ("write", last.write, mean.write),
        ("total", last.total(), mean.total()),
    ] {
        lines.push(format!("{name:<13}{}  {}", ms(l), ms(m)));
    }
    lines.push(format!("bytes sent   {:>10}", count(last.bytes)));
    lines
}

/// The link to the terminal: round trip and throughput measured by the
/// pacing queries, or why there are none, and what else holds frames.
pub fn link_lines(link: &LinkInfo) -> Vec<String> {
    let mut lines = reply_lines(link);
    match link.held_by {
        HoldBy::Nothing => {}
        HoldBy::Queue => lines.push("held by      SSH send queue".into()),
        HoldBy::Rate(bytes) => lines.push(format!(
            "held by      --link {:.2} Mbit/s",
            bytes * 8.0 / 1e6
        )),
    }
    lines
}

/// Round trip and throughput, or why there are none.
fn reply_lines(link: &LinkInfo) -> Vec<String> {
    let rtt = |d: std::time::Duration| format!("{:7.1} ms", d.as_secs_f64() * 1e3);
    match (link.answers, link.round_trip) {
        (Answers::No, _) => vec![
            "round trip   no reply".into(),
            "frames paced by the writes".into(),
        ],
        (_, None) => vec!["round trip   waiting".into(), "throughput   —".into()],
        (_, Some(d)) => {
            let rate = link.throughput.map_or_else(
                || "—".to_string(),
                |t| {
                    let mbit = t * 8.0 / 1e6;
                    if mbit < 10.0 {
                        format!("{mbit:.2} Mbit/s")
                    } else {
                        format!("{mbit:.0} Mbit/s")
                    }
                },
            );
            vec![
                format!("round trip  {}", rtt(d)),
                format!("throughput  {rate:>10}"),
            ]
        }
    }
}

/// The colour depth and what decided it (see [`relief_term::depth`]).
pub fn colour_line(depth: relief_term::ColorDepth, source: &str) -> String {
    format!("{}: {source}", depth.label())
}

/// The panel: stage times, the link, a sparkline of frame times, the active stages.
pub struct CostPanel<'a> {
    pub history: &'a CostHistory,
    pub link: &'a LinkInfo,
    /// The colour depth and what decided it.
    pub colour: String,
    /// What limits the pixel image, if anything (the largest sixel image
    /// the terminal takes).
    pub pixels: Option<String>,
}

impl Widget for CostPanel<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let block = Block::default().borders(Borders::ALL).title(" cost (k) ");
        let inner = block.inner(area);
        block.render(area, buf);
        let mut stages = stage_lines(self.history);
        stages.extend(link_lines(self.link));
        stages.push(self.colour);
        stages.extend(self.pixels);
        let [table, spark, active] = Layout::vertical([
            Constraint::Length(stages.len() as u16),
            Constraint::Length(3),
            Constraint::Min(1),
        ])
        .areas(inner);
        Paragraph::new(stages.into_iter().map(Line::from).collect::<Vec<_>>()).render(table, buf);
        let data = self.history.totals_us();
        // The newest frames, as many as there are columns.
        let shown = &data[data.len().saturating_sub(spark.width as usize)..];
        Sparkline::default()
            .block(Block::default().title("frame time"))
            .data(shown)
            .render(spark, buf);
        let stages = self
            .history
            .last()
            .map(|c| active_stages(&c.counters).join(" · "))
            .unwrap_or_default();
        Paragraph::new(format!("active: {stages}"))
            .wrap(Wrap { trim: true })
            .render(active, buf);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::frame_cost::{FrameCost, HISTORY};

    fn frame(ms: u64) -> FrameCost {
        FrameCost {
            plan: Duration::from_micros(100),
            raster: Duration::from_millis(ms),
            encode: Duration::from_micros(300),
            write: Duration::from_micros(50),
            counters: Counters {
                triangles_drawn: 6,
                pixels_shaded: 11_700,
                light_evals: 46_800,
                ..Counters::default()
            },
            bytes: 42_000,
        }
    }

    #[test]
    fn history_keeps_the_last_frames_and_averages_them() {
        let mut h = CostHistory::default();
        assert!(h.mean().is_none());
        for i in 0..HISTORY as u64 + 10 {
            h.push(frame(i % 2 + 1));
        }
        assert_eq!(h.len(), HISTORY);
        let mean = h.mean().unwrap();
        assert_eq!(mean.raster, Duration::from_micros(1500));
        assert_eq!(mean.plan, Duration::from_micros(100));
        assert_eq!(h.totals_us().len(), HISTORY);
        assert_eq!(*h.totals_us().last().unwrap(), 100 + 2000 + 300 + 50);
    }

    #[test]
    fn only_stages_that_worked_are_active() {
        let c = frame(1).counters;
        assert_eq!(
            active_stages(&c),
            vec!["triangles 6", "pixels 11.7k", "lights 46.8k"]
        );
        assert!(active_stages(&Counters::default()).is_empty());
    }

    #[test]
    fn panel_draws_stages_sparkline_and_active_list() {
        let mut h = CostHistory::default();
        for i in 0..30 {
            h.push(frame(1 + i % 3));
        }
        let area = Rect::new(0, 0, 44, 18);
        let mut buf = Buffer::empty(area);
        let link = LinkInfo {
            answers: Answers::Yes,
            round_trip: Some(Duration::from_millis(42)),
            throughput: Some(125_000.0),
            late_replies: 0,
            held_by: HoldBy::Nothing,
        };
        CostPanel {
            history: &h,
            link: &link,
            colour: colour_line(relief_term::ColorDepth::Palette256, "tmux client no RGB"),
            pixels: None,
        }
        .render(area, &mut buf);
        let text: String = (0..area.height)
            .map(|y| {
                (0..area.width)
                    .map(|x| buf[(x, y)].symbol().to_string())
                    .collect::<String>()
                    + "\n"
            })
            .collect();
        for needle in [
            "cost (k)",
            "raster+shade",
            "encode",
            "write",
            "total",
            "frame time",
            "active:",
            "pixels 11.7k",
            "round trip     42.0 ms",
            "1.00 Mbit/s",
            "256 colours: tmux client no RGB",
        ] {
            assert!(text.contains(needle), "{needle} missing from\n{text}");
        }
        // The sparkline drew bars.
        assert!(text.chars().any(|c| "▁▂▃▄▅▆▇█".contains(c)), "{text}");
        // An empty history and a tiny area draw without panicking.
        let mut small = Buffer::empty(Rect::new(0, 0, 3, 2));
        CostPanel {
            history: &CostHistory::default(),
            link: &LinkInfo::default(),
            colour: String::new(),
            pixels: None,
        }
        .render(small.area, &mut small);
        assert_eq!(link_lines(&LinkInfo::default())[0], "round trip   waiting");
        let silent = LinkInfo {
            answers: Answers::No,
            ..LinkInfo::default()
        };
        assert!(link_lines(&silent)[1].contains("paced by the writes"));
        assert_eq!(link_lines(&silent).len(), 2);
        // Inside a multiplexer over SSH, or with --link, the panel says what holds frames.
        let queue = LinkInfo {
            held_by: HoldBy::Queue,
            ..silent
        };
        assert_eq!(link_lines(&queue)[2], "held by      SSH send queue");
        let stated = LinkInfo {
            held_by: HoldBy::Rate(125_000.0),
            ..silent
        };
        assert_eq!(link_lines(&stated)[2], "held by      --link 1.00 Mbit/s");
    }

    #[test]
    fn key_k_toggles_the_panel_in_the_view() {
        use crate::app::action::Action;
        use crate::app::keys::action_for_key;
        use crate::app::state::State;
        use crate::app::update::update;
        use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
        let mut state = State::new(
            relief_core::settings::Settings::default(),
            relief_term::ColorDepth::Truecolor,
        );
        let k = KeyEvent::new(KeyCode::Char('k'), KeyModifiers::NONE);
        assert_eq!(action_for_key(&state, &k), Some(Action::ToggleCost));
        let screen = Rect::new(0, 0, 80, 24);
        let fb = relief_core::framebuffer::Framebuffer::new(80, 44);
        let shows = |state: &State| {
            let mut buf = Buffer::empty(screen);
            crate::app::view::draw(state, &fb, [0, 0, 0], screen, &mut buf);
            (0..screen.height).any(|y| {
                (0..screen.width)
                    .map(|x| buf[(x, y)].symbol().to_string())
                    .collect::<String>()
                    .contains("cost (k)")
            })
        };
        assert!(!shows(&state));
        update(&mut state, Action::ToggleCost);
        assert!(state.cost_panel && shows(&state));
        update(&mut state, Action::ToggleCost);
        assert!(!state.cost_panel && !shows(&state));
    }
}
