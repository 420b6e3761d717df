#!/usr/bin/env bash
# vkrt on a real GPU, in one go: builds Release, checks that a GPU Vulkan device (not a CPU one such as
# lavapipe) is there, runs the GPU conformance tests on it, the ray benchmark suite against Embree, texel
# against storage reads of the scene (scene_access.json) and the convergence report (Cornell and Whitted, both
# integrators), and writes a summary: summary.json and
# summary.md (tables ready for the README) in the output folder. Meant to take under 8 minutes on 16 cores: from a
# kit, 138 to 151 s on an NVIDIA H200 with 16 host threads (2026-12-04). Tests whose images are off the CPU reference
# leave both images and their difference in test-failures/ there.
#
#   tools/gpu_check.sh [options] [OUT_DIR]        (OUT_DIR: gpu-check-out)
#
#   --allow-cpu-device  accept a CPU Vulkan device (lavapipe): a dry run of the script on any machine
#   --quick             short settings (a few tests, small benchmark and convergence runs), for the dry run
#   --build-dir DIR     the Release build tree [build-gpu-check]; an existing one is only brought up to date
#   --tests REGEX       ctest -R: which tests [the GPU suites: Gpu*, Stability, ShadingFunctions, Cli]
#   --jobs N            build and test jobs [nproc]
#   --debs DIR          first unpack every .deb in DIR into / and run ldconfig (root): the Vulkan loader on a
#                       machine that has the NVIDIA driver but no libvulkan1
#   --kit DIR           no build: take the programs, the test programs and their libraries from a kit that
#                       tools/gpu_kit.sh made on Debian 12 (for a machine without the Debian packages or a
#                       network, such as this project's lent NVIDIA machines). The kit is unpacked into
#                       /tmp/vkrt-kit (replacing what is there) with src a link to this checkout, which should be
#                       at the kit's commit; its debs/ are unpacked as with --debs when there is no Vulkan
#                       loader. Without ctest, the test programs run directly, with gpu_check's suites as a
#                       GoogleTest filter (--tests needs ctest).
#   --tar FILE          at the end, also pack the output folder into FILE (.tar.gz): one file to bring back
#   --budget SECONDS    stop each step after the build at its share of SECONDS (tests 40%, ray benchmarks 25%,
#                       scene access 10%, convergence 25%; what a step leaves unused passes to the next), so that
#                       a slow or hung step cannot take the others' time on a machine lent for minutes; a step
#                       stopped at its limit counts as failed and the summary says so
#
# The device: with VK_DRIVER_FILES (or VK_ICD_FILENAMES) unset, the script looks for NVIDIA's ICD file
# (nvidia_icd.json under /usr/share, /etc, /usr/local/share and /usr/local/nvidia/share: vulkan/icd.d) and
# points the Vulkan loader at it alone, so that the tests, the benchmarks and the renders, which take the
# best device (a discrete GPU first), cannot fall back to lavapipe. Set VK_DRIVER_FILES yourself for another
# driver. Prerequisites are those of tools/install-deps.sh (the GPU tests run under the Khronos validation
# layer, Debian's vulkan-validationlayers; Embree is optional), or, with --kit, Python 3, ldd and dpkg alone.
#
# Exit codes: 0 everything ran and the tests passed; 1 something failed (the summary says what); 2 no GPU
# Vulkan device (the devices found are listed) or bad usage.
set -uo pipefail

