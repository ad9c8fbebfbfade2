//! `tracerctl lights --front MODE [--brightness N] [--rear MODE [--rear-brightness N]] | --release`:
//! set the lights (0x121) and confirm from the light state (0x231).
//!
//! A brightness belongs to the custom mode only: `--brightness` without `--front custom` and
//! `--front custom` without `--brightness` are usage errors (exit 2), as are the same for the rear. The
//! rear bytes are reserved on TRACER: they are sent, but not confirmed. `--release` sends enable = 0,
//! which hands the lights back to the firmware. Each send carries the next count byte; the command is
//! sent again up to three times within `--timeout` until a light state received after the first send
//! matches (enable, front mode, and the brightness in custom mode).

use std::io::Write;
use std::time::Duration;

use anyhow::Result;

use super::live;
use super::Global;
use crate::exit::{Failure, SUCCESS, USAGE};
use crate::output::plural;
use crate::protocol::catalog;
use crate::protocol::message::MessageKind;
use crate::protocol::message::{Lights, LIGHT_CUSTOM};
use crate::protocol::{ControlMode, LightMode, Wire};
use crate::session::confirm::send_until;
use crate::session::Session;

/// Sends after the first one, if the light state does not match yet.
const RESENDS: u32 = 3;

/// `tracerctl lights`' settings (checked against each other by [`requested`]).
#[derive(Clone, Debug)]
pub struct Options {
    pub front: Option<LightMode>,
    /// Front brightness for custom mode, percent.
    pub brightness: Option<u8>,
    pub rear: Option<LightMode>,
    pub rear_brightness: Option<u8>,
    /// Hand the lights back to the firmware.
    pub release: bool,
    /// How long to wait for the light state to confirm.
    pub timeout: Duration,
}

pub fn run(global: &Global, args: &Options) -> Result<u8> {
    // Usage errors before touching the link.
    requested(args)?;
    let session = live::open(global, true)?;
    execute(&session, args, &mut std::io::stdout().lock())
}

/// Sets the lights on an open session; the result goes to `out`, a failure is the error.
pub fn execute(session: &Session, args: &Options, out: &mut impl Write) -> Result<u8> {
    let lights = requested(args)?;
    // Settles the protocol version on CAN (the V1 light frame is 0x140); the status itself is only used
    // to explain a failure.
    let _ = live::first_status(session);
    let attempt = send_until(
        session,
        args.timeout,
        RESENDS,
        || vec![session.codec().lights(lights)],
        |status, sent| {
            status.lights.filter(|(at, shown)| *at > sent && matches(&lights, shown)).map(|(_, shown)| shown)
        },
    )?;
    let wire = session.wire();
    let source = state_source(wire);
    if let Some(shown) = attempt.found {
        let what = if lights.enable == 0 {
            format!("released to the firmware (confirmed by {source}: {})", describe(&shown))
        } else {
            format!("{} (confirmed by {source})", describe(&lights))
        };
        writeln!(out, "lights: {what}")?;
        if let Some(rear) = args.rear {
            writeln!(
                out,
                "lights: rear {} sent, not confirmed (reserved on TRACER)",
                rear_text(rear, &lights)
            )?;
        }
        return Ok(SUCCESS);
    }

    let status = session.status();
    let wanted = if lights.enable == 0 { "released to the firmware".to_string() } else { describe(&lights) };
    let timeout = humantime::format_duration(args.timeout);
    let sends = format!("{} time{}", attempt.sends, plural(attempt.sends));
    let message = match status.lights.filter(|(at, _)| *at > attempt.first_sent) {
        Some((_, shown)) => {
            let standby = status
                .fresh_system(live::STATUS_WAIT)
                .filter(|(state, state_wire)| *state_wire == Wire::CanV2 && state.mode(*state_wire) == Some(ControlMode::Standby))
                .map_or("", |_| {
                    "; the robot is in standby, where firmware may ignore everything but the control-mode \
                     command: run `tracerctl mode can` first"
                });
            format!(
                "lights not confirmed: asked for {wanted}, sent {sends} within {timeout}, but {source} shows {}{standby}",
                describe(&shown)
            )
        }
        None if status.frames > 0 && status.link_error.is_none() => format!(
            "lights not confirmed: sent {sends} but no light state ({source}) arrived within {timeout}; {} frames \
             were received: is this a TRACER, and is --protocol right?",
            status.frames
        ),
        None => format!("lights not confirmed: sent {sends}; {}", live::no_status_message(session, &status)),
    };
    Err(Failure::not_done(message).into())
}

