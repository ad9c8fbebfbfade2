//! afl target: the check is `tracerctl::fuzzing::candump_reader` (also run on the seeds by `cargo test`).
fn main() {
    afl::fuzz!(|data: &[u8]| tracerctl::fuzzing::candump_reader(data));
}
