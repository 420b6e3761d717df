#!/usr/bin/env bash
# Builds vkrt with AddressSanitizer and UndefinedBehaviorSanitizer (-DVKRT_SANITIZE=ON, in build-sanitize/) and
# runs the loader, bad-input, environment, memory-estimate and CPU reference tests under them. Any sanitizer
# report fails its test: the build stops at the first (-fno-sanitize-recover=all).
#
# Usage: tools/sanitize_check.sh
set -euo pipefail
case "${1:-}" in
    "") ;;
    -h | --help) sed -n '2,6s/^# \{0,1\}//p' "$0"; exit 0 ;;
    *) echo "sanitize_check: takes no arguments, got '$1' (see --help)" >&2; exit 2 ;;
esac
cd "$(dirname "$0")/.."
build=build-sanitize
mkdir -p "$build"
# -O1 -g1 (line tables: reports still name file and line): the build took 5.6 minutes instead of 9.8 at -O2 -g on
# a 2-core machine, and the tests under the sanitizers as long (119 against 116 s).
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
      -DVKRT_SANITIZE=ON > "$build/configure.log" 2>&1 ||
    { cat "$build/configure.log"; exit 1; }
cmake --build "$build" -j"$(nproc)" --target vkrt gltf_loader_test gltf_compression_test bad_input_test deformation_test environment_test \
      reference_renderer_test common_test image_io_test memory_test
export ASAN_OPTIONS=abort_on_error=1:detect_stack_use_after_return=1:fast_unwind_on_malloc=0 UBSAN_OPTIONS=print_stacktrace=1
export LSAN_OPTIONS="suppressions=$PWD/tools/lsan.supp:print_suppressions=0"
ctest --test-dir "$build" -j"$(nproc)" --output-on-failure \
      -R '^(GltfLoader|GltfCompression|Skins|MorphTargets|Deformation|CameraSelection|Mipmaps|TangentFrames|BadInput|Environment|ReferenceRenderer|CornellBox|CheckpointSchedule|ForkJoin|ParallelFor|ImageIo|ImageMetrics|ToneMap|MemoryNeed|HostMemory)\.'
