//! Holding frames for a link the pacing replies do not see.
//!
//! Inside tmux or GNU screen the multiplexer answers the pacing query at
//! once, so a reply no longer means "on screen". Two other signals stand in:
//!
//! - **The send queue** of the SSH connection ([`crate::term::backlog`]):
//!   after a frame, the next waits until the queue is down to what the link
//!   delivers within [`ACK_DELAY`] (at least [`QUEUE_THRESHOLD`], at most
//!   the frame), i.e. until the client has about acknowledged the frame,
//!   which is what the reply means over plain SSH. While it drains, the fall
//!   of the queue measures the link's rate (acknowledgements arrive at the
//!   rate the link delivers), which decides previews and that allowance.
//!   Why the allowance: inside a multiplexer the client sends nothing back
//!   (over plain SSH the terminal's reply carries the acknowledgement), so
//!   its TCP delays the acknowledgement of a frame's last segments; waiting
//!   for it cost 40–80 ms a frame on a fast link.
//! - **A rate the user states** (`--link RATE`): each frame occupies the link
//!   for its bytes (plus the framing of SSH, TCP and IP) over that rate, and
//!   the next waits for the link to be free.
//!
//! Input keeps being applied while a frame is held, so the frame that goes
//! is the newest state; when input stops, the exact picture goes as soon as
//! the link is free. The clock and the queue readings are passed in, so
//! tests drive both.

use std::time::{Duration, Instant};

/// Bytes still queued that let the next frame go. The queue reads 0 on an
/// idle link; a frame is 20–50 kB at 160×48 (a half-resolution preview a
/// third of that), so what remains below this is a few segments at most:
/// the next frame waits behind next to nothing, as over plain SSH.
pub const QUEUE_THRESHOLD: u64 = 2048;

/// The multiplexer needs a moment to take the frame and write it to the
/// SSH connection: a reading taken earlier could find the queue still
/// empty. Measured at a few milliseconds; this leaves room for a busy
/// machine.
pub const GRACE: Duration = Duration::from_millis(15);

/// How often the queue is read while a frame is held.
pub const POLL: Duration = Duration::from_millis(10);

/// How long a receiver may delay an acknowledgement (Linux's shortest
/// delayed-acknowledgement time-out): bytes the link delivers within it are
/// as good as shown.
pub const ACK_DELAY: Duration = Duration::from_millis(40);

/// Bytes on the wire per byte written: SSH packets (length, padding, MAC)
/// and TCP/IP segments (about 66 bytes of headers per 1448) add 5–8 %;
/// rounded up so a stated rate is not overrun.
pub const FRAMING: f64 = 1.1;

/// Weight of a new drain-rate sample in the smoothed rate.
const SMOOTHING: f64 = 0.25;

/// Drain intervals shorter than this say little (timer noise).
const MIN_INTERVAL: Duration = Duration::from_millis(2);

/// What holds frames, besides the replies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HoldBy {
    /// Nothing: the replies alone pace (plain SSH, a local terminal or a
    /// local tmux).
    Nothing,
    /// The SSH connection's send queue.
    Queue,
    /// A stated link rate, in bytes per second.
    Rate(f64),
}

/// The hold's state (see the module notes).
#[derive(Clone, Debug)]
pub struct Hold {
    by: HoldBy,
    /// When the last frame was written.
    wrote: Option<Instant>,
    /// Stated rate: when the link is done with what was written.
    busy_until: Option<Instant>,
    /// The last queue reading, taken after the grace.
    last: Option<(Instant, Option<u64>)>,
    /// The largest write since the queue was last seen drained.
    frame: u64,
    /// Smoothed bytes per second the queue drained at.
    drained: Option<f64>,
}

impl Hold {
    pub fn new(by: HoldBy) -> Self {
        Hold {
            by,
            wrote: None,
            busy_until: None,
            last: None,
            frame: 0,
            drained: None,
        }
    }

    pub fn by(&self) -> HoldBy {
        self.by
    }

    /// A frame of `bytes` was written at `at`.
    pub fn wrote(&mut self, at: Instant, bytes: u64) {
        self.wrote = Some(at);
        self.last = None;
        self.frame = self.frame.max(bytes);
        if let HoldBy::Rate(rate) = self.by {
            let start = self.busy_until.map_or(at, |b| b.max(at));
            let busy = Duration::from_secs_f64(bytes as f64 * FRAMING / rate);
            self.busy_until = Some(start + busy);
        }
    }

