//! What the lights key cycles through: pure data, read by the glue (what to send) and shown by name.

use crate::protocol::message::Lights;
use crate::protocol::LightMode;

/// The light settings, in the order the lights key steps through them, and what the message calls each.
pub const LIGHT_CYCLE: [(Lights, &str); 5] = [
    (
        Lights {
            enable: 1,
            front_mode: LightMode::On.code(),
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
            front_mode: LightMode::Breath.code(),
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
            front_mode: LightMode::Custom.code(),
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
            front_mode: LightMode::Off.code(),
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
