//! What a frame cost, counted per stage. Tests read the counters to prove
//! that an effect that is off does no work; the app and `relief bench` show them.

use std::ops::AddAssign;
use std::time::Duration;

/// Work counters of one frame (sums over all threads: identical for any thread count).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Triangles submitted after culling and clipping.
    pub triangles_drawn: u64,
    /// Triangles that crossed a clip plane and were cut.
    pub triangles_clipped: u64,
    /// Pixels (or samples) whose colour was computed.
    pub pixels_shaded: u64,
    /// Texture colour reads (one per filtered sample).
    pub texture_samples: u64,
    /// Height-map derivative evaluations (bump).
    pub bump_evals: u64,
    /// Light × point evaluations (N·L).
    pub light_evals: u64,
    /// Light × point highlight evaluations ((N·H)^s); 0 when specular is off.
    pub specular_evals: u64,
    /// Environment reads (one per reflecting pixel); 0 when the environment is off.
    pub env_lookups: u64,
    /// Depth comparisons.
    pub depth_tests: u64,
    /// Mip chains built this frame (the texture's and the dot3 normal map's).
    pub mip_builds: u64,
    /// Dot3 normal maps built this frame.
    pub normal_map_builds: u64,
    /// Shadow-map texels written.
    pub shadow_texels: u64,
    /// Shadow-map lookups.
    pub shadow_lookups: u64,
    /// Tangent-frame segments drawn (T, B, N at each shown vertex); 0 when the view is off.
    pub frame_lines: u64,
    /// Colours that were NaN or infinite before quantisation (must stay 0).
    pub nonfinite: u64,
    /// Of `pixels_shaded`, those shaded or filled eight at a time (a
    /// packet's live lanes); the rest went through the one-pixel loop.
    pub packet_pixels: u64,
}

impl AddAssign for Counters {
    fn add_assign(&mut self, o: Counters) {
        self.triangles_drawn += o.triangles_drawn;
        self.triangles_clipped += o.triangles_clipped;
        self.pixels_shaded += o.pixels_shaded;
        self.texture_samples += o.texture_samples;
        self.bump_evals += o.bump_evals;
        self.light_evals += o.light_evals;
        self.specular_evals += o.specular_evals;
        self.env_lookups += o.env_lookups;
        self.depth_tests += o.depth_tests;
        self.mip_builds += o.mip_builds;
        self.normal_map_builds += o.normal_map_builds;
        self.shadow_texels += o.shadow_texels;
        self.shadow_lookups += o.shadow_lookups;
        self.frame_lines += o.frame_lines;
        self.nonfinite += o.nonfinite;
        self.packet_pixels += o.packet_pixels;
    }
}

/// Counters plus the wall time of each stage of one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameStats {
    pub counters: Counters,
    /// Deciding what runs and transforming vertices.
    pub plan_time: Duration,
    /// Rasterizing and shading (including any shadow pass and resolve).
    pub raster_time: Duration,
    /// Bands of rows drawn whole, and in all (they depend on the number
    /// of threads, unlike the counters).
    pub bands_drawn: usize,
    pub bands: usize,
    /// The frame was stopped by the renderer's cancel hook: its picture
    /// is incomplete.
    pub abandoned: bool,
}