usage() { sed -n '2,/^set -uo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; }

allow_cpu=0 quick=0 build_dir=build-gpu-check tests="" jobs=$(nproc) debs="" out="" kit="" tar="" budget=""
while [ $# -gt 0 ]; do
    case "$1" in
        --allow-cpu-device) allow_cpu=1 ;;
        --quick) quick=1 ;;
        --build-dir) build_dir=${2:?--build-dir needs a folder}; shift ;;
        --tests) tests=${2:?--tests needs a regular expression}; shift ;;
        --jobs) jobs=${2:?--jobs needs a number}; shift ;;
        --debs) debs=${2:?--debs needs a folder}; shift ;;
        --kit) kit=${2:?--kit needs a folder}; shift ;;
        --tar) tar=${2:?--tar needs a file}; shift ;;
        --budget) budget=${2:?--budget needs seconds}; shift ;;
        -h|--help) usage; exit 0 ;;
        -*) echo "gpu_check: unknown option $1 (see --help)" >&2; exit 2 ;;
        *) [ -z "$out" ] || { echo "gpu_check: one output folder only (see --help)" >&2; exit 2; }; out=$1 ;;
    esac
    shift
done
case "$jobs" in ''|*[!0-9]*) echo "gpu_check: --jobs takes a number" >&2; exit 2 ;; esac
case "$budget" in *[!0-9]*) echo "gpu_check: --budget takes whole seconds" >&2; exit 2 ;; esac

if [ -n "$kit" ]; then
    [ -f "$kit/vkrt-gpu-kit.tar.xz" ] || { echo "gpu_check: $kit holds no kit (tools/gpu_kit.sh)" >&2; exit 2; }
    kit=$(cd "$kit" && pwd)
fi
root=$(cd "$(dirname "$0")/.." && pwd)
out=$(mkdir -p "${out:-gpu-check-out}" && cd "${out:-gpu-check-out}" && pwd) || exit 2
cd "$root" || exit 1
case "$build_dir" in /*) ;; *) build_dir="$root/$build_dir" ;; esac
log="$out/log.txt"
: >"$log"
start=$(date +%s)
steps="$out/steps.tsv"  # step, status, seconds, note
: >"$steps"
failed=0

say() { echo "gpu_check: $*" | tee -a "$log" >&2; }
# Runs "$@" as a job of its own (its own process group, children included) and stops the whole group after
# $1 seconds: status 124 then, as timeout(1) gives.
run_limited() {
    local limit=$1 waited=0 pid; shift
    set -m
    "$@" &
    pid=$!
    set +m
    while kill -0 "$pid" 2>/dev/null; do
        if [ "$waited" -ge "$limit" ]; then
            kill -TERM -- "-$pid" 2>/dev/null; sleep 2; kill -KILL -- "-$pid" 2>/dev/null
            wait "$pid"
            return 124
        fi
        sleep 1
        waited=$((waited + 1))
    done
    wait "$pid"
}
# Each limited step's share of --budget, in percent; the seconds a step leaves unused pass to the next one.
declare -A share=([tests]=40 [benchmark_suite]=25 [scene_access]=10 [convergence_report]=25)
unused=0
# Runs a step with its output in the log (within its share of --budget, if one was given); records its status,
# duration and, when it was stopped, its limit.
step() {
    local name=$1; shift
    local t0=$(date +%s) limit="" status note=""
    [ -z "$budget" ] || [ -z "${share[$name]:-}" ] || limit=$(( budget * ${share[$name]} / 100 + unused ))
    say "$name${limit:+ (at most $limit s)}: $*"
    if [ -n "$limit" ]; then run_limited "$limit" "$@" >>"$log" 2>&1; else "$@" >>"$log" 2>&1; fi
    status=$?
    local seconds=$(( $(date +%s) - t0 ))
    if [ -n "$limit" ]; then
        unused=$(( limit > seconds ? limit - seconds : 0 ))
        [ $status -ne 124 ] || note="stopped at its limit of $limit s"
    fi
    printf '%s\t%s\t%s\t%s\n' "$name" "$status" "$seconds" "$note" >>"$steps"
    [ $status -eq 0 ] || { say "$name failed (exit $status${note:+, $note}; see $log)"; failed=1; }
    return $status
}
# Records a step that could not run: it fails the check, and its share of --budget passes to the next step.
not_run() {
    local name=$1
    printf '%s\tnot run\t0\n' "$name" >>"$steps"
    failed=1
    [ -z "$budget" ] || [ -z "${share[$name]:-}" ] || unused=$(( budget * ${share[$name]} / 100 + unused ))
}

if [ $quick -eq 1 ]; then
    gtest_filter=Gpu.TexelStorageAndAddressedScenesGiveTheSameImage:Scenes/GpuImage.MatchesCpuReference/cornell
    gtest_filter+=:Cli.GpuRenderUnderValidationWritesGpuStats
    : "${tests:=^(Gpu\.TexelStorageAndAddressedScenesGiveTheSameImage|Scenes/GpuImage\.MatchesCpuReference/cornell |Cli\.GpuRenderUnderValidationWritesGpuStats)}"
    bench_args=(--runs 1 --size 128)
    access_args=(--runs 1 --width 128 --height 128)
    conv_args=(--width 32 --gpu-spp 16 --cpu-spp 16 --reference-spp 64)
else
    gtest_filter='Gpu*:*/Gpu*:Stability*:ShadingFunctions*:Cli*:MemoryCli*'
    : "${tests:=^(Gpu|[A-Za-z]+/Gpu|Stability|ShadingFunctions|Cli|MemoryCli)}"
    bench_args=(--runs 3 --size 1024)
    access_args=(--runs 3)
    conv_args=(--width 256 --gpu-spp 256 --cpu-spp 64 --reference-spp 1024)
