//! The real binary on one fixture per candump variant (tests/data/candump/README.md gives the counts).

use serde_json::{json, Value};

use crate::util::{data, json_lines, stderr, stdout, tracerctl};

fn decode(file: &str, extra: &[&str]) -> (Vec<Value>, String) {
    let path = data("candump").join(file);
    let output = tracerctl().args(["decode", "--format", "json"]).args(extra).arg(&path).output().unwrap();
    assert!(output.status.success(), "{file}: {}", stderr(&output));
    (json_lines(&output), stderr(&output))
}

#[test]
fn every_variant_decodes_every_frame_without_rejections() {
    let expected = [
        ("log_basic.log", 10),
        ("log_padded_dir.log", 6),
        ("log_ns_relative.log", 8),
        ("log_rtr_dlc_dots.log", 10),
        ("log_fd_error_eff.log", 12),
        ("log_dropcount_comments.log", 3),
        ("console_plain.txt", 8),
        ("console_rtr_fd_dlc.txt", 8),
        ("console_ta.txt", 4),
        ("console_tA.txt", 3),
        ("console_td.txt", 5),
        ("console_tz.txt", 5),
        ("console_x.txt", 7),
        ("console_color.txt", 5),
        ("console_eff_indent.txt", 6),
        ("console_ascii.txt", 6),
        ("console_errorframe.txt", 4),
        ("mixed.log", 20),
    ];
    for (file, frames) in expected {
        let (objects, errors) = decode(file, &[]);
        assert_eq!(objects.len(), frames, "{file}");
        assert!(!errors.contains("rejected"), "{file}: {errors}");
    }
}

fn first_with_id<'a>(objects: &'a [Value], id: &str) -> &'a Value {
    objects.iter().find(|o| o["id"] == id).unwrap_or_else(|| panic!("no {id}"))
}

#[test]
fn padded_interfaces_directions_and_nanoseconds() {
    let (objects, _) = decode("log_padded_dir.log", &[]);
    assert!(objects.iter().any(|o| o["iface"] == "vcan10"));
    assert!(objects.iter().all(|o| o["iface"] == "can0" || o["iface"] == "vcan10"));
    assert_eq!(objects[0]["dir"], "rx");
    assert!(objects.iter().any(|o| o["dir"] == "tx"));
    assert_eq!(objects.last().unwrap()["dir"], Value::Null);
    let (objects, _) = decode("log_ns_relative.log", &[]);
    let stamps: Vec<String> = objects.iter().map(|o| o["ts"].to_string()).collect();
    assert!(stamps.iter().any(|s| s.len() - s.find('.').unwrap() - 1 == 9), "a 9-digit stamp: {stamps:?}");
    assert!(stamps.contains(&"0.020113".to_string()), "{stamps:?}");
}

#[test]
fn console_variants_carry_the_same_values_as_the_log_format() {
    for file in
        ["console_plain.txt", "console_ta.txt", "console_color.txt", "console_x.txt", "console_ascii.txt"]
    {
        let (objects, _) = decode(file, &[]);
        let status = first_with_id(&objects, "0x211");
        assert_eq!(status["fields"]["battery_voltage"], 25.9, "{file}");
        assert_eq!(status["fields"]["count"], 0xB1, "{file}");
    }
    let (objects, _) = decode("console_tA.txt", &[]);
    assert_eq!(objects[0]["ts"], json!(1700000000.0), "-t A read as UTC");
    let (objects, _) = decode("console_td.txt", &["--delta-stamps"]);
    let stamps: Vec<f64> = objects.iter().map(|o| o["ts"].as_f64().unwrap()).collect();
    assert_eq!(stamps, [0.0, 0.00025, 0.0005, 0.02, 1.02]);
    let (objects, _) = decode("console_eff_indent.txt", &[]);
    assert!(objects.iter().any(|o| o["id"].as_str().unwrap().len() == 10), "an extended id");
    assert!(objects.iter().filter(|o| o["msg"] != "raw").count() >= 2, "indented standard ids still decode");
}

#[test]
fn error_frames_remote_requests_and_fd_frames() {
    let (objects, _) = decode("console_errorframe.txt", &[]);
    let errors: Vec<&Value> = objects.iter().filter(|o| o["msg"] == "error_frame").collect();
    assert_eq!(errors.len(), 3);
    assert_eq!(
        errors[0]["fields"],
        json!({"classes": ["controller_problem"], "controller": ["tx_warning"],
                                           "tx_errors": 120, "rx_errors": 0})
    );
    assert!(errors.iter().any(|e| e["fields"]["classes"].as_array().unwrap().contains(&json!("bus_off"))));
    let (objects, errors) = decode("log_fd_error_eff.log", &[]);
    assert!(objects.iter().any(|o| o["msg"] == "error_frame" && o["id"] == "0x20000080"));
    assert!(objects.iter().any(|o| o["id"] == "0x00000123" && o["msg"] == "raw"));
    // An empty 0x211 is a TRACER ID with invalid content: shown, counted, and reported.
    let empty = objects.iter().find(|o| o["id"] == "0x211" && o["data"] == "").unwrap();
    assert_eq!(empty["msg"], "invalid");
    assert!(errors.contains("invalid frames"), "{errors}");
    let (objects, _) = decode("log_rtr_dlc_dots.log", &[]);
    assert!(objects.iter().any(|o| o["msg"] == "remote_request" && o["fields"]["len"] == 8));
}

#[test]
fn dropcount_lines_are_reported_not_lost() {
    let (_, errors) = decode("log_dropcount_comments.log", &[]);
    assert!(errors.contains("candump reported 4 dropped frames"), "{errors}");
    let output =
        tracerctl().args(["decode", "--summary"]).arg(data("candump").join("mixed.log")).output().unwrap();
    let report = stdout(&output);
    assert!(report.contains("frames dropped by the socket"), "{report}");
    assert!(report.contains("error-frame text"), "{report}");
}

#[test]
fn bad_lines_are_each_reported_with_their_line_number() {
    let path = data("candump").join("bad_lines.log");
    let output = tracerctl().args(["decode", "--summary"]).arg(&path).output().unwrap();
    assert!(output.status.success());
    let report = stdout(&output);
    let rejected: u64 = report
        .split("Rejected input")
        .nth(1)
        .unwrap()
        .lines()
        .filter_map(|line| line.split_whitespace().next()?.parse::<u64>().ok())
        .sum();
    // 33 bad lines on the even lines 2..66 (line 66, 5029 bytes, has more than 8 data bytes).
    assert_eq!(rejected, 33, "{report}");
    assert!(report.contains("2  more than 8 data bytes"), "{report}");
    let errors = stderr(&output);
    assert!(errors.contains("bad_lines.log:2: column"), "{errors}");
}

#[test]
fn bare_frame_lines_in_a_file() {
    let output = tracerctl()
        .args(["decode", "-f", "json", "-"])
        .write_stdin("211#00000103000000B1\n  311#FFFFFFC100000012\r\n211#zz\n")
        .output()
        .unwrap();
    let objects = json_lines(&output);
    assert_eq!(objects.len(), 2);
    assert_eq!(objects[1]["fields"]["right_wheel_odometer"], 0.018);
    assert!(stderr(&output).contains("<stdin>:3: bare frame: column 5"), "{}", stderr(&output));
}
