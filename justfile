# hopsim recipes: `just --list`

# Simulate Robbit (the README's main job) and write recordings to out/
run scene="scenes/robbit.toml":
    mkdir -p out
    cargo run --release -- run {{scene}} --mcap out/run.mcap --rrd out/run.rrd --summary out/summary.json

# All tests (the command CI runs)
test:
    cargo test --workspace --release

# Criterion benchmarks (LCP solver, stepper, sweep)
bench:
    cargo bench --workspace

# Formatting and lints, as CI checks them
lint:
    cargo fmt --all -- --check
    cargo clippy --workspace --all-targets --release -- -D warnings

# Everything CI does
ci:
    bash .ci/run
