//! afl target: the check is `tracerctl::fuzzing::can_decode` (also run on the seeds by `cargo test`).
fn main() {
    afl::fuzz!(|data: &[u8]| tracerctl::fuzzing::can_decode(data));
}