    /// Whether the queue should be read at `now`: a frame was written more
    /// than the grace ago and the last reading is older than the poll.
    pub fn wants_reading(&self, now: Instant) -> bool {
        self.by == HoldBy::Queue
            && self.wrote.is_some_and(|w| now >= w + GRACE)
            && self.last.is_none_or(|(t, _)| now >= t + POLL)
    }

    /// A reading of the queue at `at` (`None`: the socket was not found).
    pub fn reading(&mut self, at: Instant, queued: Option<u64>) {
        if let (Some((t, Some(before))), Some(now)) = (self.last, queued) {
            let dt = at.saturating_duration_since(t);
            // A falling queue drains at the link's rate; a flat one waits
            // for acknowledgements (the round trip), which says nothing of
            // it, and one that emptied between two readings may have done
            // so at any time between them.
            if now < before && now > QUEUE_THRESHOLD && dt >= MIN_INTERVAL {
                let sample = (before - now) as f64 / dt.as_secs_f64();
                self.drained = Some(match self.drained {
                    Some(r) => r + SMOOTHING * (sample - r),
                    None => sample,
                });
            }
        }
        self.last = Some((at, queued));
        if queued.is_none_or(|q| q <= QUEUE_THRESHOLD) {
            self.frame = 0;
        }
    }

    /// The queue at or below which the next frame may go: what the link
    /// delivers within [`ACK_DELAY`] at the measured rate, at least
    /// [`QUEUE_THRESHOLD`] and at most the frame (an unknown rate is a link
    /// that drained whole frames between two readings: the frame).
    pub fn release_at(&self) -> u64 {
        let within = self
            .drained
            .map_or(u64::MAX, |r| (r * ACK_DELAY.as_secs_f64()) as u64);
        within.min(self.frame).max(QUEUE_THRESHOLD)
    }

    /// Whether the next frame may go at `now` (the readings so far).
    pub fn clear(&self, now: Instant) -> bool {
        self.until(now).is_none()
    }

    /// While held: when to look again (`None`: not held).
    pub fn until(&self, now: Instant) -> Option<Instant> {
        match self.by {
            HoldBy::Nothing => None,
            HoldBy::Rate(_) => self.busy_until.filter(|&b| b > now),
            HoldBy::Queue => {
                let wrote = self.wrote?;
                if now < wrote + GRACE {
                    return Some(wrote + GRACE);
                }
                match self.last {
                    // Not read since the grace: read now.
                    None => Some(now),
                    Some((t, Some(q))) if q > self.release_at() => Some((t + POLL).max(now)),
                    // Drained, or the socket is gone: nothing to wait for.
                    Some(_) => None,
                }
            }
        }
    }

    /// The link's rate in bytes per second, as stated or as measured from
    /// the queue's drain (`None`: not known here).
    pub fn rate(&self) -> Option<f64> {
        match self.by {
            HoldBy::Nothing => None,
            HoldBy::Queue => self.drained,
            HoldBy::Rate(r) => Some(r),
        }
    }
}

/// `--link`: measured, or as the user states it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LinkRate {
    /// By the replies, and by the send queue inside a multiplexer over SSH.
    Auto,
    /// Bytes per second.
    Stated(f64),
}

/// `--link`: `auto`, or a rate in bits per second with an optional `k`, `M`
/// or `G` (powers of 1000): `1M`, `50M`, `500k`, `2.5M`.
pub fn parse_link(text: &str) -> Result<LinkRate, String> {
    let t = text.trim();
    if t.eq_ignore_ascii_case("auto") {
        return Ok(LinkRate::Auto);
    }
    let (number, scale) = match t.char_indices().last() {
        Some((i, 'k' | 'K')) => (&t[..i], 1e3),
        Some((i, 'm' | 'M')) => (&t[..i], 1e6),
        Some((i, 'g' | 'G')) => (&t[..i], 1e9),
        _ => (t, 1.0),
    };
    let bits: f64 = number.parse().map_err(|_| {
        format!("expected auto or a rate in bits/s such as 1M or 50M, got '{text}'")
    })?;
    let bits = bits * scale;
    // Below 1 kbit/s a single frame would take minutes.
    if !bits.is_finite() || bits < 1e3 {
        return Err(format!(
            "the link rate must be at least 1k (bits/s), got '{text}'"
        ));
    }
    Ok(LinkRate::Stated(bits / 8.0))
}

