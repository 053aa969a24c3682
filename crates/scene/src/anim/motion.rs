//! A scene's animation: its rig and the instant its objects show.

use std::sync::Arc;

use super::rig::{Clip, Rig};
use crate::Object;

/// The scene's rig, shared by the scenes built from one file, and the
/// instant its objects were last posed at.
#[derive(Clone, Debug)]
pub struct Motion {
    pub rig: Arc<Rig>,
    shown: Option<(Option<usize>, f32)>,
}

impl Motion {
    /// A motion whose objects show no instant yet.
    pub fn new(rig: Rig) -> Motion {
        Motion {
            rig: Arc::new(rig),
            shown: None,
        }
    }

    pub fn clips(&self) -> &[Clip] {
        &self.rig.clips
    }

    /// Poses `objects` (one per part of the rig, in order) at `time`
    /// seconds into `clip` (none: the rest pose), unless they show that
    /// instant already. Whether they changed.
    pub fn show(&mut self, objects: &mut [Object], clip: Option<usize>, time: f32) -> bool {
        let clip = clip.filter(|&c| c < self.rig.clips.len());
        let time = if time.is_finite() { time } else { 0.0 };
        if self.shown == Some((clip, time)) {
            return false;
        }
        let pose = self.rig.pose(clip, time);
        for (p, object) in objects.iter_mut().enumerate().take(self.rig.parts.len()) {
            let mesh = &mut object.mesh;
            if mesh.vertices.len() != self.rig.parts[p].rest.len() {
                continue;
            }
            self.rig
                .deform(p, &pose, &mesh.triangles, &mut mesh.vertices);
        }
        self.shown = Some((clip, time));
        true
    }
}
