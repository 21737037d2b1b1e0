// A build script makes cargo resolve the crate's build dependencies (hakari).
fn main() {}
