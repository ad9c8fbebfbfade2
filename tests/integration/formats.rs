//! `decode` on every log a user may hand it: compressed logs, Vector ASC, PEAK trc, candump's other
//! views, a BOM, TAB-indented lines, and the formats it refuses in one line (issue 11, section 4).

use std::io::Write;

use crate::util::{data, stderr, stdout, tracerctl};

fn fixture(name: &str) -> String {
    data("formats").join(name).display().to_string()
}

/// `decode` on one input: (exit status, stdout lines, stderr).
fn decode(args: &[&str]) -> (i32, Vec<String>, String) {
    // ASC dates are local time: one zone for every run.
    let output = tracerctl().env("TZ", "UTC").arg("decode").args(args).output().unwrap();
    let lines = stdout(&output).lines().map(str::to_owned).collect();
    (output.status.code().unwrap_or(-1), lines, stderr(&output))
}

const SESSION: &str = "(1700000000.000000) can0 211#00000103000000B1\n(1700000000.020000) can0 421#01\n";
const FIRST: &str = "1700000000.000000 can0 0x211 system_state vehicle_state=normal control_mode=standby \
                     battery_voltage=25.9V fault_code=0x0000 faults=none count=177";
const SECOND: &str = "1700000000.020000 can0 0x421 control_mode_command control_mode=can";

fn compressed(tool: &str, data: &[u8]) -> Vec<u8> {
    match tool {
        "gz" => {
            let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
            encoder.write_all(data).unwrap();
            encoder.finish().unwrap()
        }
        "zst" => zstd::encode_all(data, 3).unwrap(),
        "xz" => {
            let mut encoder = liblzma::write::XzEncoder::new(Vec::new(), 6);
            encoder.write_all(data).unwrap();
            encoder.finish().unwrap()
        }
        _ => {
            let mut encoder = bzip2::write::BzEncoder::new(Vec::new(), bzip2::Compression::default());
            encoder.write_all(data).unwrap();
            encoder.finish().unwrap()
        }
    }
}

#[test]
fn compressed_logs_decode_from_files_and_standard_input() {
    let dir = tempfile::tempdir().unwrap();
    for tool in ["gz", "zst", "xz", "bz2"] {
        let bytes = compressed(tool, SESSION.as_bytes());
        // A misleading name: the bytes decide.
        let path = dir.path().join(format!("capture-{tool}.log"));
        std::fs::write(&path, &bytes).unwrap();
        let (code, lines, errors) = decode(&[path.to_str().unwrap()]);
        assert_eq!((code, errors.as_str()), (0, ""), "{tool}");
        assert_eq!(lines, [FIRST, SECOND], "{tool}");

        let output = tracerctl().args(["decode", "-"]).write_stdin(bytes).output().unwrap();
        assert!(output.status.success(), "{tool}: {}", stderr(&output));
        assert_eq!(stdout(&output).lines().collect::<Vec<_>>(), [FIRST, SECOND], "{tool} on stdin");
    }
}

#[test]
fn a_truncated_gzip_log_is_an_error_naming_the_file_and_the_compression() {
    let dir = tempfile::tempdir().unwrap();
    let big: String = SESSION.repeat(5000);
    let whole = compressed("gz", big.as_bytes());
    let path = dir.path().join("cut.log.gz");
    std::fs::write(&path, &whole[..whole.len() / 2]).unwrap();
    let (code, lines, errors) = decode(&[path.to_str().unwrap()]);
    assert_ne!(code, 0);
    let name = path.display().to_string();
    assert!(errors.contains(&format!("{name}: the gzip data ends early, at byte ")), "{errors}");
    // What was decoded before the damage was real data (whether it is all written out is decode's
    // buffering, not this reader's).
    assert!(lines.iter().all(|line| line == FIRST || line == SECOND));
}

