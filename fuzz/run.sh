#!/usr/bin/env bash
# Runs demkit's fuzz targets one after the other, each for SECONDS, with one libFuzzer process.
#
#   fuzz/run.sh SECONDS [TARGET...]     (default: every target; `fuzz/run.sh --list` lists them)
#
# Needs cargo-fuzz (`cargo install cargo-fuzz`). cargo-fuzz passes nightly-only flags to rustc;
# RUSTC_BOOTSTRAP=1 lets a stable toolchain accept them, so no nightly is needed. The corpora
# live in fuzz/corpus/TARGET (seeded from generated meshes on the first run), crashes in
# fuzz/artifacts/TARGET; both are ignored by git. Environment:
#   FUZZ_SANITIZER   none (default; demkit has no unsafe code) or address
#   FUZZ_MAX_LEN     longest input tried, in bytes (default 8192)
#   FUZZ_CODEGEN_UNITS  codegen units of the fuzz build (default 16: quicker to build)
#   FUZZ_TIMEOUT     seconds one input may take before it counts as a hang (default 30; on a
#                    loaded machine a shorter limit reports stalls of the machine as hangs)
#   CARGO_TARGET_DIR build directory (default fuzz/target)
# Exit status: 0 when no target found anything, 1 otherwise (the artifacts are listed).
set -euo pipefail

here="$(cd "$(dirname "$0")" && pwd)"
cd "$here"
export RUSTC_BOOTSTRAP=1

all_targets=(mesh_obj mesh_ply mesh_off mesh_stl expr geojson landmarks)

if [[ $# -lt 1 || "$1" == "-h" || "$1" == "--help" ]]; then
    sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'
    exit 2
fi
if [[ "$1" == "--list" ]]; then
    printf '%s\n' "${all_targets[@]}"
    exit 0
fi
seconds="$1"
shift
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || [[ "$seconds" -lt 1 ]]; then
    echo "error: SECONDS must be a positive whole number, got '$seconds'" >&2
    exit 2
fi
targets=("$@")
if [[ ${#targets[@]} -eq 0 ]]; then
    targets=("${all_targets[@]}")
fi
for t in "${targets[@]}"; do
    if ! printf '%s\n' "${all_targets[@]}" | grep -qx "$t"; then
        echo "error: unknown target '$t' (targets: ${all_targets[*]})" >&2
        exit 2
    fi
done

sanitizer="${FUZZ_SANITIZER:-none}"
max_len="${FUZZ_MAX_LEN:-8192}"
timeout="${FUZZ_TIMEOUT:-30}"
target_dir="${CARGO_TARGET_DIR:-$here/target}"

# Seed corpora, written once from generated meshes.
for t in "${targets[@]}"; do
    if [[ ! -d "corpus/$t" ]] || [[ -z "$(ls -A "corpus/$t")" ]]; then
        cargo run --quiet --release --target-dir "$target_dir" --example seed_corpus -- corpus
        break
    fi
done

# One build of every target (debug assertions and overflow checks on, so that an arithmetic
# overflow is a crash too), then the binaries are run directly.
cargo fuzz build --target-dir "$target_dir" --sanitizer "$sanitizer" -O -a \
    --codegen-units "${FUZZ_CODEGEN_UNITS:-16}"
bin_dir="$target_dir/$(rustc -vV | sed -n 's/^host: //p')/release"

found=0
for t in "${targets[@]}"; do
    mkdir -p "artifacts/$t"
    before=$(ls "artifacts/$t" | wc -l)
    echo "== $t: ${seconds}s"
    dict=()
    if [[ -f "dict/$t.dict" ]]; then
        dict=("-dict=dict/$t.dict")
    fi
    # libFuzzer stops at the first crash; its exit status is not fatal here, so that the
    # next target still runs.
    status=0
    "$bin_dir/$t" "corpus/$t" -artifact_prefix="artifacts/$t/" \
        -max_total_time="$seconds" -max_len="$max_len" -timeout="$timeout" -rss_limit_mb=2048 \
        -print_final_stats=1 "${dict[@]}" || status=$?
    after=$(ls "artifacts/$t" | wc -l)
    if [[ $status -ne 0 || $after -ne $before ]]; then
        found=1
        echo "== $t: libFuzzer exited with $status; artifacts:"
        ls -l "artifacts/$t"
    fi
done
exit $found
