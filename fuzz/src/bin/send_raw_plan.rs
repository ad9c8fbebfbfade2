//! afl target: the check is `tracerctl::fuzzing::send_raw_plan` (also run on the seeds by `cargo test`).
fn main() {
    afl::fuzz!(|data: &[u8]| tracerctl::fuzzing::send_raw_plan(data));
}
