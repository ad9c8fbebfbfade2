//! MCAP output (issue 15): every file is read back with the `mcap` crate's reader and compared with
//! `decode --format json` of the same input. Every MCAP (and the JSON lines beside it) is left in
//! `target/tmp/mcap-check`, where CI reads them again with Foxglove's Python reader and `jsonschema`.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::util::{data, stderr, tracerctl};

/// Where every test writes its MCAP files (read again by tests/mcap/verify.py in CI).
const CHECK_DIR: &str = concat!(env!("CARGO_TARGET_TMPDIR"), "/mcap-check");

fn check_path(name: &str, extension: &str) -> PathBuf {
    std::fs::create_dir_all(CHECK_DIR).unwrap();
    Path::new(CHECK_DIR).join(format!("{name}.{extension}"))
}

/// A made-up input log, kept apart from the files CI checks.
fn input_path(name: &str) -> PathBuf {
    let dir = concat!(env!("CARGO_TARGET_TMPDIR"), "/mcap-inputs");
    std::fs::create_dir_all(dir).unwrap();
    Path::new(dir).join(format!("{name}.log"))
}

/// An MCAP file as read back.
#[derive(Debug, Default)]
struct Read {
    profile: String,
    library: String,
    /// topic -> (schema name, schema encoding, message encoding)
    channels: BTreeMap<String, (String, String, String)>,
    /// (topic, log time, message)
    messages: Vec<(String, u64, Value)>,
    metadata: BTreeMap<String, BTreeMap<String, String>>,
    compressions: Vec<String>,
}

impl Read {
    fn count(&self, topic: &str) -> usize {
        self.messages.iter().filter(|(t, _, _)| t == topic).count()
    }

    fn on(&self, topic: &str) -> Vec<&Value> {
        self.messages.iter().filter(|(t, _, _)| t == topic).map(|(_, _, m)| m).collect()
    }
}

fn read_mcap(path: &Path) -> Read {
    let bytes = std::fs::read(path).unwrap();
    let mut read = Read::default();
    for record in mcap::read::LinearReader::new(&bytes).unwrap() {
        if let mcap::records::Record::Header(header) = record.unwrap() {
            read.profile = header.profile;
            read.library = header.library;
            break;
        }
    }
    let summary = mcap::Summary::read(&bytes).unwrap().expect("a summary section");
    for channel in summary.channels.values() {
        let schema = channel.schema.as_ref().expect("every channel has a schema");
        let parsed: Value = serde_json::from_slice(&schema.data).expect("the schema is JSON");
        assert_eq!(parsed["type"], "object", "{}", schema.name);
        read.channels.insert(
            channel.topic.clone(),
            (schema.name.clone(), schema.encoding.clone(), channel.message_encoding.clone()),
        );
    }
    for index in &summary.metadata_indexes {
        let metadata = mcap::read::metadata(&bytes, index).unwrap();
        read.metadata.insert(metadata.name, metadata.metadata);
    }
    read.compressions = summary.chunk_indexes.iter().map(|chunk| chunk.compression.clone()).collect();
    for message in mcap::MessageStream::new(&bytes).unwrap() {
        let message = message.unwrap();
        let value: Value = serde_json::from_slice(&message.data).expect("every message is JSON");
        assert_eq!(message.log_time, message.publish_time);
        read.messages.push((message.channel.topic.clone(), message.log_time, value));
    }
    read
}

/// `decode -o NAME.mcap ARGS` and `decode --format json ARGS > NAME.jsonl`; both read back.
fn decode_both(name: &str, args: &[&str]) -> (Read, Vec<Value>) {
    let mcap = check_path(name, "mcap");
    let output = tracerctl().arg("decode").args(args).arg("-o").arg(&mcap).output().unwrap();
    assert!(output.status.success(), "{name}: {}", stderr(&output));
    let jsonl = check_path(name, "jsonl");
    let output =
        tracerctl().args(["decode", "--format", "json"]).args(args).arg("-o").arg(&jsonl).output().unwrap();
    assert!(output.status.success(), "{name}: {}", stderr(&output));
    let lines: Vec<Value> = std::fs::read_to_string(&jsonl)
        .unwrap()
        .lines()
        .map(|line| serde_json::from_str(line).unwrap())
        .collect();
    (read_mcap(&mcap), lines)
}

