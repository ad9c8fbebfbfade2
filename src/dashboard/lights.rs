//! What the lights key cycles through: pure data, read by the glue (what to send) and shown by name.

use crate::protocol::message::{Lights, LIGHT_BREATH, LIGHT_CUSTOM, LIGHT_OFF, LIGHT_ON};

/// The light settings, in the order the lights key steps through them, and what the message calls each.
pub const LIGHT_CYCLE: [(Lights, &str); 5] = [
    (
        Lights {
            enable: 1,
            front_mode: LIGHT_ON,
            front_brightness: 0,
            rear_mode: 0,
            rear_brightness: 0,
            count: 0,
        },
        "on",
    ),
    (
        Lights {
            enable: 1,
            front_mode: LIGHT_BREATH,
            front_brightness: 0,
            rear_mode: 0,
            rear_brightness: 0,
            count: 0,
        },
        "breathing",
    ),
    (
        Lights {
            enable: 1,
            front_mode: LIGHT_CUSTOM,
            front_brightness: 30,
            rear_mode: 0,
            rear_brightness: 0,
            count: 0,
        },
        "custom 30 %",
    ),
    (
        Lights {
            enable: 1,
            front_mode: LIGHT_OFF,
            front_brightness: 0,
            rear_mode: 0,
            rear_brightness: 0,
            count: 0,
        },
        "off",
    ),
    (
        Lights { enable: 0, front_mode: 0, front_brightness: 0, rear_mode: 0, rear_brightness: 0, count: 0 },
        "released to the firmware",
    ),
];