#[test]
fn vector_asc_frames_are_decoded_and_its_other_lines_counted() {
    let (code, lines, errors) = decode(&[&fixture("vector.asc")]);
    assert_eq!((code, errors.as_str()), (0, ""));
    // The date line (10:00 local, UTC here) puts the stamps on the clock; the ErrorFrame is an error frame.
    assert_eq!(lines.len(), 8, "{lines:#?}");
    assert_eq!(
        lines[0],
        "1795514400.020000 can1 0x211 system_state vehicle_state=normal control_mode=standby battery_voltage=25.9V \
         fault_code=0x0000 faults=none count=177 dir=rx"
    );
    assert_eq!(lines[2], "1795514400.050000 can2 0x18FF0001 raw len=2 data=0102 dir=rx");
    assert_eq!(lines[3], "1795514400.060000 can1 0x7FF remote_request len=0 dir=tx");
    assert_eq!(
        lines[5],
        "1795514400.080000 can1 0x20000080 error_frame classes=bus_error data=0000000000000000"
    );
    assert_eq!(
        lines[7],
        "1795514400.100000 can3 0x12345678 raw fd_flags=7 len=12 data=00112233445566778899AABB dir=tx"
    );

    let output =
        tracerctl().args(["decode", "--summary", "-f", "json", &fixture("vector.asc")]).output().unwrap();
    assert!(output.status.success());
    let summary: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!((summary["frames"].as_u64(), summary["lines"].as_u64()), (Some(8), Some(17)));
}

#[test]
fn peak_trc_files_of_every_version_are_decoded() {
    let system_state = "0x211 system_state vehicle_state=normal control_mode=standby battery_voltage=25.9V \
                        fault_code=0x0000 faults=none count=177";
    for (name, frames, first) in [
        ("peak_v10.trc", 2, format!("0.020000 can1 {system_state}")),
        // `;$STARTTIME=46350.4166666667`: 10:00:00.000003 UTC, as python-can reads it.
        ("peak_v11.trc", 4, format!("1795514400.020503 can1 {system_state} dir=rx")),
        ("peak_v13.trc", 2, format!("1795514400.020503 can1 {system_state} dir=rx")),
        ("peak_v20.trc", 2, format!("1795514400.020503 can1 {system_state} dir=rx")),
        ("peak_v21.trc", 4, format!("1795514400.020503 can1 {system_state} dir=rx")),
    ] {
        let (code, lines, errors) = decode(&[&fixture(name)]);
        assert_eq!((code, errors.as_str()), (0, ""), "{name}");
        assert_eq!(lines.len(), frames, "{name}: {lines:#?}");
        assert_eq!(lines[0], first, "{name}");
    }
    let (_, lines, _) = decode(&[&fixture("peak_v21.trc")]);
    assert_eq!(
        lines[1],
        "1795514400.040003 can2 0x111 motion_command linear_velocity=0.15m/s angular_velocity=0rad/s dir=tx"
    );
    assert_eq!(
        lines[3],
        "1795514400.070003 can1 0x12345678 raw fd_flags=7 len=12 data=00112233445566778899AABB dir=rx"
    );
}

#[test]
fn candump_swapped_binary_and_pengutronix_outputs_are_decoded() {
    let (code, lines, errors) = decode(&[&fixture("candump_swapped.log")]);
    assert_eq!((code, errors.as_str(), lines.len()), (0, "", 5), "{lines:#?}");
    assert!(lines[0].starts_with("- can0 0x211 system_state vehicle_state=normal"), "{}", lines[0]);
    assert_eq!(lines[3], "- can0 0x18FF0001 raw len=2 data=0102");

    let (code, lines, errors) = decode(&[&fixture("candump_binary.log")]);
    assert_eq!((code, errors.as_str(), lines.len()), (0, "", 3), "{lines:#?}");
    assert!(lines[0].starts_with("- can0 0x211 system_state vehicle_state=normal"), "{}", lines[0]);
    assert_eq!(lines[1], "- can0 0x421 control_mode_command control_mode=can");

    let (code, lines, errors) = decode(&[&fixture("pengutronix.log")]);
    assert_eq!((code, errors.as_str(), lines.len()), (0, "", 3), "{lines:#?}");
    assert!(lines[0].starts_with("- can1 0x211 system_state vehicle_state=normal"), "{}", lines[0]);
    assert_eq!(lines[1], "- can1 0x18EEFF01 raw len=2 data=05A0");
}

#[test]
fn a_utf8_bom_does_not_lose_the_first_frame() {
    let (code, lines, errors) = decode(&[&fixture("bom.log")]);
    assert_eq!((code, errors.as_str()), (0, ""));
    assert_eq!(lines, [FIRST, SECOND]);
    let bytes = std::fs::read(fixture("bom.log")).unwrap();
    let output = tracerctl().args(["decode", "-"]).write_stdin(bytes).output().unwrap();
    assert_eq!(stdout(&output).lines().collect::<Vec<_>>(), [FIRST, SECOND]);
}