/// The topic a JSON line's frame goes to (besides /tracer/raw), as docs/foxglove.md says.
fn topic_of(line: &Value) -> Option<String> {
    let msg = line["msg"].as_str().unwrap();
    match msg {
        "raw" | "invalid" | "error_frame" | "remote_request" => None,
        "motor_high_speed" => Some(format!("/tracer/motor/{}", line["fields"]["motor"])),
        "motor_low_speed" => Some(format!("/tracer/motor/{}/low_speed", line["fields"]["motor"])),
        _ => Some(format!("/tracer/{msg}")),
    }
}

/// What every file must satisfy against decode's JSON of the same input.
fn check_against_json(read: &Read, lines: &[Value], command: &str) {
    assert_eq!(read.profile, "");
    assert_eq!(read.library, format!("tracerctl {}", env!("CARGO_PKG_VERSION")));
    for topic in ["/tracer/system_state", "/tracer/motor/1", "/tracer/motor/2/low_speed", "/tracer/odometry"]
    {
        let (schema, encoding, message_encoding) = &read.channels[topic];
        assert!(schema.starts_with("tracer."), "{topic}: {schema}");
        assert_eq!((encoding.as_str(), message_encoding.as_str()), ("jsonschema", "json"));
    }
    assert_eq!(read.channels["/tracer/raw"].0, "tracer.raw");
    assert_eq!(read.channels["/tracer/events"].0, "foxglove.Log");
    assert_eq!(read.channels["/tracer/pose"].0, "foxglove.PoseInFrame");
    assert_eq!(read.channels["/tf"].0, "foxglove.FrameTransform");

    // Every frame on /tracer/raw, in order, with decode's header values.
    let raw = read.on("/tracer/raw");
    assert_eq!(raw.len(), lines.len(), "one raw message per JSON line");
    for (message, line) in raw.iter().zip(lines) {
        for key in ["ts_ns", "iface", "id", "data", "dir", "msg", "wire"] {
            assert_eq!(message[key], line[key], "{key} of {line}");
        }
    }
    // Per message channel: the same count, and the fields at top level.
    let mut expected: BTreeMap<String, Vec<&Value>> = BTreeMap::new();
    for line in lines {
        if let Some(topic) = topic_of(line) {
            expected.entry(topic).or_default().push(line);
        }
    }
    for (topic, want) in &expected {
        let got = read.on(topic);
        assert_eq!(got.len(), want.len(), "{topic}");
        for (message, line) in got.iter().zip(want) {
            for (key, value) in line["fields"].as_object().unwrap() {
                assert_eq!(&message[key], value, "{topic}.{key}");
            }
            assert_eq!(message["iface"], line["iface"]);
            assert_eq!(message["wire"], line["wire"]);
        }
    }
    let message_topics = read.messages.iter().filter(|(topic, _, _)| topic.starts_with("/tracer/"));
    let on_message_channels = message_topics
        .filter(|(topic, _, _)| !["/tracer/raw", "/tracer/events", "/tracer/pose"].contains(&topic.as_str()))
        .count();
    assert_eq!(on_message_channels, expected.values().map(Vec::len).sum::<usize>());
    // Log time never decreases, and is the stamp where there is one.
    let times: Vec<u64> = read.messages.iter().map(|(_, time, _)| *time).collect();
    assert!(times.windows(2).all(|pair| pair[0] <= pair[1]), "log times decrease");
    let raw_times = read.messages.iter().filter(|(topic, _, _)| topic == "/tracer/raw");
    let mut previous = 0;
    for (_, time, message) in raw_times {
        let expected = message["ts_ns"].as_u64().map_or(previous, |stamp| stamp.max(previous));
        assert_eq!(*time, expected);
        previous = *time;
    }
    // One pose and one transform per odometry frame.
    assert_eq!(read.count("/tracer/pose"), read.count("/tracer/odometry"));
    assert_eq!(read.count("/tf"), read.count("/tracer/odometry"));
    let metadata = &read.metadata["tracerctl"];
    assert_eq!(metadata["version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(metadata["command"], command);
    let sources: Vec<String> = serde_json::from_str(&metadata["sources"]).expect("sources: a JSON list");
    assert!(!sources.is_empty());
}

#[test]
fn a_session_log_has_every_frame_on_raw_and_each_message_on_its_channel() {
    let log = data("tracer_session.log");
    let (read, lines) = decode_both("session", &[log.to_str().unwrap()]);
    check_against_json(&read, &lines, "decode");
    assert!(read.count("/tracer/system_state") > 0);
    assert_eq!(read.metadata["tracerctl"]["protocol"], "can-v2");
    let sources: Vec<String> = serde_json::from_str(&read.metadata["tracerctl"]["sources"]).unwrap();
    assert_eq!(sources, [log.to_str().unwrap()]);
    let battery = &read.on("/tracer/system_state")[0]["battery_voltage"];
    assert!(battery.is_number(), "a plot path: /tracer/system_state.battery_voltage = {battery}");
}

#[test]
fn every_fixture_kind_round_trips() {
    let fixtures = [
        ("every_kind", "decode/every_kind.log"),
        ("bad_lines", "candump/bad_lines.log"),
        ("console_errorframe", "candump/console_errorframe.txt"),
        ("console_x", "candump/console_x.txt"),
        ("log_fd_error_eff", "candump/log_fd_error_eff.log"),
        ("console_plain", "candump/console_plain.txt"),
        ("mixed", "candump/mixed.log"),
        ("vector_asc", "formats/vector.asc"),
        ("monitor_gap", "monitor_gap.log"),
    ];
    for (name, fixture) in fixtures {
        let path = data(fixture);
        let (read, lines) = decode_both(name, &[path.to_str().unwrap()]);
        check_against_json(&read, &lines, "decode");
    }
}

#[test]
fn invalid_and_error_frames_are_logged_as_events() {
    let path = data("candump/log_fd_error_eff.log");
    let (read, lines) = decode_both("errors_as_events", &[path.to_str().unwrap()]);
    let error_frames = lines.iter().filter(|line| line["msg"] == "error_frame").count();
    assert!(error_frames > 0);
    let events = read.on("/tracer/events");
    let logged: Vec<&&Value> = events
        .iter()
        .filter(|event| event["message"].as_str().unwrap().starts_with("CAN error frame"))
        .collect();
    assert_eq!(logged.len(), error_frames);
    assert!(logged.iter().all(|event| event["level"] == 4 && event["name"] == "tracerctl"));
    let invalid = lines.iter().filter(|line| line["msg"] == "invalid").count();
    let rejected =
        events.iter().filter(|event| event["message"].as_str().unwrap().starts_with("invalid frame"));
    assert_eq!(rejected.count(), invalid);
}

#[test]
fn a_serial_capture_and_a_v1_log_round_trip() {
    let capture = data("decode/serial_xxd.txt");
    let (read, lines) = decode_both("serial_capture", &["--serial", capture.to_str().unwrap()]);
    check_against_json(&read, &lines, "decode");
    assert!(lines.iter().all(|line| line["wire"] == "serial"));
    assert_eq!(read.metadata["tracerctl"]["protocol"], "serial");

    let v1 = input_path("v1_input");
    std::fs::write(
        &v1,
        "(1700000000.000000) can0 151#00010103004009A8\n(1700000000.010000) can0 130#0107F61400000651\n\
         (1700000000.020000) can0 140#0103320000000281\n(1700000000.030000) can0 151#00010103004009A8\n",
    )
    .unwrap();
    let (read, lines) = decode_both("v1_log", &[v1.to_str().unwrap()]);
    check_against_json(&read, &lines, "decode");
    assert_eq!(read.metadata["tracerctl"]["protocol"], "can-v1");
    assert_eq!(read.on("/tracer/motion_command")[0]["fault_clear"], "driver_overheat");
}

#[test]
fn frames_without_stamps_take_the_previous_log_time() {
    let path = input_path("unstamped_input");
    std::fs::write(
        &path,
        "211#0001010300000000\n(1700000000.500000) can0 211#0001010300000001\n221#0000000000000000\n\
         (1700000000.400000) can0 221#0000000000000000\n",
    )
    .unwrap();
    let (read, lines) = decode_both("unstamped", &[path.to_str().unwrap()]);
    check_against_json(&read, &lines, "decode");
    let raw: Vec<u64> = read
        .messages
        .iter()
        .filter(|(topic, _, _)| topic == "/tracer/raw")
        .map(|(_, time, _)| *time)
        .collect();
    let stamp = 1_700_000_000_500_000_000;
    assert_eq!(raw, [0, stamp, stamp, stamp], "an earlier stamp does not move log time back");
    assert_eq!(read.on("/tracer/raw")[3]["ts_ns"], 1_700_000_000_400_000_000u64, "ts_ns stays as captured");
}

#[test]
fn a_straight_drive_ends_at_the_distance_driven_and_faults_are_logged_when_set_and_cleared() {
    let path = input_path("drive_input");
    let mut log = String::new();
    for step in 0..=20u32 {
        let mm = step * 50;
        log.push_str(&format!("(1700000000.{:06}) can0 311#{mm:08X}{mm:08X}\n", step * 20_000));
    }
    log.push_str("(1700000001.000000) can0 211#0001010300000000\n");
    log.push_str("(1700000001.020000) can0 211#0101010301000001\n");
    log.push_str("(1700000001.040000) can0 211#0101010301000002\n");
    log.push_str("(1700000001.060000) can0 211#0001010300000003\n");
    std::fs::write(&path, log).unwrap();
    let (read, lines) = decode_both("drive_and_fault", &[path.to_str().unwrap()]);
    check_against_json(&read, &lines, "decode");

    let poses = read.on("/tracer/pose");
    assert_eq!(poses.len(), 21);
    let last = poses[20];
    assert_eq!(last["frame_id"], "odom");
    assert!((last["pose"]["position"]["x"].as_f64().unwrap() - 1.0).abs() < 1e-9, "{last}");
    assert_eq!(last["pose"]["position"]["y"].as_f64(), Some(0.0));
    assert_eq!(last["pose"]["orientation"]["w"].as_f64(), Some(1.0));
    assert_eq!(last["timestamp"], serde_json::json!({"sec": 1_700_000_000u64, "nsec": 400_000_000}));
    let tf = read.on("/tf")[20];
    assert_eq!((&tf["parent_frame_id"], &tf["child_frame_id"]), (&"odom".into(), &"base_link".into()));
    assert_eq!(tf["translation"], last["pose"]["position"]);

    let events: Vec<(u64, String)> = read
        .on("/tracer/events")
        .iter()
        .map(|event| (event["level"].as_u64().unwrap(), event["message"].as_str().unwrap().to_string()))
        .collect();
    let texts: Vec<&str> = events.iter().map(|(_, text)| text.as_str()).collect();
    assert_eq!(texts[0], "control mode can (first status)");
    assert_eq!(texts[1], "vehicle state normal (first status)");
    assert_eq!(texts[2], "vehicle state normal -> estop: E-stop on");
    assert!(texts[3].starts_with("fault set: battery_"), "{texts:?}");
    assert_eq!(texts[4], "vehicle state estop -> normal: E-stop off");
    assert!(texts[5].starts_with("fault cleared: battery_"), "{texts:?}");
    assert_eq!(texts.len(), 6, "{texts:?}");
    assert_eq!(events[2].0, 4, "E-stop on is an error");
    assert_eq!(events[5].0, 2, "a clear is info");
}

#[test]
fn mcap_output_is_refused_on_standard_output_and_with_a_report() {
    let log = data("tracer_session.log");
    let log = log.to_str().unwrap();
    for args in [
        vec!["decode", "--format", "mcap", log],
        vec!["decode", "--format", "mcap", "-o", "-", log],
        vec!["decode", "--summary", "-o", "x.mcap", log],
        vec!["decode", "--format", "mcap", "--plot", "x.svg", "-o", "x.mcap", log],
    ] {
        let output = tracerctl().args(&args).output().unwrap();
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        assert!(stderr(&output).contains("--format mcap"), "{args:?}: {}", stderr(&output));
    }
}

#[test]
fn every_compression_is_readable_and_says_which_it_is() {
    let log = data("tracer_session.log");
    for (method, expected) in [("zstd", "zstd"), ("lz4", "lz4"), ("none", "")] {
        let name = format!("compression_{method}");
        let (read, lines) = decode_both(&name, &["--mcap-compression", method, log.to_str().unwrap()]);
        check_against_json(&read, &lines, "decode");
        assert!(!read.compressions.is_empty());
        assert!(read.compressions.iter().all(|compression| compression == expected), "{method}");
    }
}

#[test]
fn an_explicit_format_writes_that_format_to_the_file() {
    let log = data("tracer_session.log");
    let path = check_path("not_mcap", "txt");
    let output =
        tracerctl().args(["decode", "--format", "json", "-o"]).arg(&path).arg(&log).output().unwrap();
    assert!(output.status.success());
    assert!(output.stdout.is_empty());
    let written = std::fs::read_to_string(&path).unwrap();
    assert_eq!(written.lines().count(), crate::util::decode_json(&[log.to_str().unwrap()]).len());
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn a_write_error_names_the_file_and_fails() {
    if !Path::new("/dev/full").exists() {
        return;
    }
    let log = data("tracer_session.log");
    let output =
        tracerctl().args(["decode", "--format", "mcap", "-o", "/dev/full"]).arg(&log).output().unwrap();
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr(&output).contains("cannot write /dev/full"), "{}", stderr(&output));
}

/// `tracerctl --sim --fault estop@1s monitor --format json --log NAME.mcap`: the MCAP holds every frame
/// monitor printed, with the same stamps, and logs the injected E-stop. (monitor.rs's
/// `the_log_file_holds_every_frame_printed_and_decode_reads_it` shows the same of a candump --log, so a
/// candump log and an MCAP of one session hold the same frames.)
#[test]
fn a_sim_session_recorded_as_mcap_holds_every_frame_monitor_printed() {
    let mcap = check_path("sim_monitor", "mcap");
    let output = tracerctl()
        .args(["--sim", "--fault", "estop@1s", "monitor", "--format", "json", "--duration", "2s", "--log"])
        .arg(&mcap)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    std::fs::write(check_path("sim_monitor", "jsonl"), &output.stdout).unwrap();
    let printed = crate::util::json_lines(&output);
    assert!(printed.len() > 200);
    let read = read_mcap(&mcap);
    check_against_json(&read, &printed, "monitor");
    assert_eq!(read.metadata["tracerctl"]["protocol"], "can-v2");
    assert_eq!(read.metadata["tracerctl"]["sources"], "[\"sim\"]");
    let events: Vec<&str> =
        read.on("/tracer/events").iter().map(|event| event["message"].as_str().unwrap()).collect();
    assert!(events.contains(&"vehicle state normal -> estop: E-stop on"), "{events:?}");
}

/// A recording killed outright (SIGKILL) has no summary, but everything up to its last flushed chunk
/// (at most a second old) reads back.
#[test]
fn a_recording_killed_with_sigkill_reads_back_up_to_its_last_flushed_chunk() {
    // `.killed`: CI's check streams it as far as it goes instead of asking for a summary.
    let path = check_path("sim_sigkill.killed", "mcap");
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
        .args(["--sim", "monitor", "--format", "json", "--log"])
        .arg(&path)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(2500));
    child.kill().unwrap(); // SIGKILL
    let output = child.wait_with_output().unwrap();
    let printed = String::from_utf8_lossy(&output.stdout).lines().count();
    let bytes = std::fs::read(&path).unwrap();
    assert!(mcap::Summary::read(&bytes).is_err() || mcap::Summary::read(&bytes).unwrap().is_none());
    let options = mcap::read::Options::IgnoreEndMagic.into();
    let mut raw = 0;
    for message in mcap::MessageStream::new_with_options(&bytes, options).unwrap() {
        match message {
            Ok(message) if message.channel.topic == "/tracer/raw" => raw += 1,
            Ok(_) => {}
            Err(_) => break, // the chunk being written when it was killed
        }
    }
    // The simulator sends about 640 frames a second; two chunks were flushed by 2 s.
    assert!(raw >= 640, "{raw} frames readable ({printed} printed before the kill)");
    eprintln!("killed after 2.5 s: {raw} frames readable, {printed} printed");
}

/// SIGTERM (and so SIGINT, SIGHUP) ends a live recording normally: the file is finished, with its summary
/// and metadata.
#[test]
fn a_recording_ended_by_sigterm_is_finished() {
    let path = check_path("sim_sigterm", "mcap");
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
        .args(["--sim", "monitor", "--format", "json", "--log"])
        .arg(&path)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1500));
    // SAFETY: kill only sends a signal to a process id; no memory is touched.
    unsafe { libc::kill(child.id() as i32, libc::SIGTERM) };
    assert_eq!(child.wait().unwrap().code(), Some(143));
    let read = read_mcap(&path);
    assert_eq!(read.metadata["tracerctl"]["command"], "monitor");
    assert!(read.count("/tracer/raw") > 300, "{}", read.count("/tracer/raw"));
    assert_eq!(read.count("/tracer/pose"), read.count("/tracer/odometry"));
}

