//! The TRACER protocol: typed messages and their CAN (V1, V2) and RS232 encodings. Pure: no I/O.

pub mod can;
pub mod catalog;
pub mod codec;
pub mod constants;
pub mod detect;
pub mod error_frame;
pub mod faults;
pub mod fields;
pub mod frame;
pub mod id;
pub mod light;
pub mod message;
pub mod mode;
pub mod payload;
pub mod pose;
pub mod serial;
pub mod transitions;
pub mod version;
pub mod wire;

pub use can::{decode, DecodeError, ProtocolHint};
pub use codec::{ClearTarget, Codec, LinkFrame};
pub use faults::{FlagInfo, FlagTable, Flags, Severity};
pub use fields::{for_each_field, Field, FieldName, Value};
pub use frame::{CanFrame, FrameError, FrameKind};
pub use id::FrameId;
pub use light::LightMode;
pub use message::{Decoded, Message, MessageKind};
pub use mode::ControlMode;
pub use wire::Wire;
