#!/usr/bin/env bash
# Fuzzes xcut's input readers with libFuzzer (docs/fuzzing.md).
#
#   tools/fuzz.sh [MINUTES] [TARGET...]      default: 5 minutes each for every target
#   tools/fuzz.sh 20s [TARGET...]            seconds instead (what CI runs)
#
# Targets: scene gmsh vtu vtk tetgen surface trajectory. Builds preset "fuzz" (clang-14, ASan + UBSan) in
# build-fuzz/, then runs each target for MINUTES (a decimal is fine) on a working
# corpus build-fuzz/corpus/TARGET seeded from tests/fuzz/corpus/TARGET. XCUT_FUZZ_JOBS=N runs N
# targets at a time (default 1). A crash, a sanitizer report, a leak, an uncaught exception other
# than InputError or an input taking over 10 s stops that target; its input is saved as
# build-fuzz/artifacts/TARGET/crash-* (or timeout-*, leak-*, oom-*) and the script exits 1.
# XCUT_FUZZ_DIR=DIR runs the targets already built in DIR instead (CI builds them with its
# sanitizer stage, preset "ci-sanitize", and does not build them twice).
set -euo pipefail
cd "$(dirname "$0")/.."
minutes="${1:-5}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(scene gmsh vtu vtk tetgen surface trajectory)
case "$minutes" in
    *s) seconds="${minutes%s}" ;;
    *) seconds=$(awk -v m="$minutes" 'BEGIN { s = int(m * 60 + 0.5); if (s < 1) s = 1; print s }') ;;
esac
[[ "$seconds" =~ ^[0-9]+$ ]] || { echo "usage: tools/fuzz.sh [MINUTES|SECONDSs] [TARGET...]" >&2; exit 2; }
jobs="${XCUT_FUZZ_JOBS:-1}"

dir="${XCUT_FUZZ_DIR:-}"
if [ -z "$dir" ]; then
    dir="build-fuzz"
    cmake --preset fuzz > /dev/null
    cmake --build --preset fuzz
fi

run_one() {
    local t="$1"
    mkdir -p "$dir/corpus/$t" "$dir/artifacts/$t"
    local log="$dir/fuzz_$t.log" dict=()
    [ -f "tests/fuzz/$t.dict" ] && dict=(-dict="tests/fuzz/$t.dict")
    if "$dir/fuzz_$t" "${dict[@]}" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
        -artifact_prefix="$dir/artifacts/$t/" "$dir/corpus/$t" "tests/fuzz/corpus/$t" > "$log" 2>&1; then
        echo "fuzz_$t: ok, $(grep -m1 -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$') runs in ${seconds} s"
    else
        echo "fuzz_$t: FAILED (full log: $log)"
        grep -E 'ERROR|runtime error|SUMMARY|uncaught|Test unit written|Base64' "$log" | head -n 20 || true
        return 1
    fi
}

status=0
pids=()
for t in "${targets[@]}"; do
    [ -f "tests/fuzz/fuzz_$t.cpp" ] || { echo "unknown fuzz target: $t" >&2; exit 2; }
    run_one "$t" &
    pids+=($!)
    if [ ${#pids[@]} -ge "$jobs" ]; then
        wait "${pids[0]}" || status=1
        pids=("${pids[@]:1}")
    fi
done
for p in "${pids[@]}"; do wait "$p" || status=1; done
exit $status
