#!/usr/bin/env bash
# Peer benchmarks (docs/performance.md): hopsim's Lemke against Siconos' C lexicographic
# Lemke on the same .dat LCPs, and hopsim's Robbit run against MuJoCo's native rollout of an
# equivalent planar model, and both stepping gymnasium's hopper.xml, interleaved in one run;
# prints the tables.
#
#   bash benches/peers/run.sh [bench.py options]     (or: just bench-peers)
#
# Installs what is missing when it can: libsiconos-numerics-dev with apt-get (as root), the
# mujoco Python package with pip (into the current python3, or else into a venv under the
# target directory). PEERS_NO_INSTALL=1: install nothing, only say what is missing.
# Environment: ROUNDS (default 11), CARGO_TARGET_DIR (default ./target), PEERS_NO_BUILD=1
# (use the examples already built instead of running cargo).
# Options after the script name go to bench.py (see `python3 benches/peers/bench.py -h`),
# e.g. --only lcp, --rounds 3, --json out.json.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
cd "$root"
target="${CARGO_TARGET_DIR:-$root/target}"
build="$target/peers"
mkdir -p "$build"

say() { printf '==> %s\n' "$*" >&2; }
die() { printf 'error: %s\n' "$*" >&2; exit 1; }
no_install() { [[ "${PEERS_NO_INSTALL:-0}" == 1 ]]; }

for tool in gcc python3 cargo; do
    command -v "$tool" >/dev/null || die "'$tool' is not installed (needed to build and run the peer benchmarks)"
done

# --- Siconos numerics (C Lemke) -------------------------------------------------------
siconos_inc=/usr/include/siconos
have_siconos() {
    [[ -f "$siconos_inc/numerics/LCP_Solvers.h" ]] && compgen -G '/usr/lib/*/libsiconos_numerics.so' >/dev/null
}
if ! have_siconos; then
    how="apt-get update && apt-get install -y libsiconos-numerics-dev   (Debian/Ubuntu; as root)"
    if no_install; then
        die "Siconos numerics is missing; install it with: $how"
    elif [[ "$(id -u)" == 0 ]] && command -v apt-get >/dev/null; then
        say "installing libsiconos-numerics-dev with apt-get"
        apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libsiconos-numerics-dev >/dev/null \
            || die "apt-get could not install libsiconos-numerics-dev; install it with: $how"
    else
        die "Siconos numerics is missing and this is not a root shell with apt-get; install it with: sudo $how"
    fi
    have_siconos || die "libsiconos-numerics-dev installed, but $siconos_inc/numerics/LCP_Solvers.h or libsiconos_numerics.so is still missing"
fi
say "Siconos numerics $(dpkg-query -W -f='${Version}' libsiconos-numerics-dev 2>/dev/null || echo '(version unknown)')"

# --- MuJoCo (Python package, native rollout) -------------------------------------------
python=python3
has_mujoco() { "$1" -c 'import mujoco, mujoco.rollout, numpy, gymnasium' 2>/dev/null; }
if ! has_mujoco "$python"; then
    venv="$build/venv"
    if [[ -x "$venv/bin/python" ]] && has_mujoco "$venv/bin/python"; then
        python="$venv/bin/python"
    elif no_install; then
        die "MuJoCo's Python package is missing; install it with: python3 -m pip install 'mujoco>=3.2' gymnasium"
    else
        say "installing mujoco with pip"
        if ! python3 -m pip install -q 'mujoco>=3.2' gymnasium || ! has_mujoco python3; then
            say "pip into $(command -v python3) failed; trying a venv in $venv"
            python3 -m venv "$venv" && "$venv/bin/python" -m pip install -q 'mujoco>=3.2' gymnasium \
                || die "could not install mujoco; install it with: python3 -m pip install 'mujoco>=3.2' gymnasium (needs python3-venv for the fallback)"
            python="$venv/bin/python"
        fi
        has_mujoco "$python" || die "mujoco installed but 'import mujoco.rollout' still fails in $python"
    fi
fi
say "MuJoCo $("$python" -c 'import mujoco; print(mujoco.__version__)') ($python)"

# --- Build both sides ------------------------------------------------------------------
say "compiling benches/peers/siconos_lcp.c"
gcc -O2 -Wall -I"$siconos_inc" -I"$siconos_inc/numerics" \
    -o "$build/siconos_lcp" "$here/siconos_lcp.c" -lsiconos_numerics \
    || die "could not compile benches/peers/siconos_lcp.c against libsiconos-numerics-dev"
if [[ "${PEERS_NO_BUILD:-0}" == 1 ]]; then
    say "PEERS_NO_BUILD=1: using the examples already built in $target/release/examples"
else
    say "building hopsim's examples peer_lcp and peer_rollout (release)"
    cargo build --release --quiet -p hopsim-lcp --example peer_lcp \
        || die "cargo could not build the example peer_lcp of hopsim-lcp"
    cargo build --release --quiet -p hopsim-sim --example peer_rollout \
        || die "cargo could not build the example peer_rollout of hopsim-sim"
fi
for example in peer_lcp peer_rollout; do
    [[ -x "$target/release/examples/$example" ]] \
        || die "$target/release/examples/$example is missing (build it, or unset PEERS_NO_BUILD)"
done

# --- Run, interleaved ------------------------------------------------------------------
say "running (ROUNDS=${ROUNDS:-11}); one to two minutes"
exec "$python" "$here/bench.py" \
    --siconos "$build/siconos_lcp" \
    --hopsim-lcp "$target/release/examples/peer_lcp" \
    --hopsim-rollout "$target/release/examples/peer_rollout" \
    --rounds "${ROUNDS:-11}" \
    --json "$build/last-run.json" \
    "$@"
