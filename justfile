# hopsim recipes: `just --list`

# Simulate Robbit (the README's main job) and write recordings to out/
run scene="scenes/robbit.toml":
    mkdir -p out
    cargo run --release -- run {{scene}} --mcap out/run.mcap --rrd out/run.rrd --summary out/summary.json

# The thesis' 30 × 30 Robbit sweep: speed against transferred impulse (docs/sweeps.md)
sweep-robbit:
    cargo run --release -- sweep scenes/robbit.toml --grid controller.torque=0.1:0.3:30 \
        --grid controller.impulse_limit=0.04:0.07:30 --out out/robbit-sweep

# CaneBot's cane-timing sweep with the retracted and extended baselines (docs/canebot.md)
sweep-canebot:
    cargo run --release -- sweep scenes/canebot-timed.toml --grid controller.cane_delay=0:1:41 \
        --grid controller.cane_duration=0.5,1 --baseline retracted:controller.cane_mode=retracted \
        --baseline extended:controller.cane_mode=extended --out out/canebot-sweep

# All tests (the command CI runs)
test:
    cargo test --workspace --release

# Criterion benchmarks (LCP solver, stepper, sweep)
bench:
    cargo bench --workspace

# Peer benchmarks: Siconos' C Lemke and MuJoCo's rollout against hopsim, in one table
# (installs libsiconos-numerics-dev and mujoco if missing; docs/performance.md)
bench-peers:
    bash benches/peers/run.sh

# Mutation testing (cargo-mutants, release profile) of the LCP solver's core files and the
# contact geometry, each against its crate's tests; results in out/mutants-*/mutants.out
# (installs cargo-mutants if missing; about 2 h for the LCP and 7 h for the geometry on two
# cores; docs/validation.md)
mutants:
    command -v cargo-mutants >/dev/null || cargo install --locked cargo-mutants --version '^27'
    -CARGO_PROFILE_RELEASE_INCREMENTAL=true CARGO_PROFILE_RELEASE_DEBUG=false cargo mutants \
        -p hopsim-lcp --test-package hopsim-lcp --profile release --cargo-test-arg=--tests \
        --minimum-test-timeout 30 --output out/mutants-lcp \
        -f crates/hopsim-lcp/src/certificate.rs -f crates/hopsim-lcp/src/lemke.rs \
        -f crates/hopsim-lcp/src/lemke/warm.rs -f crates/hopsim-lcp/src/primary.rs \
        -f crates/hopsim-lcp/src/tableau.rs -f crates/hopsim-lcp/src/enumerate.rs
    CARGO_PROFILE_RELEASE_INCREMENTAL=true CARGO_PROFILE_RELEASE_DEBUG=false cargo mutants \
        -p hopsim-model --test-package hopsim-model --profile release --cargo-test-arg=--tests \
        --minimum-test-timeout 60 --output out/mutants-model \
        -f crates/hopsim-model/src/contact.rs -f crates/hopsim-model/src/pairs.rs \
        -f crates/hopsim-model/src/ellipse.rs -f crates/hopsim-model/src/capsule.rs

# Formatting and lints, as CI checks them
lint:
    cargo fmt --all -- --check
    cargo clippy --workspace --all-targets --release -- -D warnings

# docs/ as a book in target/book, links checked (installs mdBook if missing; docs/book.md)
book:
    bash .ci/book

# Everything CI does
ci:
    bash .ci/run

# Generated mechanisms, a long campaign (docs/reliability.md, "Generated mechanisms")
fuzz cases="200000":
    HOPSIM_GEN_CASES={{cases}} HOPSIM_GEN_SEED=random cargo test --release -p hopsim-gen --test generated_mechanisms
