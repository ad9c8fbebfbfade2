//! A log of every awkward line for the chunk-boundary tests: shared by `decode -j`'s sweeps and the stress
//! run of tests/integration/stress.rs.

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