/// The pacer for this process: a stated rate holds by that rate; `auto`
/// holds by the SSH connection's send queue inside tmux or screen when one
/// is found (see [`crate::term::backlog::SendQueue::here`]), else the
/// replies alone pace.
pub fn pacer_here(link: LinkRate) -> super::pacing::Pacer {
    use super::pacing::Pacer;
    match link {
        LinkRate::Stated(rate) => Pacer::default().with_hold(Hold::new(HoldBy::Rate(rate)), None),
        LinkRate::Auto => match super::backlog::SendQueue::here() {
            Some(mut queue) => Pacer::default().with_hold(
                Hold::new(HoldBy::Queue),
                Some(Box::new(move || queue.queued())),
            ),
            None => Pacer::default(),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Clock(Instant);

    impl Clock {
        fn at(&self, ms: u64) -> Instant {
            self.0 + Duration::from_millis(ms)
        }
    }

    fn clock() -> Clock {
        Clock(Instant::now())
    }

    /// Reads the queue whenever the hold asks, as the loop does.
    fn poll(h: &mut Hold, now: Instant, queued: Option<u64>) -> bool {
        if h.wants_reading(now) {
            h.reading(now, queued);
        }
        h.clear(now)
    }

    #[test]
    fn nothing_never_holds() {
        let c = clock();
        let mut h = Hold::new(HoldBy::Nothing);
        h.wrote(c.at(0), 1 << 20);
        assert!(h.clear(c.at(0)) && !h.wants_reading(c.at(100)));
        assert_eq!(h.rate(), None);
    }

    #[test]
    fn a_frame_is_held_until_the_queue_has_drained() {
        let c = clock();
        let mut h = Hold::new(HoldBy::Queue);
        assert!(h.clear(c.at(0)), "nothing written yet");
        h.wrote(c.at(0), 27_000);
        // Within the grace the queue is not trusted (the frame may not be in it yet).
        assert!(!h.wants_reading(c.at(14)));
        assert!(!poll(&mut h, c.at(14), Some(0)));
        assert_eq!(h.until(c.at(14)), Some(c.at(15)));
        // After it: 27 kB queued, more than the frame's 27 000 bytes: held
        // (the rate unknown, the frame may stay in flight); read again a poll later.
        assert_eq!(h.release_at(), 27_000);
        assert!(!poll(&mut h, c.at(15), Some(27_100)));
        assert_eq!(h.until(c.at(16)), Some(c.at(25)));
        assert!(!h.wants_reading(c.at(24)));
        // Flat for a round trip (no acknowledgement yet): no rate from it.
        assert!(!poll(&mut h, c.at(25), Some(27_100)));
        assert!(!poll(&mut h, c.at(55), Some(27_100)));
        assert_eq!(h.rate(), None);
        // Then it falls 1250 bytes every 10 ms: 125 kB/s (1 Mbit/s), which
        // delivers 5000 bytes within the acknowledgement delay.
        assert!(!poll(&mut h, c.at(65), Some(25_850)));
        assert!((h.rate().unwrap() - 125_000.0).abs() < 1e-6);
        assert_eq!(h.release_at(), 5_000);
        assert!(!poll(&mut h, c.at(75), Some(24_600)));
        // Still 125 kB/s: 5850 bytes left at 225 ms, 4600 at 235.
        assert!(!poll(&mut h, c.at(225), Some(5_850)));
        assert!(poll(&mut h, c.at(235), Some(4_600)));
        assert!((h.rate().unwrap() - 125_000.0).abs() < 1e-6);
        assert_eq!(h.until(c.at(235)), None);
        // The next frame: one of 3 kB, queued behind what is left.
        h.wrote(c.at(240), 3_000);
        assert!(!h.clear(c.at(240)));
        assert_eq!(h.release_at(), 5_000, "the largest since the queue drained");
        assert!(!poll(&mut h, c.at(255), Some(7_000)));
        assert!(poll(&mut h, c.at(265), Some(QUEUE_THRESHOLD)));
        // Drained: the allowance starts over from the next frame, never
        // below the threshold.
        h.wrote(c.at(270), 1_000);
        assert_eq!(h.release_at(), QUEUE_THRESHOLD);
        assert!(poll(&mut h, c.at(285), Some(QUEUE_THRESHOLD)));
    }

    #[test]
    fn on_a_fast_link_one_frame_may_stay_unacknowledged() {
        let c = clock();
        let mut h = Hold::new(HoldBy::Queue);
        // 25 kB written; the next reading finds them all still queued (the
        // acknowledgement delayed), the one after that none: no rate.
        h.wrote(c.at(0), 25_000);
        assert!(poll(&mut h, c.at(15), Some(25_000)), "one frame in flight");
        h.wrote(c.at(16), 25_000);
        assert!(!poll(&mut h, c.at(31), Some(50_000)), "not two");
        assert!(poll(&mut h, c.at(41), Some(0)));
        assert_eq!(h.rate(), None, "the drop may have come at any time");
    }

    #[test]
    fn the_drain_rate_is_smoothed_and_ignores_rises() {
        let c = clock();
        let mut h = Hold::new(HoldBy::Queue);
        h.wrote(c.at(0), 60_000);
        h.reading(c.at(20), Some(60_000));
        h.reading(c.at(30), Some(50_000)); // 1 MB/s
        assert!((h.rate().unwrap() - 1e6).abs() < 1e-3);
        h.reading(c.at(40), Some(55_000)); // rose: more came in, no sample
        h.reading(c.at(41), Some(54_000)); // 1 ms: too short to say
        assert!((h.rate().unwrap() - 1e6).abs() < 1e-3);
        h.reading(c.at(51), Some(52_000)); // 200 kB/s: a quarter of the way there
        assert!((h.rate().unwrap() - 800_000.0).abs() < 1e-3);
        // Emptied between two readings: no sample.
        h.reading(c.at(61), Some(0));
        h.reading(c.at(62), Some(4000));
        h.reading(c.at(72), Some(QUEUE_THRESHOLD));
        assert!((h.rate().unwrap() - 800_000.0).abs() < 1e-3);
    }

    #[test]
    fn a_lost_socket_does_not_hold() {
        let c = clock();
        let mut h = Hold::new(HoldBy::Queue);
        h.wrote(c.at(0), 27_000);
        assert!(poll(&mut h, c.at(20), None));
    }

    #[test]
    fn a_stated_rate_spaces_the_frames() {
        let c = clock();
        // 1 Mbit/s: 125 kB/s; 25 kB with the framing take 220 ms.
        let mut h = Hold::new(HoldBy::Rate(125_000.0));
        assert_eq!(h.rate(), Some(125_000.0));
        h.wrote(c.at(0), 25_000);
        assert!(!h.clear(c.at(219)));
        assert!(h.clear(c.at(220)));
        // Written before the link is free (a status refresh): it queues behind.
        h.wrote(c.at(100), 1_000);
        assert_eq!(
            h.until(c.at(100)),
            Some(c.at(228) + Duration::from_micros(800))
        );
        // Written after: from then on.
        h.wrote(c.at(1000), 12_500);
        assert!(!h.clear(c.at(1109)) && h.clear(c.at(1110)));
        assert!(!h.wants_reading(c.at(2000)), "no queue to read");
    }

    #[test]
    fn link_rates_parse_in_bits_per_second() {
        use LinkRate::{Auto, Stated};
        assert_eq!(parse_link("auto"), Ok(Auto));
        assert_eq!(parse_link("AUTO"), Ok(Auto));
        assert_eq!(parse_link("1M"), Ok(Stated(125_000.0)));
        assert_eq!(parse_link("50M"), Ok(Stated(6_250_000.0)));
        assert_eq!(parse_link("500k"), Ok(Stated(62_500.0)));
        assert_eq!(parse_link("2.5m"), Ok(Stated(312_500.0)));
        assert_eq!(parse_link("1G"), Ok(Stated(125_000_000.0)));
        assert_eq!(parse_link("64000"), Ok(Stated(8_000.0)));
        for bad in ["", "M", "fast", "-1M", "0", "999", "NaNM", "infM", "1T"] {
            assert!(parse_link(bad).is_err(), "{bad}");
        }
    }
}
