//! The TRACER protocol: typed messages and their CAN (V1, V2) and RS232 encodings. Pure: no I/O.

pub mod frame;

pub use frame::{CanFrame, FrameError, FrameKind};
