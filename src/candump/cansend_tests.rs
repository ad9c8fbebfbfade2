//! `parse_cansend` against every edge case of candump-formats.md §3, with the strict verdicts.

use super::{parse_cansend, FrameSyntaxError, Reason};
use crate::protocol::{CanFrame, FrameKind};

fn ok(text: &str) -> CanFrame {
    parse_cansend(text.as_bytes()).unwrap_or_else(|e| panic!("{text:?} rejected: {e}"))
}

fn err(text: &str) -> (usize, Reason) {
    match parse_cansend(text.as_bytes()) {
        Ok(frame) => panic!("{text:?} accepted as {frame}"),
        Err(FrameSyntaxError { column, reason }) => (column, reason),
    }
}

#[test]
fn table_empty_payload() {
    let frame = ok("123#");
    assert_eq!(
        (frame.id(), frame.is_extended(), frame.kind(), frame.len()),
        (0x123, false, FrameKind::Data, 0)
    );
}

#[test]
fn table_remote_requests() {
    for (text, len) in [("123#R", 0), ("123#r", 0), ("123#R5", 5), ("123#R0", 0), ("00000123#R3", 3)] {
        let frame = ok(text);
        assert_eq!(frame.kind(), FrameKind::Remote, "{text}");
        assert_eq!(frame.len(), len, "{text}");
        assert!(frame.data().is_empty());
    }
    assert!(ok("00000123#R3").is_extended());
    let frame = ok("333#R8_E");
    assert_eq!((frame.id(), frame.len(), frame.raw_dlc()), (0x333, 8, Some(0xE)));
    assert_eq!(ok("333#r8_e").raw_dlc(), Some(0xE));
}

#[test]
fn table_bad_remote_lengths_are_rejected_not_zeroed() {
    assert_eq!(err("123#R9"), (6, Reason::BadRemoteLength));
    assert_eq!(err("123#RX"), (6, Reason::BadRemoteLength));
    assert_eq!(err("123#R5_E"), (7, Reason::BadRawDlc));
    assert_eq!(err("123#R8_3"), (7, Reason::BadRawDlc));
    assert_eq!(err("123#R8_"), (7, Reason::BadRawDlc));
    assert_eq!(err("123#R8_EE"), (9, Reason::TrailingGarbage));
    assert_eq!(err("123#R55"), (7, Reason::TrailingGarbage));
}

#[test]
fn table_standard_ids_above_7ff_are_rejected() {
    assert_eq!(err("FFF#00"), (1, Reason::SffIdTooLarge));
    assert_eq!(err("800#"), (1, Reason::SffIdTooLarge));
    assert_eq!(ok("7FF#").id(), 0x7FF);
    assert_eq!(ok("7ff#").id(), 0x7FF);
}

#[test]
fn table_eight_digits_mean_extended_even_for_small_values() {
    let frame = ok("00000123#11");
    assert_eq!((frame.id(), frame.is_extended(), frame.data()), (0x123, true, &[0x11][..]));
    let frame = ok("1F334455#1122334455667788_B");
    assert_eq!(
        (frame.id(), frame.is_extended(), frame.len(), frame.raw_dlc()),
        (0x1F33_4455, true, 8, Some(0xB))
    );
}

#[test]
fn table_bit_29_makes_an_error_frame_and_bits_30_31_are_rejected() {
    let frame = ok("20000080#00");
    assert_eq!(
        (frame.kind(), frame.id(), frame.is_extended(), frame.data()),
        (FrameKind::Error, 0x80, true, &[0][..])
    );
    let frame = ok("20000004#0008000000007800");
    assert_eq!(frame.id(), 0x4);
    assert_eq!(frame.data(), &[0, 8, 0, 0, 0, 0, 0x78, 0]);
    assert_eq!(ok("20000080#").len(), 0);
    assert_eq!(err("40000123#"), (1, Reason::IdTooLarge));
    assert_eq!(err("80000123#11"), (1, Reason::IdTooLarge));
    assert_eq!(err("20000004#R"), (10, Reason::ErrorFrameNotData));
    assert_eq!(err("20000004##0"), (10, Reason::ErrorFrameNotData));
    assert_eq!(err("20000004#1122334455667788_9"), (26, Reason::BadRawDlc));
}

#[test]
fn table_only_three_or_eight_digit_ids() {
    for text in ["12#00", "0123#00", "1#", "1234567#00", "123456789#00", "12345#00", "#00"] {
        assert_eq!(err(text), (1, Reason::IdLength), "{text}");
    }
    assert_eq!(err("12G#00"), (3, Reason::NotHex));
    assert_eq!(err("123"), (4, Reason::MissingHash));
    assert_eq!(err(""), (1, Reason::EmptyFrame));
}

#[test]
fn table_ninth_byte_and_trailing_junk_are_rejected() {
    assert_eq!(err("123#112233445566778899"), (21, Reason::TooManyBytes));
    assert_eq!(err("123#1122334455667788zz"), (21, Reason::TrailingGarbage));
    assert_eq!(err("123#1122334455667788#"), (21, Reason::TrailingGarbage));
}

