#!/usr/bin/env bash
# Packs vkrt for a GPU machine that cannot build it (no Debian packages and no network, such as the lent
# NVIDIA machines of this project), for `tools/gpu_check.sh --kit`. Run here, on Debian 12 with the packages of
# tools/install-deps.sh:
#
#   tools/gpu_kit.sh [--jobs N] [KIT_DIR]        (KIT_DIR: .gpu-kit, which git ignores)
#
# It clones the checkout's HEAD to /tmp/vkrt-kit/src and builds it in Release at /tmp/vkrt-kit/build: the test
# programs hold those paths (the source tree, vkrt), and gpu_check.sh puts the kit back there on the GPU
# machine, with src a link to that machine's copy of the repository. KIT_DIR then holds:
#   vkrt-gpu-kit.tar.xz  vkrt, ray_benchmark, the GPU test programs (gpu_check.sh's suites) and the build's
#                        ctest files; the shared libraries they load beyond the C and C++ runtimes (lib/); the
#                        Khronos validation layer with a manifest beside it (layers/); 2CylinderEngine (models/);
#                        the third-party scenes beside the checkout (../shared/scenes-real), for the tests of them
#   debs/                the Vulkan loader and glvnd (NVIDIA's driver needs libGLdispatch), for dpkg -x there
#   manifest.json        the commit, the paths, and what is in the archive
# About 40 MB (24 without the third-party scenes); 6 to 7 minutes on 2 cores (the build about 4).
set -euo pipefail

usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; }

jobs=$(nproc) kit=""
while [ $# -gt 0 ]; do
    case "$1" in
        --jobs) jobs=${2:?--jobs needs a number}; shift ;;
        -h|--help) usage; exit 0 ;;
        -*) echo "gpu_kit: unknown option $1 (see --help)" >&2; exit 2 ;;
        *) [ -z "$kit" ] || { echo "gpu_kit: one kit folder only (see --help)" >&2; exit 2; }; kit=$1 ;;
    esac
    shift
done
case "$jobs" in ''|*[!0-9]*) echo "gpu_kit: --jobs takes a number" >&2; exit 2 ;; esac

root=$(cd "$(dirname "$0")/.." && pwd)
kit=$(mkdir -p "${kit:-$root/.gpu-kit}" && cd "${kit:-$root/.gpu-kit}" && pwd)
prefix=/tmp/vkrt-kit  # gpu_check.sh's too
# The programs gpu_check.sh runs, and the test programs that hold its suites (Gpu*, Scenes/GpuImage, Stability,
# ShadingFunctions, Cli, MemoryCli).
programs=(vkrt ray_benchmark)
test_programs=(gpu_image_test gpu_ray_test gpu_render_test gpu_physics_test gpu_material_test gpu_surface_test
               gpu_environment_test gpu_path_test gpu_cycles_test gpu_energy_test stability_test
               shading_functions_test cli_test memory_test)
engine=/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb
layer=/usr/lib/x86_64-linux-gnu/libVkLayer_khronos_validation.so

say() { echo "gpu_kit: $*" >&2; }
[ -f "$layer" ] || { say "no Khronos validation layer ($layer): install vulkan-validationlayers"; exit 1; }
if [ -n "$(git -C "$root" status --porcelain --untracked-files=no)" ]; then
    say "note: the checkout has uncommitted changes; the kit is built from HEAD"
fi
commit=$(git -C "$root" rev-parse HEAD)

say "cloning $commit to $prefix/src"
rm -rf "$prefix"
mkdir -p "$prefix"
git clone --quiet --no-checkout "$root" "$prefix/src"
git -C "$prefix/src" checkout --quiet --detach "$commit"

say "building (Release) in $prefix/build"
cmake -S "$prefix/src" -B "$prefix/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$prefix/build" -j "$jobs" --target "${programs[@]}" "${test_programs[@]}" >/dev/null

