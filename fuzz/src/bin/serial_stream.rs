//! afl target: the check is `tracerctl::fuzzing::serial_stream` (also run on the seeds by `cargo test`).
fn main() {
    afl::fuzz!(|data: &[u8]| tracerctl::fuzzing::serial_stream(data));
}
