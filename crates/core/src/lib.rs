//! The leaves every stage of relief shares: the settings a frame is drawn
//! with, the framebuffer it is drawn into, the frame's statistics, the memory
//! budget, panic containment and number sanitising.

pub mod budget;
pub mod contain;
pub mod framebuffer;
pub mod sanitize;
pub mod settings;
pub mod stats;