/// An input error ends decode, and the MCAP is still finished: after decoded frames, and also when the first
/// input already failed (an empty, finished file with its channels and metadata).
#[test]
fn an_input_error_still_finishes_the_file() {
    let log = data("tracer_session.log");
    let path = check_path("input_error", "mcap");
    let output =
        tracerctl().args(["decode", "-o"]).arg(&path).arg(&log).arg("no-such-file.log").output().unwrap();
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr(&output).contains("no-such-file.log: no such file"), "{}", stderr(&output));
    let read = read_mcap(&path);
    let lines = crate::util::decode_json(&[log.to_str().unwrap()]);
    assert_eq!(read.count("/tracer/raw"), lines.len());
    let jsonl: String = lines.iter().map(|line| format!("{line}\n")).collect();
    std::fs::write(check_path("input_error", "jsonl"), jsonl).unwrap();

    let path = check_path("input_error_first", "mcap");
    std::fs::write(check_path("input_error_first", "jsonl"), "").unwrap();
    let output = tracerctl().args(["decode", "-o"]).arg(&path).arg("no-such-file.log").output().unwrap();
    assert_eq!(output.status.code(), Some(1));
    let read = read_mcap(&path);
    assert_eq!(read.messages.len(), 0);
    assert_eq!(read.metadata["tracerctl"]["protocol"], "unknown");
    assert!(read.channels.contains_key("/tracer/system_state"));
}

