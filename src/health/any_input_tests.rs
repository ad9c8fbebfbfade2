//! Any messages at any stamps: the analysis never panics (tests build with overflow checks) and always
//! reports. The fuzz target `summary` reaches it through `decode`; this feeds the analyzer directly, with
//! stamps at the ends of `i64`, stamps running backwards, and every field at its extremes.

use proptest::prelude::*;

use super::Analyzer;
use crate::protocol::{can, id, CanFrame, ProtocolHint};

/// The identifiers whose messages the analysis takes (and one it ignores).
const IDS: [u32; 9] = [
    id::ID_MOTION_COMMAND,
    id::ID_SYSTEM_STATE,
    id::ID_MOTION_STATE,
    id::ID_MOTOR1_HIGH_SPEED,
    id::ID_MOTOR2_HIGH_SPEED,
    id::ID_MOTOR1_LOW_SPEED,
    id::ID_MOTOR2_LOW_SPEED,
    id::ID_ODOMETRY,
    id::ID_LIGHT_STATE,
];

/// A time step: mostly a feedback period, sometimes a jump anywhere (the ends of `i64` included).
fn stamps() -> impl Strategy<Value = i64> {
    prop_oneof![
        6 => Just(20_000i64),
        2 => -30_000i64..3_000_000,
        1 => Just(i64::MAX),
        1 => Just(i64::MIN),
        1 => any::<i64>(),
    ]
}

fn messages() -> impl Strategy<Value = Vec<(i64, usize, [u8; 8])>> {
    let byte = prop_oneof![Just(0u8), Just(0x7f), Just(0x80), Just(0xff), any::<u8>()];
    proptest::collection::vec((stamps(), 0..IDS.len(), proptest::array::uniform8(byte)), 0..600)
}

/// Feeds `messages`: a step is added to the time (wrapping), a jump replaces it.
fn feed(messages: &[(i64, usize, [u8; 8])], analyzer: &mut Analyzer) {
    let mut t: i64 = 1_700_000_000_000_000;
    for &(step, index, data) in messages {
        t = match step {
            i64::MAX | i64::MIN => step,
            step if step.unsigned_abs() > 3_000_000 => step,
            step => t.wrapping_add(step),
        };
        let frame = CanFrame::new(IDS[index], &data).expect("a standard identifier");
        if let Ok(Some(decoded)) = can::decode(&frame, ProtocolHint::V2) {
            analyzer.observe(t, &decoded.message);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    #[test]
    fn any_messages_at_any_stamps_are_analysed_without_panic(messages in messages()) {
        let mut whole = Analyzer::new();
        feed(&messages, &mut whole);
        let report = whole.report();
        // Two chunks merged: the same path `decode -j N --summary` takes.
        let half = messages.len() / 2;
        let mut first = Analyzer::partial();
        let mut second = Analyzer::partial();
        feed(&messages[..half], &mut first);
        feed(&messages[half..], &mut second);
        if first.can_absorb(&second) {
            first.absorb(&second);
        }
        let _ = first.report();
        prop_assert!(report.steps.len() <= messages.len());
    }
}

/// The fuzzing find of CI run 36 (fuzz/regressions/summary/health_silence_gap_overflow): commands stamped
/// `i64::MAX` survived a fresh start, so the next run's command period was 2^63 µs and overflowed.
#[test]
fn commands_at_the_end_of_time_then_at_the_start_are_analysed() {
    let command = |linear| {
        let mut data = [0u8; 8];
        data[..2].copy_from_slice(&i16::to_be_bytes(linear));
        can::decode(&CanFrame::new(id::ID_MOTION_COMMAND, &data).unwrap(), ProtocolHint::V2)
            .unwrap()
            .unwrap()
            .message
    };
    let mut analyzer = Analyzer::new();
    analyzer.observe(i64::MAX, &command(300));
    analyzer.observe(5, &command(0));
    let report = analyzer.report();
    assert!(report.steps.is_empty(), "{:?}", report.steps);
}
