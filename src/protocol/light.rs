//! The light mode: one type for the front (and reserved rear) mode byte of the light command and state,
//! what `tracerctl lights` accepts and every display. The wire codes live here and nowhere else.

use strum::{EnumString, IntoStaticStr, VariantArray};

/// A light mode. Names (`off`, `on`, `breath`, `custom`) come from the variants.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Hash, EnumString, IntoStaticStr, VariantArray, strum::Display,
)]
#[strum(serialize_all = "snake_case")]
pub enum LightMode {
    Off,
    On,
    /// Breathing.
    Breath,
    /// The brightness byte (0-100 %) sets the brightness.
    Custom,
}

impl LightMode {
    /// `off`, `on`, `breath` or `custom`.
    pub fn name(self) -> &'static str {
        self.into()
    }

    /// The mode byte: off 0, on 1, breath 2, custom 3 (the same on every wire).
    pub const fn code(self) -> u8 {
        match self {
            LightMode::Off => 0,
            LightMode::On => 1,
            LightMode::Breath => 2,
            LightMode::Custom => 3,
        }
    }

    /// The mode a byte means, or `None` for a byte no document defines; the inverse of [`LightMode::code`].
    pub const fn from_code(code: u8) -> Option<Self> {
        match code {
            0 => Some(LightMode::Off),
            1 => Some(LightMode::On),
            2 => Some(LightMode::Breath),
            3 => Some(LightMode::Custom),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_round_trip() {
        let codes: Vec<_> = LightMode::VARIANTS.iter().map(|mode| mode.code()).collect();
        assert_eq!(codes, [0, 1, 2, 3]);
        for code in 0..=u8::MAX {
            match LightMode::from_code(code) {
                Some(mode) => assert_eq!(mode.code(), code),
                None => assert!(code > 3, "{code}"),
            }
        }
    }

    #[test]
    fn names_and_parsing_agree() {
        let names: Vec<_> = LightMode::VARIANTS.iter().map(|mode| mode.name()).collect();
        assert_eq!(names, ["off", "on", "breath", "custom"]);
        for mode in LightMode::VARIANTS {
            assert_eq!(mode.name().parse::<LightMode>(), Ok(*mode));
            assert_eq!(mode.to_string(), mode.name());
        }
        assert!("breathing".parse::<LightMode>().is_err());
    }
}