/// `tracerctl --sim --fault battery-warning@1s dashboard --record x.mcap` in tmux, armed, Up held for two
/// seconds, then q: the file is finished with `command` dashboard, holds the motion commands sent and the
/// warning set, and the pose moved forward.
#[test]
fn a_dashboard_drive_recorded_as_mcap_holds_the_commands_the_fault_and_the_path() {
    use crate::dashboard::{arm, Session};
    use std::time::{Duration, Instant};
    let path = check_path("sim_dashboard", "mcap");
    let _ = std::fs::remove_file(&path);
    let command = format!(
        "{} --sim --fault battery-warning@1s dashboard --record {}; echo \"exit status $?\"; sleep 30",
        assert_cmd::cargo::cargo_bin("tracerctl").display(),
        path.display()
    );
    let session = Session::start(&format!("tracerctl-mcap-{}", std::process::id()), &command);
    let (up, screen) =
        session.wait_for(Duration::from_secs(10), |s| s.contains("tracerctl") && s.contains("sim"));
    assert!(up, "{screen}");
    arm(&session);
    let pressed = Instant::now();
    while pressed.elapsed() < Duration::from_millis(2000) {
        session.keys(&["Up"]);
        std::thread::sleep(Duration::from_millis(33));
    }
    std::thread::sleep(Duration::from_millis(500));
    session.keys(&["q"]);
    let (ended, screen) = session.wait_for(Duration::from_secs(10), |s| s.contains("exit status"));
    assert!(ended && screen.contains("exit status 0"), "{screen}");

    let read = read_mcap(&path);
    assert_eq!(read.metadata["tracerctl"]["command"], "dashboard");
    assert_eq!(read.metadata["tracerctl"]["protocol"], "can-v2");
    let commands = read.on("/tracer/motion_command");
    assert!(
        commands.iter().any(|command| command["linear_velocity"].as_f64() > Some(0.1)),
        "{}",
        commands.len()
    );
    let events: Vec<&str> =
        read.on("/tracer/events").iter().map(|event| event["message"].as_str().unwrap()).collect();
    assert!(events.iter().any(|event| event.starts_with("fault set: battery")), "{events:?}");
    let last = read.on("/tracer/pose").last().copied().cloned().expect("poses");
    assert!(last["pose"]["position"]["x"].as_f64().unwrap() > 0.1, "{last}");
    let raw = read.on("/tracer/raw");
    assert_eq!(raw.len(), read.messages.iter().filter(|(topic, _, _)| topic == "/tracer/raw").count());
    let times: Vec<u64> = read.messages.iter().map(|(_, time, _)| *time).collect();
    assert!(times.windows(2).all(|pair| pair[0] <= pair[1]));
}