/// The light command the arguments ask for, or a usage error.
pub fn requested(args: &Options) -> Result<Lights, Failure> {
    let usage = |message: String| Failure { code: USAGE, message };
    if args.release {
        return Ok(Lights::release());
    }
    let Some(front) = args.front else {
        return Err(usage("give --front MODE, or --release to hand the lights back to the firmware".into()));
    };
    let front_brightness = brightness("--front", "--brightness", front, args.brightness).map_err(usage)?;
    let (rear_mode, rear_brightness) = match args.rear {
        Some(rear) => (
            rear.code(),
            brightness("--rear", "--rear-brightness", rear, args.rear_brightness).map_err(usage)?,
        ),
        None if args.rear_brightness.is_some() => {
            return Err(usage("--rear-brightness applies only to --rear custom".into()))
        }
        None => (LightMode::Off.code(), 0),
    };
    let lights = Lights::front(front, front_brightness).map_err(|error| usage(error.to_string()))?;
    Ok(Lights { rear_mode, rear_brightness, ..lights })
}

fn brightness(
    option: &str,
    brightness_option: &str,
    mode: LightMode,
    value: Option<u8>,
) -> Result<u8, String> {
    match (mode, value) {
        (LightMode::Custom, Some(percent)) => Ok(percent),
        (LightMode::Custom, None) => {
            Err(format!("{option} custom needs {brightness_option} PERCENT (0-100)"))
        }
        (_, Some(_)) => Err(format!(
            "{brightness_option} applies only to {option} custom (the other modes have a fixed brightness)"
        )),
        (_, None) => Ok(0),
    }
}

/// Whether a reported light state shows what was asked: released (enable 0; the firmware then picks the
/// mode), or enable 1 with the front mode, and the brightness in custom mode. The rear bytes are reserved.
pub fn matches(asked: &Lights, shown: &Lights) -> bool {
    if asked.enable == 0 {
        return shown.enable == 0;
    }
    shown.enable == asked.enable
        && shown.front_mode == asked.front_mode
        && (asked.front_mode != LIGHT_CUSTOM || shown.front_brightness == asked.front_brightness)
}

/// `front custom 30 %`, `front on`, `firmware control, front on`
pub fn describe(lights: &Lights) -> String {
    let mode = LightMode::from_code(lights.front_mode)
        .map_or_else(|| format!("mode 0x{:02X}", lights.front_mode), |mode| mode.name().to_string());
    let front = if lights.front_mode == LIGHT_CUSTOM {
        format!("front {mode} {} %", lights.front_brightness)
    } else {
        format!("front {mode}")
    };
    match lights.enable {
        0 => format!("firmware control, {front}"),
        1 => front,
        other => format!("enable 0x{other:02X}, {front}"),
    }
}

fn rear_text(rear: LightMode, lights: &Lights) -> String {
    match rear {
        LightMode::Custom => format!("custom {} %", lights.rear_brightness),
        LightMode::Off | LightMode::On | LightMode::Breath => rear.name().to_string(),
    }
}

