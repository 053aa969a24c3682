//! The keys of an animated model (`A` play / pause, `C` next clip, `,` `.`
//! step) and the clock that moves it: what `update` does with them.

use super::state::{ANIMATION_STEP, Playback, State};
use relief_core::sanitize::clean;

/// Longest step one tick moves the animation: a stall (a slow link) is
/// not made up for in one leap.
const MAX_TICK: f32 = 0.25;

/// A new model's clips: the first plays from its start (none: nothing
/// plays).
pub fn take_clips(state: &mut State, clips: Vec<(String, f32)>) {
    let playing = !clips.is_empty();
    state.playback = Playback {
        clips,
        clip: 0,
        time: 0.0,
        playing,
    };
}

/// `seconds` passed: a playing animation moves on by them.
pub fn tick(state: &mut State, seconds: f32) {
    if state.playback.playing && seconds.is_finite() && seconds > 0.0 {
        state.playback.advance(seconds.min(MAX_TICK));
    }
}

/// `A`: play or pause.
pub fn toggle(state: &mut State) {
    let p = &mut state.playback;
    if p.clips.is_empty() {
        state.message = Some("this model has no animation".into());
    } else {
        p.playing = !p.playing;
        state.message = Some(describe(p));
    }
}

/// `C`: the next clip, from its start.
pub fn next_clip(state: &mut State) {
    let p = &mut state.playback;
    if p.clips.is_empty() {
        state.message = Some("this model has no animation".into());
        return;
    }
    p.clip = (p.clip + 1) % p.clips.len();
    p.time = 0.0;
    state.message = Some(describe(p));
}

/// `,` `.`: paused, `frames` steps back or on.
pub fn step(state: &mut State, frames: i32) {
    let p = &mut state.playback;
    if p.clips.is_empty() {
        state.message = Some("this model has no animation".into());
        return;
    }
    p.playing = false;
    p.advance(frames as f32 * ANIMATION_STEP);
    state.message = Some(describe(p));
}

/// One line: which clip of how many, its name, where it is, and whether
/// it plays.
fn describe(p: &Playback) -> String {
    let (name, length) = &p.clips[p.clip];
    let how = if p.playing { "playing" } else { "paused" };
    format!(
        "animation {} of {}: {} at {:.2} of {:.2} s, {how} (A C , .)",
        p.clip + 1,
        p.clips.len(),
        clean(name),
        p.time,
        length
    )
}