fi

# A kit: unpacked where it was built, with its libraries and validation layer in the search paths.
ldconfig=$(command -v ldconfig || echo /sbin/ldconfig)
if [ -n "$kit" ]; then
    prefix=/tmp/vkrt-kit
    kit_commit=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["commit"])' \
        "$kit/manifest.json")
    say "unpacking the kit (commit $kit_commit) into $prefix"
    rm -rf "$prefix" && mkdir -p "$prefix" || exit 1
    if command -v xz >/dev/null; then
        tar -C "$prefix" -xJf "$kit/vkrt-gpu-kit.tar.xz" || exit 1
    else
        python3 -c 'import sys, tarfile; t = tarfile.open(sys.argv[1])
t.extractall(sys.argv[2], **({"filter": "data"} if hasattr(tarfile, "data_filter") else {}))' \
            "$kit/vkrt-gpu-kit.tar.xz" "$prefix" || exit 1
    fi
    ln -s "$root" "$prefix/src" || exit 1
    build_dir=$prefix/build
    export LD_LIBRARY_PATH="$prefix/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" VK_LAYER_PATH="$prefix/layers"
    if [ -z "$debs" ] && ! "$ldconfig" -p 2>/dev/null | grep 'libvulkan\.so\.1' >/dev/null; then
        debs=$kit/debs
    fi
    head=$(git -C "$root" rev-parse HEAD 2>/dev/null || true)
    [ -z "$head" ] || [ "$head" = "$kit_commit" ] || say "note: the kit is of $kit_commit, this checkout $head"
fi

