//! The terminal side: encoder bytes, colours, input decoding.

mod bytes;
mod colour;
mod encoder;
mod input;
mod pixels;