#[test]
fn table_raw_dlc_after_eight_bytes() {
    let frame = ok("123#1122334455667788_E");
    assert_eq!((frame.len(), frame.raw_dlc()), (8, Some(14)));
    assert_eq!(frame.data(), &[0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88]);
    assert_eq!(err("123#1122334455667788_3"), (21, Reason::BadRawDlc));
    assert_eq!(err("123#1122334455667788_8"), (21, Reason::BadRawDlc));
    assert_eq!(err("123#1122334455667788_"), (21, Reason::BadRawDlc));
    assert_eq!(err("123#1122334455667788_EF"), (23, Reason::TrailingGarbage));
    assert_eq!(err("123#11_E"), (7, Reason::BadRawDlc));
    assert_eq!(err("123#_E"), (5, Reason::BadRawDlc));
}

#[test]
fn table_dot_separators() {
    for text in ["123#11.22", "123#.11.22", "123#11.22.", "123#1122"] {
        assert_eq!(ok(text).data(), &[0x11, 0x22], "{text}");
    }
    assert_eq!(ok("123#.11").data(), &[0x11]);
    assert_eq!(ok("123#11.").data(), &[0x11]);
    assert_eq!(ok("123#.").len(), 0);
    let frame = ok("5A1#11.2233.44556677.88");
    assert_eq!(frame.id(), 0x5A1);
    assert_eq!(frame.data(), &[0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88]);
    assert_eq!(err("123#1.1"), (6, Reason::BadSeparator));
    assert_eq!(err("123#11..22"), (8, Reason::BadSeparator));
    assert_eq!(err("123#.."), (6, Reason::BadSeparator));
}

#[test]
fn table_odd_digits_and_non_hex() {
    assert_eq!(err("123#112"), (7, Reason::OddHexDigits));
    assert_eq!(err("123#1"), (5, Reason::OddHexDigits));
    assert_eq!(err("123#zz"), (5, Reason::NotHex));
    assert_eq!(err("123#1z"), (6, Reason::NotHex));
    assert_eq!(err("123#11_"), (7, Reason::BadRawDlc));
    assert_eq!(err("123#1_"), (5, Reason::OddHexDigits));
}

#[test]
fn table_whitespace_is_rejected() {
    assert_eq!(err("123#11 "), (7, Reason::UnexpectedWhitespace));
    assert_eq!(err(" 123#11"), (1, Reason::UnexpectedWhitespace));
    assert_eq!(err("123#11\r"), (7, Reason::UnexpectedWhitespace));
    assert_eq!(err("123#11\t22"), (7, Reason::UnexpectedWhitespace));
}

#[test]
fn table_can_fd() {
    assert_eq!(err("123##"), (6, Reason::BadFdFlags));
    assert_eq!(err("123##G1"), (6, Reason::BadFdFlags));
    let frame = ok("123##0");
    assert_eq!((frame.kind(), frame.len(), frame.fd_flags()), (FrameKind::Fd, 0, 0));
    let frame = ok("123##1");
    assert_eq!((frame.kind(), frame.len(), frame.fd_flags()), (FrameKind::Fd, 0, 1));
    let frame = ok("213##311223344");
    assert_eq!((frame.id(), frame.fd_flags(), frame.data()), (0x213, 3, &[0x11, 0x22, 0x33, 0x44][..]));
    let frame = ok("00000123##f.11.22");
    assert_eq!((frame.is_extended(), frame.fd_flags(), frame.data()), (true, 0xF, &[0x11, 0x22][..]));
    let twelve = format!("123##4{}", "AB".repeat(12));
    assert_eq!(ok(&twelve).len(), 12);
    let sixty_four = format!("123##5{}", "CD".repeat(64));
    assert_eq!(ok(&sixty_four).data(), &[0xCD; 64]);
    // Unlike cansend, lengths between the valid ones are not rounded up.
    assert_eq!(err(&format!("123##4{}", "00".repeat(9))), (7, Reason::BadFdLength));
    assert_eq!(err(&format!("123##4{}", "00".repeat(65))), (135, Reason::FdTooManyBytes));
    assert_eq!(err("123##40011_E"), (11, Reason::BadRawDlc));
}

#[test]
fn usage_examples_from_cansend() {
    assert_eq!(ok("123#DEADBEEF").data(), &[0xDE, 0xAD, 0xBE, 0xEF]);
    assert_eq!(ok("5AA#").id(), 0x5AA);
    assert_eq!(ok("123#deadbeef").data(), &[0xDE, 0xAD, 0xBE, 0xEF]);
    assert_eq!(ok("211#00000103000000B1").data(), &[0, 0, 1, 3, 0, 0, 0, 0xB1]);
}

#[test]
fn can_xl_is_recognised_but_not_returned() {
    assert_eq!(err("45123#81:00:12345678#112233"), (1, Reason::XlUnsupported));
    assert_eq!(err("45123#81:00:1234567#11"), (20, Reason::BadXlFrame));
}