/// Where the light state comes from on each wire: `0x231`, `0x141`, `the RS232 light status (0xAA07)`.
fn state_source(wire: Wire) -> String {
    let id =
        catalog::identifier_of(MessageKind::LightState, wire).map_or_else(String::new, |id| id.to_string());
    match wire {
        Wire::Serial => format!("the RS232 light status ({id})"),
        Wire::CanV1 | Wire::CanV2 => id,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::link::LinkFrame;
    use crate::protocol::message::{LIGHT_BREATH, LIGHT_ON};
    use crate::protocol::Codec;

    fn args(front: Option<LightMode>, brightness: Option<u8>) -> Options {
        Options {
            front,
            brightness,
            rear: None,
            rear_brightness: None,
            release: false,
            timeout: Duration::from_secs(1),
        }
    }

    fn usage_message(result: Result<Lights, Failure>) -> String {
        let error = result.unwrap_err();
        assert_eq!(error.code, USAGE);
        error.message
    }

    #[test]
    fn custom_30_percent_is_the_documented_frame_with_a_rolling_count() {
        let lights = requested(&args(Some(LightMode::Custom), Some(30))).unwrap();
        let mut codec = Codec::new(Wire::CanV2);
        let frames: Vec<String> = (0..3)
            .map(|_| match codec.lights(lights) {
                LinkFrame::Can(frame) => frame.to_string(),
                other => panic!("{other:?}"),
            })
            .collect();
        assert_eq!(frames, ["121#01031E0000000000", "121#01031E0000000001", "121#01031E0000000002"]);
    }

    #[test]
    fn release_is_enable_0() {
        let release = Options { release: true, ..args(None, None) };
        let lights = requested(&release).unwrap();
        let LinkFrame::Can(frame) = Codec::new(Wire::CanV2).lights(lights) else { panic!() };
        assert_eq!(frame.to_string(), "121#0000000000000000");
    }

    #[test]
    fn brightness_belongs_to_custom_only() {
        let message = usage_message(requested(&args(Some(LightMode::On), Some(30))));
        assert_eq!(
            message,
            "--brightness applies only to --front custom (the other modes have a fixed brightness)"
        );
        let message = usage_message(requested(&args(Some(LightMode::Custom), None)));
        assert_eq!(message, "--front custom needs --brightness PERCENT (0-100)");
        let rear = Options { rear_brightness: Some(5), ..args(Some(LightMode::On), None) };
        assert_eq!(usage_message(requested(&rear)), "--rear-brightness applies only to --rear custom");
        let rear = Options { rear: Some(LightMode::Custom), ..args(Some(LightMode::On), None) };
        assert_eq!(usage_message(requested(&rear)), "--rear custom needs --rear-brightness PERCENT (0-100)");
        let rear = Options {
            rear: Some(LightMode::Custom),
            rear_brightness: Some(40),
            ..args(Some(LightMode::Breath), None)
        };
        let lights = requested(&rear).unwrap();
        assert_eq!(
            (lights.front_mode, lights.front_brightness, lights.rear_mode, lights.rear_brightness),
            (2, 0, 3, 40)
        );
    }

    #[test]
    fn confirmation_compares_what_the_mode_uses() {
        let custom = Lights::front(LightMode::Custom, 30).unwrap();
        assert!(matches(&custom, &Lights { count: 9, ..custom }));
        assert!(!matches(&custom, &Lights { front_brightness: 31, ..custom }));
        assert!(!matches(&custom, &Lights { enable: 0, ..custom }));
        let on = Lights::front(LightMode::On, 0).unwrap();
        assert!(matches(&on, &Lights { front_brightness: 77, rear_mode: 2, ..on }));
        assert!(!matches(&on, &Lights { front_mode: LIGHT_BREATH, ..on }));
        let release = Lights::release();
        assert!(matches(&release, &Lights { enable: 0, front_mode: LIGHT_ON, ..release }));
        assert!(!matches(&release, &on));
    }

    #[test]
    fn descriptions() {
        assert_eq!(describe(&Lights::front(LightMode::Custom, 30).unwrap()), "front custom 30 %");
        assert_eq!(describe(&Lights::front(LightMode::Breath, 0).unwrap()), "front breath");
        assert_eq!(
            describe(&Lights { enable: 0, front_mode: LIGHT_ON, ..Lights::default() }),
            "firmware control, front on"
        );
        assert_eq!(describe(&Lights { enable: 1, front_mode: 9, ..Lights::default() }), "front mode 0x09");
    }
}
