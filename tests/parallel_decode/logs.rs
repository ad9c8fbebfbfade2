//! The logs the chunk-boundary tests decode, and how two runs are compared: shared by `decode -j`'s sweeps
//! (tests/parallel_decode/main.rs), several inputs in one run (tests/integration/parallel_inputs.rs) and the
//! stress run (tests/integration/stress.rs).

use std::process::Output;

use crate::util::{stderr, stdout};

pub(crate) fn assert_same(single: &Output, parallel: &Output, what: &str) {
    assert_eq!(stdout(parallel), stdout(single), "stdout of {what}");
    assert_eq!(stderr(parallel), stderr(single), "stderr of {what}");
    assert_eq!(parallel.status.code(), single.status.code(), "exit status of {what}");
}

/// Every awkward line kind, with chunk boundaries falling before, inside and after each: CRLF endings,
/// bad lines, an error frame's continuation text, a count-byte wrap of 0x211, DROPCOUNT, a Pengutronix
/// header, over-long lines (one a log line padded with spaces, after an error frame), blank lines, and a
/// last line without a newline.
pub(crate) fn awkward_log() -> String {
    let mut log = String::new();
    for count in 250..=262u32 {
        let count = count % 256;
        log.push_str(&format!("(1700000000.{count:06}) can0 211#00000103000000{count:02X}\n"));
        match count % 6 {
            0 => log.push_str("(1700000000.500000) can0 221#0096000000000000\r\n"),
            1 => log.push_str("this line is not candump\n\n   \n"),
            2 => log.push_str(
                " (000.000000)  can0  20000080   [8]  00 00 00 00 00 00 00 00   ERRORFRAME\n\
                 \tcontroller-problem{}\n\tbus-off\n",
            ),
            3 => {
                log.push_str("DROPCOUNT: dropped 3 CAN frames on 'can0' socket (total drops 3)\n# comment\n")
            }
            4 => log.push_str(
                "interface = can1, family = 29, type = 3, proto = 1\n<0x211> [8] 00 00 01 03 00 00 00 b1 \n",
            ),
            _ => log.push_str("(1700000000.1) can0 211#ZZ\r\n211#00000103000000B1\n\tstray text\n"),
        }
    }
    log.push_str(&"x".repeat(70_000));
    log.push('\n');
    // A log line past the line limit (spaces after its stamp) right after an error frame: rejected whole as
    // too long, never parsed, so the TAB line after it is still the error frame's text.
    log.push_str(" (000.000000)  can0  20000080   [8]  00 00 00 00 00 00 00 00   ERRORFRAME\n");
    log.push_str(&format!("(1700000000.777777){}can0 211#00000103000000B1\n", " ".repeat(70_000)));
    log.push_str("\tbus-off\n");
    log.push_str("(1700000000.999999) can0 311#0000000A00000014");
    log
}

/// A Vector ASC log whose header changes how the lines after it read halfway (`base dec`, then `base hex`
/// again), with the lines every ASC writer leaves: measurement events, statistics, error frames, remote and
/// CAN FD frames, CRLF endings, a bad line and an unknown event.
pub(crate) fn asc_log() -> String {
    let mut log = String::from(
        "date Tue Nov 24 10:00:00.000 2026\nbase hex  timestamps absolute\ninternal events logged\n\
         Begin Triggerblock Tue Nov 24 10:00:00.000 2026\n   0.000000 Start of measurement\n",
    );
    for tick in 0..300u32 {
        let at = format!("{:4}.{:06}", tick / 50, (tick % 50) * 20_000);
        match tick {
            100 => log.push_str("base dec  timestamps absolute\n"),
            200 => log.push_str("base hex  timestamps absolute\r\n"),
            _ => {}
        }
        // Identifiers and bytes as the header in force says: hex, or decimal between ticks 100 and 200.
        let decimal = (100..200).contains(&tick);
        let number = |value: u32| if decimal { value.to_string() } else { format!("{value:02X}") };
        let bytes = |data: &[u32]| data.iter().map(|&byte| number(byte)).collect::<Vec<_>>().join(" ");
        let frame =
            |id: u32, data: &[u32]| format!("{at} 1  {}  Rx   d {} {}", number(id), data.len(), bytes(data));
        log.push_str(&frame(0x211, &[0, 0, 1, 3, 0, 0, 0, (tick + 250) % 256]));
        log.push('\n');
        log.push_str(&frame(0x221, &[0, tick % 256, 0, 0, 0, 0, 0, 1]));
        log.push_str("\r\n");
        match tick % 23 {
            0 => log.push_str(&format!("{at} 1  ErrorFrame\n")),
            5 => log.push_str(&format!(
                "{at} 2  {}x  Rx   d 2 01 02\n{at} 1  {}   Tx   r 4\n",
                number(0x18FF_0001),
                number(0x7FF)
            )),
            9 => log.push_str(&format!("{at} 1  211             Rx   d 8 ZZ 00\n")),
            13 => log.push_str(&format!(
                "{at} CANFD   1 Rx        {}  1 0 9 12 {}   0    0   3000 0 0 0 0 0\n",
                number(0x251),
                bytes(&[0x00, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88, 0x99, 0xAA, 0xBB])
            )),
            17 => {
                log.push_str(&format!("{at} 1  Statistic: D 10 R 0 XD 0 XR 0 E 0 O 0 B 0.10%\n{at} Sync\n"))
            }
            _ => {}
        }
    }
    log.push_str("End TriggerBlock\n");
    log
}

