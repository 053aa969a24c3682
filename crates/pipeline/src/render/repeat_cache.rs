//! The repeated triangles of each object's mesh (`scene::repeats`), found
//! when a mesh is first drawn and kept while the same mesh is drawn again.

use relief_scene::Scene;
use relief_scene::repeats::{RepeatPairs, find_repeats};

/// Per object: which triangle list the pairs were found on (its address
/// and length) and the pairs.
#[derive(Default)]
pub(super) struct RepeatCache {
    objects: Vec<((usize, usize), RepeatPairs)>,
}

impl RepeatCache {
    /// Finds the repeats of every object whose triangle list is new.
    pub(super) fn update(&mut self, scene: &Scene) {
        self.objects.truncate(scene.objects.len());
        for (i, object) in scene.objects.iter().enumerate() {
            let tris = &object.mesh.triangles;
            let key = (tris.as_ptr() as usize, tris.len());
            match self.objects.get_mut(i) {
                Some((k, _)) if *k == key => {}
                Some(slot) => *slot = (key, find_repeats(tris)),
                None => self.objects.push((key, find_repeats(tris))),
            }
        }
    }

    /// The pairs of object `i` (none before `update`).
    pub(super) fn of(&self, i: usize) -> &[(u32, u32)] {
        self.objects.get(i).map_or(&[], |(_, p)| p.as_slice())
    }

    /// The pairs of every object, in object order.
    pub(super) fn all(&self) -> Vec<&[(u32, u32)]> {
        self.objects.iter().map(|(_, p)| p.as_slice()).collect()
    }
}
