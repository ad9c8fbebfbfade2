//! afl target: the check is `tracerctl::fuzzing::summary` (also run on the seeds by `cargo test`).
fn main() {
    afl::fuzz!(|data: &[u8]| tracerctl::fuzzing::summary(data));
}