#[test]
fn tab_indented_frames_are_decoded_and_stray_error_text_rejected() {
    let (code, lines, errors) = decode(&[&fixture("tab_indented.log")]);
    assert_eq!(code, 0);
    assert_eq!(lines.len(), 3, "{lines:#?}");
    assert_eq!(lines[1], FIRST);
    assert_eq!(lines[2], "- can0 0x421 control_mode_command control_mode=can");
    assert!(
        errors
            .contains("tab_indented.log:6: column 1: TAB-indented text that does not follow an error frame"),
        "{errors}"
    );
    assert!(errors.contains("decoded 3 frames from 6 lines; rejected 1"), "{errors}");

    // 100 TAB-indented frames among ordinary ones: none vanishes.
    let mut log = String::new();
    for i in 0..200 {
        let indent = if i % 2 == 0 { "\t" } else { "" };
        log.push_str(&format!("{indent}(1700000000.{i:06}) can0 421#01\n"));
    }
    let output = tracerctl().args(["decode", "-"]).write_stdin(log).output().unwrap();
    assert_eq!((stdout(&output).lines().count(), stderr(&output)), (200, String::new()));
}

#[test]
fn unsupported_formats_are_refused_in_one_line_with_exit_3() {
    for (name, format, advice) in [
        ("vector.blf", "a Vector BLF log", "convert it with `python -m can.logconvert"),
        ("savvycan.csv", "a SavvyCAN/GVRET CSV log", "SavvyCAN"),
        ("crtd.txt", "a CRTD log", "SavvyCAN"),
        ("busmaster.log", "a BUSMASTER log", "SavvyCAN"),
        ("microchip.log", "a Microchip CAN BUS Analyzer log", "SavvyCAN"),
        ("carbusanalyzer.trc", "a CarBusAnalyzer trace", "SavvyCAN"),
        ("yachtdevices.txt", "a Yacht Devices RAW log", "candump -L can0"),
        ("canboat.csv", "an Actisense/canboat CSV log", "candump -L can0"),
        ("truckdevil.txt", "a TruckDevil dump", "candump -L can0"),
        ("python-can.csv", "a python-can CSV log", "python -m can.logconvert"),
    ] {
        let path = fixture(name);
        for args in [vec![path.as_str()], vec!["--summary", "-f", "json", path.as_str()]] {
            let (code, lines, errors) = decode(&args);
            assert_eq!(code, 3, "{name}: {errors}");
            assert!(lines.is_empty(), "{name}: {lines:?}");
            assert_eq!(errors.lines().count(), 1, "{name}: {errors}");
            let expected = format!("tracerctl: {path} is {format}, which tracerctl does not read: ");
            assert!(errors.starts_with(&expected), "{errors}");
            assert!(errors.contains(advice), "{errors}");
        }
    }
    // On standard input too, and gzipped.
    let blf = std::fs::read(fixture("vector.blf")).unwrap();
    let output = tracerctl().args(["decode", "-"]).write_stdin(compressed("gz", &blf)).output().unwrap();
    assert_eq!(output.status.code(), Some(3));
    assert!(stderr(&output).starts_with("tracerctl: <stdin> is a Vector BLF log"), "{}", stderr(&output));
}

/// Issue 28: ASC `ErrorFrame` lines are error frames, and the `date` line and trc's `$STARTTIME` put the
/// stamps on the clock (hand-written fixtures; tests/formats/compare_python_can.py checks both against
/// python-can in CI).
#[test]
fn asc_error_frames_and_start_times_line_up_with_other_logs() {
    let (code, lines, errors) = decode(&[&fixture("day_errors.asc")]);
    assert_eq!((code, errors.as_str()), (0, ""));
    // Fri Nov 27 14:05:09.250 2026, UTC: 1795788309.25, plus 0.0125.
    assert!(lines[0].starts_with("1795788309.262500 can1 0x211 system_state"), "{lines:#?}");
    assert_eq!(
        lines[2],
        "1795788309.290000 can1 0x20000080 error_frame classes=bus_error data=0000000000000000"
    );
    assert_eq!(
        lines[4],
        "1795788309.311000 can2 0x20000080 error_frame classes=bus_error data=0000000000000000"
    );
    assert_eq!(lines.len(), 7);
    let (code, lines, errors) = decode(&[&fixture("day_start.trc")]);
    assert_eq!((code, errors.as_str()), (0, ""));
    // 46353.5868518519 days after 1899-12-30: 2026-11-27 14:05:04.000004 UTC.
    assert!(lines[0].starts_with("1795788304.012504 can1 0x211 system_state"), "{lines:#?}");
    assert_eq!(lines.len(), 5);
}