# The staging tree, laid out as gpu_check.sh unpacks it into $prefix: build/ (the programs where the build put
# them, stripped, and every ctest file), lib/, layers/, models/, shared/.
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
(cd "$prefix/build" && find . -name CTestTestfile.cmake -o -name '*_include.cmake' -o -name '*_tests.cmake') |
    while read -r f; do mkdir -p "$stage/build/$(dirname "$f")" && cp "$prefix/build/$f" "$stage/build/$f"; done
binaries=()
for p in "${programs[@]}"; do binaries+=("build/$p"); done
for p in "${test_programs[@]}"; do binaries+=("build/tests/$p"); done
for b in "${binaries[@]}"; do
    strip -o "$stage/$b" "$prefix/$b"
done

# Shared libraries: what the programs and the layer load, less the C and C++ runtimes (the GPU machine's own,
# newer ones serve) and the Vulkan loader (from debs/, installed there system-wide).
mkdir -p "$stage/lib" "$stage/layers"
ldd "${binaries[@]/#/$prefix/}" "$layer" | awk '$2 == "=>" && $3 ~ /^\// { print $3 }' | sort -u |
    grep -Ev '/(libc|libm|libdl|libpthread|librt|libresolv|libstdc\+\+|libgcc_s|libvulkan)\.so' |
    while read -r lib; do cp -L "$lib" "$stage/lib/"; done
cp "$layer" "$stage/layers/"
python3 - "$stage/layers" <<'EOF'
import json, sys
manifest = json.load(open("/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json"))
manifest["layer"]["library_path"] = "./libVkLayer_khronos_validation.so"  # beside the manifest
json.dump(manifest, open(sys.argv[1] + "/VkLayer_khronos_validation.json", "w"), indent=1)
EOF
# The tests of third-party scenes look for them beside the source tree, as here.
if [ -d "$root/../shared/scenes-real" ]; then
    mkdir -p "$stage/shared" && cp -r "$root/../shared/scenes-real" "$stage/shared/"
else
    say "note: no ../shared/scenes-real beside the checkout; the tests of third-party scenes will be skipped there"
fi
if [ -f "$engine" ]; then
    mkdir -p "$stage/models" && cp "$engine" "$stage/models/"
else
    say "note: no 2CylinderEngine (Debian's assimp-testmodels); the benchmark suite there will go without it"
fi

# The Vulkan loader and glvnd as .deb files, as the GPU machine's notes ask (the same packages gpu_check.sh
# unpacks with dpkg -x when that machine has no libvulkan.so.1).
rm -rf "$kit/debs" && mkdir -p "$kit/debs"
(cd "$kit/debs" && apt-get download -q -o APT::Sandbox::User=root \
    libvulkan1 libglvnd0 libegl1 libgl1 libglx0 libopengl0 libgles2 >/dev/null) ||
    { say "apt-get download of the Vulkan loader failed"; exit 1; }

say "compressing"
parts=(build lib layers)
[ -d "$stage/models" ] && parts+=(models)
[ -d "$stage/shared" ] && parts+=(shared)
tar -C "$stage" -cf - "${parts[@]}" | xz -9 -T0 >"$kit/vkrt-gpu-kit.tar.xz"
python3 - "$kit" "$stage" "$commit" "$prefix" <<'EOF'
import json, os, sys, time
kit, stage, commit, prefix = sys.argv[1:5]
files = sorted(os.path.relpath(os.path.join(d, f), stage) for d, _, names in os.walk(stage) for f in names)
json.dump({"commit": commit, "prefix": prefix, "made": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
           "archive": "vkrt-gpu-kit.tar.xz", "debs": sorted(os.listdir(os.path.join(kit, "debs"))),
           "files": files},
          open(os.path.join(kit, "manifest.json"), "w"), indent=1)
EOF
say "done: $kit ($(du -sh "$kit" | cut -f1))"
say "on the GPU machine, in the repository's root: tools/gpu_check.sh --kit ${kit#$root/} [OUT_DIR]"
