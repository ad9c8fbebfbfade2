//! One integration-test binary (as ripgrep does): every test runs the real `tracerctl`.

mod decode;
mod docs;
mod generated;
mod util;
mod variants;