/// A PEAK trc 2.1 trace whose `;$COLUMNS=` header changes the columns halfway (the reserved column left out,
/// then back), with status and error lines, events, remote and FD frames, CRLF endings and a bad line.
pub(crate) fn trc_log() -> String {
    let mut log = String::from(
        ";$FILEVERSION=2.1\n;$STARTTIME=46350.4166666667\n;$COLUMNS=N,O,T,B,I,d,R,L,D\n;\n\
         ;   Start time: 24.11.2026 10:00:00.000.0\n",
    );
    let mut number = 0;
    for tick in 0..300u32 {
        let at = format!("{:9}.{:03}", tick * 20, tick % 7);
        let count = (tick + 250) % 256;
        match tick {
            100 => log.push_str(";$COLUMNS=N,O,T,B,I,d,L,D\n"),
            200 => log.push_str(";$COLUMNS=N,O,T,B,I,d,R,L,D\r\n"),
            _ => {}
        }
        let reserved = if (100..200).contains(&tick) { "" } else { "-  " };
        let mut line = |kind: &str, id: &str, rest: &str| {
            number += 1;
            log.push_str(&format!("{number:7} {at} {kind} 1      {id} Rx {reserved}{rest}\n"));
        };
        line("DT", "0211", &format!("8    00 00 01 03 00 00 00 {count:02X}"));
        line("DT", "0221", &format!("8    00 {:02X} 00 00 00 00 00 01\r", tick % 256));
        match tick % 19 {
            0 => line("ER", "   -", "5    00 00 08 01 00"),
            4 => line("ST", "   -", "4    00 00 00 08"),
            8 => line("RR", "0123", "4"),
            11 => line("FB", "0251", "9    00 11 22 33 44 55 66 77 88 99 AA BB"),
            14 => line("DT", "0211", "8    00 ZZ"),
            16 => log.push_str(&format!("{:7} {at} EV              User event\n", number + 1)),
            _ => {}
        }
    }
    log
}

/// A session for the summary and the plot: 0x211 whose count byte wraps 0xFF -> 0x00 and then skips, a
/// 3-second gap, mode and vehicle-state changes, faults coming and going, an E-stop, motion and motor frames,
/// an invalid frame (a V1 0x151 after V1 traffic), bad lines, error frames with their text, CRLF endings.
pub(crate) fn session_log() -> String {
    let mut log = String::new();
    let mut at = 1_700_000_000_000_000u64;
    for tick in 0..400u32 {
        at += if tick == 200 { 3_000_000 } else { 20_000 };
        let stamp = format!("({}.{:06})", at / 1_000_000, at % 1_000_000);
        // Count 250 .. 255, 0, 1, ... wraps; tick 300 skips two counts.
        let count = (tick + 250 + u32::from(tick >= 300) * 2) % 256;
        let (mode, state, fault) = (u32::from(tick >= 100), u32::from(tick % 150 > 140) * 2, (tick / 50) % 3);
        log.push_str(&format!("{stamp} can0 211#{state:02X}{mode:02X}0103{fault:02X}0000{count:02X}\n"));
        log.push_str(&format!("{stamp} can0 221#{:04X}0000000000{:02X}\r\n", tick * 3, tick % 256));
        log.push_str(&format!("{stamp} can0 251#{:04X}{:04X}00000000\n", tick * 7, tick));
        match tick % 37 {
            0 => log.push_str(&format!("{stamp} can0 211#ZZ\n")),
            5 => log.push_str(
                " (000.000000)  can0  20000080   [8]  00 00 00 00 00 00 00 00   ERRORFRAME\n\
                 \tcontroller-problem{}\n\tbus-off\n",
            ),
            9 => log
                .push_str(&format!("{stamp} can1 131#0000000000000000\n{stamp} can1 151#0000000000000000\n")),
            _ => {}
        }
    }
    log
}
