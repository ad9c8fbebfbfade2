//! Which encoding a frame uses: CAN V2, CAN V1 or RS232. A leaf: the messages, the control mode's codes and
//! the catalog all read it.

/// Which encoding a message came from or is meant for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Wire {
    /// CAN protocol V2 (current TRACER firmware).
    CanV2,
    /// CAN protocol V1 (older firmware): checksum in the last byte.
    CanV1,
    /// RS232 `5A A5` frames.
    Serial,
}

impl Wire {
    pub fn as_str(self) -> &'static str {
        match self {
            Wire::CanV2 => "can-v2",
            Wire::CanV1 => "can-v1",
            Wire::Serial => "serial",
        }
    }
}