# The Vulkan loader, when it has to be brought (see --debs).
if [ -n "$debs" ]; then
    for f in "$debs"/*.deb; do [ -e "$f" ] && dpkg -x "$f" / ; done
    "$ldconfig"
fi
if ! "$ldconfig" -p 2>/dev/null | grep 'libvulkan\.so\.1' >/dev/null; then  # not -q: pipefail
    say "no Vulkan loader (libvulkan.so.1): install libvulkan1 (tools/install-deps.sh), or unpack it with --debs DIR"
    exit 2
fi

# Only NVIDIA's driver, when it is installed and nothing else was asked (not in a dry run on a CPU device).
if [ $allow_cpu -eq 0 ] && [ -z "${VK_DRIVER_FILES:-}${VK_ICD_FILENAMES:-}" ]; then
    for icd in /usr/share/vulkan/icd.d/nvidia_icd.json /etc/vulkan/icd.d/nvidia_icd.json \
               /usr/local/share/vulkan/icd.d/nvidia_icd.json /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; do
        if [ -f "$icd" ]; then
            export VK_DRIVER_FILES=$icd VK_ICD_FILENAMES=$icd
            say "Vulkan loader restricted to $icd"
            break
        fi
    done
fi

# Build (Release), or check that the kit's programs find every library they load.
if [ -n "$kit" ]; then
    missing=$(ldd "$build_dir/vkrt" "$build_dir/ray_benchmark" "$build_dir"/tests/*_test 2>&1 |
        grep 'not found' | sort -u)
    if [ -n "$missing" ]; then
        say "the kit's programs miss libraries here:"
        echo "$missing" | sed 's/^/    /' >&2
        exit 1
    fi
else
    if ! step configure cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release; then
        say "cmake failed: are the dependencies installed (tools/install-deps.sh)?"
        exit 1
    fi
    step build cmake --build "$build_dir" -j "$jobs" || exit 1
fi
vkrt="$build_dir/vkrt"

# The device: listed, then the one vkrt and the tests take by default, probed with a small render.
"$vkrt" --list-devices >"$out/devices.txt" 2>&1
cat "$out/devices.txt" >>"$log"
probe() {
    "$vkrt" --scene scenes/cornell.gltf --width 16 --height 16 --spp 1 --quiet --out "$out/probe.png" \
        --stats "$out/probe.json" "$@"
}
if ! probe >>"$log" 2>&1; then
    say "no usable Vulkan device; the loader found:"
    sed 's/^/    /' "$out/devices.txt" >&2
    exit 2
fi
device_type=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["device_type"])' "$out/probe.json")
device_name=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["device_name"])' "$out/probe.json")
if [ "$device_type" = CPU ] && [ $allow_cpu -eq 0 ]; then
    say "no GPU Vulkan device: vkrt would run on $device_name ($device_type). The devices found:"
    sed 's/^/    /' "$out/devices.txt" >&2
    say "(set VK_DRIVER_FILES to the GPU's ICD file, or pass --allow-cpu-device for a dry run)"
    exit 2
fi
say "device: $device_name ($device_type)"

# The GPU conformance tests (each test process takes the same default device), under the validation layer.
# Without ctest (a kit on a machine without CMake), each test program runs the suites by GoogleTest's filter,
# side by side, with its shader cache where ctest would set it.
gtest_programs() {
    mkdir -p "$out/gtest"
    local status=0 pids=() p
    for p in "$build_dir"/tests/*_test; do
        VKRT_SHADER_CACHE="$build_dir/shader-cache" "$p" --gtest_filter="$gtest_filter" \
            --gtest_output="xml:$out/gtest/$(basename "$p").xml" &
        pids+=($!)
        [ ${#pids[@]} -lt "$jobs" ] || { wait "${pids[0]}" || status=1; pids=("${pids[@]:1}"); }
    done
    for p in "${pids[@]}"; do wait "$p" || status=1; done
    return $status
}
# A test whose image is off the CPU reference saves both images and their difference (support/
# reference_comparison.cpp): those of this run are kept in the output folder, to look at where the GPU was.
failures="${TMPDIR:-/tmp}/vkrt-test-failures"
rm -rf "$failures"
if ! probe --validate >>"$log" 2>&1; then
    say "the GPU tests need the Khronos validation layer (Debian: vulkan-validationlayers); tests not run"
    not_run tests
elif command -v ctest >/dev/null; then
    step tests ctest --test-dir "$build_dir" -j "$jobs" -R "$tests" --no-tests=error --output-on-failure \
        --output-junit "$out/tests.xml"
elif [ -n "$kit" ]; then
    say "no ctest here: the test programs run directly (GoogleTest filter $gtest_filter)"
    step tests gtest_programs
else
    say "no ctest (CMake's): tests not run"
    not_run tests
fi
if [ -d "$failures" ]; then
    cp -r "$failures" "$out/test-failures" && say "the images of the tests that failed: $out/test-failures"
fi

# Ray throughput against Embree, and error against render time.
models=()
if [ -n "$kit" ] && [ -f "$prefix/models/2CylinderEngine.glb" ]; then
    models=(--model "$prefix/models/2CylinderEngine.glb" --model scenes/cornell.gltf)
fi
# The GPU's clocks, performance state and what holds its clocks back, sampled every 200 ms while the benchmarks
# run (nvidia-smi, where there is one): on the H200 the same walk traced at one of two speeds 5 to 6 times
# apart from one process to the next (docs/performance-log.md), and this log shows whether the clocks moved.
clock_log=
if command -v nvidia-smi >/dev/null; then
    nvidia-smi -q -d CLOCK,PERFORMANCE >"$out/gpu_clocks_start.txt" 2>&1
    fields=timestamp,pstate,clocks.sm,clocks.mem,clocks.max.sm,power.draw,temperature.gpu,utilization.gpu
    # The reasons' field has two names (clocks_event_reasons since driver 535, clocks_throttle_reasons before).
    for reasons in clocks_event_reasons.active clocks_throttle_reasons.active ""; do
        if nvidia-smi --query-gpu="$fields${reasons:+,$reasons}" --format=csv,noheader >/dev/null 2>&1; then
            fields=$fields${reasons:+,$reasons}
            break
        fi
    done
    nvidia-smi --query-gpu="$fields" --format=csv -lms 200 >"$out/gpu_clocks.csv" 2>&1 &
    clock_log=$!
    trap '[ -z "$clock_log" ] || kill "$clock_log" 2>/dev/null' EXIT
fi
benchmark_suite() {
    python3 tools/benchmark_suite.py --ray-benchmark "$build_dir/ray_benchmark" --out "$out/benchmark.json" \
        "${bench_args[@]}" "${models[@]}" >"$out/benchmark.md"
}
step benchmark_suite benchmark_suite
# How the device reads the scene: its default (texel buffers) against storage buffers, run for run on the
# 1M-triangle sphere (texels were faster on lavapipe and on an H200; docs/performance-log.md).
scene_access() {
    "$build_dir/ray_benchmark" "${access_args[@]}" --variant VKRT_BOUND_GEOMETRY >"$out/scene_access.json.part" &&
        mv "$out/scene_access.json.part" "$out/scene_access.json"
}
step scene_access scene_access
step convergence_report python3 tools/convergence_report.py --vkrt "$vkrt" --out-dir "$out/convergence" \
    --integrators path,whitted "${conv_args[@]}" scenes/cornell.gltf scenes/whitted.gltf
[ -z "$clock_log" ] || kill "$clock_log" 2>/dev/null

# The summary.
elapsed=$(( $(date +%s) - start ))
commit=$(git -C "$root" describe --always --dirty 2>/dev/null || true)
[ -n "$commit" ] || [ -z "$kit" ] || commit="${kit_commit:0:12} (the kit's)"
step summary python3 - "$out" "$elapsed" "$quick" "$commit" <<'EOF'
import json, os, sys, time, xml.etree.ElementTree as ET
out, elapsed, quick, commit = sys.argv[1], int(sys.argv[2]), sys.argv[3] == "1", sys.argv[4]

def load(name):
    # A step stopped by its share of --budget may leave its file empty or cut short: it is missing then.
    try:
        return json.load(open(os.path.join(out, name)))
    except (OSError, ValueError):
        return None

probe = load("probe.json") or {}
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
summary = {"commit": commit, "quick": quick, "seconds": elapsed, "host_cpu": cpu, "host_threads": os.cpu_count(),
           "device": {**{k: probe.get(k) for k in ("device_name", "device_type", "driver")},
                      "memory_budget_bytes": (probe.get("memory") or {}).get("device_budget_bytes")},
           "steps": []}
for line in open(os.path.join(out, "steps.tsv")):
    name, status, seconds, note = (line.rstrip("\n").split("\t") + [""])[:4]
    summary["steps"].append({"step": name, "status": int(status) if status.isdigit() else status,
                             "seconds": int(seconds), **({"note": note} if note else {})})

# ctest's JUnit file (status run, fail, notrun or disabled), or GoogleTest's own files from the test programs
# run directly (status run or notrun, result skipped, a failure element on failure).
tests = None
gtest = os.path.join(out, "gtest")
reports = [os.path.join(out, "tests.xml")] if os.path.exists(os.path.join(out, "tests.xml")) else \
    sorted(os.path.join(gtest, f) for f in os.listdir(gtest)) if os.path.isdir(gtest) else []
if reports:
    tests = {"passed": 0, "failed": 0, "skipped": 0, "failures": []}
    for report in reports:
        for case in ET.parse(report).getroot().iter("testcase"):
            name = case.get("name") if case.get("classname") in (None, case.get("name")) else \
                case.get("classname") + "." + case.get("name")
            if case.get("status") == "fail" or case.find("failure") is not None:
                tests["failed"] += 1
                tests["failures"].append(name)
            elif case.get("status") == "run" and case.get("result") != "skipped":
                tests["passed"] += 1
            else:
                tests["skipped"] += 1
summary["tests"] = tests
# Tests that ran none (a pattern or filter that matched nothing) did not pass.
no_tests = tests is not None and tests["passed"] + tests["failed"] == 0

# nvidia-smi's samples of the SM clock (gpu_clocks.csv: the time, in local time, first), as (Unix s, MHz).
clocks = []
if os.path.exists(os.path.join(out, "gpu_clocks.csv")):
    for line in open(os.path.join(out, "gpu_clocks.csv")):
        cells = [c.strip() for c in line.split(",")]
        try:
            when = time.mktime(time.strptime(cells[0].split(".")[0], "%Y/%m/%d %H:%M:%S"))
            clocks.append((when + float("0." + cells[0].split(".")[1]), float(cells[2].split()[0])))
        except (IndexError, ValueError):
            pass  # the header, or a line nvidia-smi could not fill
def sm_clock(r):
    seen = [mhz for when, mhz in clocks if r.get("started_unix_s", 0) <= when <= r.get("finished_unix_s", 0)]
    return [min(seen), max(seen)] if seen else None

rays = []
for r in load("benchmark.json") or []:
    for kind, k in r["kinds"].items():
        if not k["rays"]:
            continue  # no camera ray hit anything, so there were none of this kind
        embree = k.get("embree_mrays_per_s")
        rays.append({"input": os.path.basename(r["input"]), "triangles": r["triangles"], "kind": kind,
                     "vkrt_mrays_per_s": k["mrays_per_s"]["median"],
                     "vkrt_mrays_per_gpu_s": (k.get("mrays_per_gpu_s") or {}).get("median"),
                     "embree_mrays_per_s": embree["median"] if embree else None,
                     "vkrt_over_embree": k.get("vkrt_over_embree") if embree else None,
                     "sm_clock_mhz": sm_clock(r)})
summary["rays"] = rays
# The device's default way of reading the scene against storage buffers, run for run: per GPU second where the
# device has timestamps (per CPU second would time the host's wait on a GPU), else per CPU second.
access = load("scene_access.json")
summary["scene_access"] = None if not access else {
    "default": access.get("scene_access"),
    "storage_over_default": {kind: v.get("over_default_gpu", v.get("over_default_cpu"))
                             for kind, k in access["kinds"].items()
                             for v in [k.get("variants", {}).get("VKRT_BOUND_GEOMETRY", {})]},
    "per": "GPU second" if all("over_default_gpu" in k.get("variants", {}).get("VKRT_BOUND_GEOMETRY", {})
                               for k in access["kinds"].values()) else "CPU second"}

convergence = []
for name, devices in (load("convergence/summary.json") or {}).items():
    for device, d in devices.items():
        # Only path outputs carry -path (a Whitted scene may be named X-path: convergence_report's output_name).
        convergence.append({"scene": name[:-5] if d["integrator"] == "path" else name, "integrator": d["integrator"],
                            "device": device, "ms_to_rmse_0.01": d.get("ms_to_rmse_0.01"), "slope": d["slope"]})
summary["convergence"] = convergence
json.dump(summary, open(os.path.join(out, "summary.json"), "w"), indent=1)

device = summary["device"]
dash = lambda v, f: f % v if v is not None else "-"
md = ["vkrt on %s (%s; driver %s), host %s (%d threads), commit %s%s; the check took %d s." % (
          device["device_name"], device["device_type"], device["driver"], cpu, os.cpu_count(), commit,
          ", short settings (--quick)" if quick else "", elapsed), ""]
if no_tests:
    md.append("Tests: none ran (%d skipped): the check fails." % tests["skipped"])
elif tests:
    md.append("Tests: %d passed, %d failed, %d skipped%s." % (tests["passed"], tests["failed"], tests["skipped"],
              " (failed: " + ", ".join(tests["failures"]) + ")" if tests["failures"] else ""))
else:
    md.append("Tests: not run.")
def failure(step):
    status = step["status"]
    return step.get("note") or ("exit %d" % status if isinstance(status, int) else status)
stopped = ["%s (%s)" % (st["step"], failure(st)) for st in summary["steps"] if st["status"] != 0]
if stopped:
    md.append("Steps that failed: " + ", ".join(stopped) + ": what they report below is partial or missing.")
md += ["", "| input | triangles | ray kind | vkrt Mrays/s | vkrt Mrays/s, GPU time | Embree Mrays/s (host CPU, %d "
       "threads) | vkrt / Embree | SM clock MHz (nvidia-smi) |" % os.cpu_count(), "|---|---|---|---|---|---|---|---|"]
md += ["| %s | %d | %s | %.2f | %s | %s | %s | %s |" % (r["input"], r["triangles"], r["kind"], r["vkrt_mrays_per_s"],
       dash(r["vkrt_mrays_per_gpu_s"], "%.2f"), dash(r["embree_mrays_per_s"], "%.2f"),
       dash(r["vkrt_over_embree"], "%.3f"), "%.0f-%.0f" % tuple(r["sm_clock_mhz"]) if r["sm_clock_mhz"] else "-")
       for r in rays]
if summary["scene_access"]:
    a = summary["scene_access"]
    md += ["", "Scene access (scene_access.json, 1M sphere, run for run per %s): storage buffers at %s of the "
           "default's (%s) rate." % (a["per"], ", ".join("%s %s" % (kind, dash(ratio, "%.3f"))
                                                         for kind, ratio in a["storage_over_default"].items()),
                                     a["default"])]
md += ["", "| scene | integrator | device | ms to RMSE 0.01 | slope |", "|---|---|---|---|---|"]
md += ["| %s | %s | %s | %s | %s |" % (c["scene"], c["integrator"],
       device["device_name"] if c["device"] == "gpu" else "CPU reference (%d threads)" % os.cpu_count(),
       dash(c["ms_to_rmse_0.01"], "%.0f"), dash(c["slope"], "%.2f")) for c in convergence]
open(os.path.join(out, "summary.md"), "w").write("\n".join(md) + "\n")
print("\n".join(md))
sys.exit(1 if no_tests else 0)
EOF
[ -f "$out/summary.md" ] && cat "$out/summary.md"
elapsed=$(( $(date +%s) - start ))
if [ -f "$out/summary.md" ]; then
    say "done in ${elapsed} s; summary in $out/summary.md and $out/summary.json"
else
    say "done in ${elapsed} s; the summary could not be made (see $log)"
fi
[ $elapsed -le 480 ] || say "note: over the 8-minute budget"
if [ -n "$tar" ]; then
    tar -C "$(dirname "$out")" -czf "$tar" "$(basename "$out")" && say "packed into $tar" || failed=1
fi
exit $failed
