//! `relief bench`: what accuracy costs in time.
//!
//! For each configuration (see `config`): the median and spread of the frame
//! time over fixed orientations, shaded pixels per second, and the error
//! against a supersampled reference image of the same views (PSNR, largest
//! channel error, SSIM).

pub mod config;
pub mod font;
pub mod metrics;
pub mod pareto;
pub mod resolve;
