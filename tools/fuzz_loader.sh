#!/usr/bin/env bash
# Fuzzes the glTF loader with libFuzzer: builds fuzz_gltf_loader (clang, ASan + UBSan) in build-fuzz/, seeds it
# with the repository's scenes and the small files of ../shared/scenes-real, and runs it for SECONDS (default
# 60). A finding is written to build-fuzz/findings/ and fails the script; keep it in tests/fuzz/regressions/
# once fixed, where the test suite loads it on every build.
#
# Usage: tools/fuzz_loader.sh [SECONDS]     (needs: clang, libfuzzer-14-dev)
set -euo pipefail
case "${1:-}" in
    -h | --help) sed -n '2,7s/^# \{0,1\}//p' "$0"; exit 0 ;;
esac
seconds="${1:-60}"
# libFuzzer reads a -max_total_time that is not a number as 0, no limit: checked before anything is built.
[[ "$seconds" =~ ^[1-9][0-9]*$ ]] ||
    { echo "fuzz_loader: SECONDS must be a whole number of seconds, got '$seconds' (see --help)" >&2; exit 2; }
cd "$(dirname "$0")/.."
build=build-fuzz
mkdir -p "$build"
cmake -S . -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVKRT_FUZZ=ON \
      -DVKRT_BUILD_TESTS=OFF > "$build/configure.log" 2>&1 || { cat "$build/configure.log"; exit 1; }
cmake --build "$build" -j"$(nproc)" --target fuzz_gltf_loader
seeds="$build/seeds"
mkdir -p "$seeds" "$build/corpus" "$build/findings"
# Seeds of up to 64 KiB, the longest input tried: larger ones slow every run and add little coverage.
find scenes tests/fuzz/regressions -type f -size -64k -exec cp {} "$seeds/" \;
if [ -d ../shared/scenes-real ]; then
    find ../shared/scenes-real -type f \( -name '*.gltf' -o -name '*.glb' \) -size -64k -exec cp {} "$seeds/" \;
fi
# The corpus grows across runs; the seeds are read each time. -timeout: one input taking 60 s (wall time, on
# a machine that may be busy) is a hang.
"$build/fuzz_gltf_loader" -max_total_time="$seconds" -max_len=65536 -timeout=60 -rss_limit_mb=4096 -print_final_stats=1 \
    -artifact_prefix="$build/findings/" "$build/corpus" "$seeds" 2>&1 | tee "$build/fuzz.log" | grep -E "^#|ERROR|SUMMARY|stat::" | tail -12
