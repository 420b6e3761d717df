#!/usr/bin/env bash
# Renders every picture in the README with the command the README shows beside it (the CPU reference; the GPU
# renders the same images, as the tests check). Usage: [VKRT=build/vkrt] tools/readme_pictures.sh [OUT_DIR]
# (default docs/images); the gallery of third-party assets needs ../shared/scenes-real and is skipped without it.
set -euo pipefail
case "${1:-}" in
    -h | --help) sed -n '2,4s/^# \{0,1\}//p' "$0"; exit 0 ;;
    -*) echo "readme_pictures: unknown option $1 (see --help)" >&2; exit 2 ;;
esac
# OUT_DIR and VKRT as given are relative to the folder it was run from; the defaults to the repository.
out=${1:+$(realpath -m -- "$1")}
binary=${VKRT:+$(realpath -m -- "$VKRT")}
cd "$(dirname "$0")/.."
out=${out:-docs/images}
binary=${binary:-build/vkrt}
mkdir -p "$out/gallery"
vkrt() { nice "$binary" --device cpu --quiet "$@"; }
sky=(--background 0.35,0.55,0.9)

# The Cornell box, path traced (the default) and by Whitted's integrator with its ambient term.
vkrt --scene scenes/cornell.gltf --width 512 --spp 1024 --out "$out/cornell-cpu.png"
vkrt --scene scenes/cornell.gltf --width 512 --spp 64 --integrator whitted --out "$out/cornell-whitted-cpu.png"

vkrt --scene scenes/whitted.gltf --width 512 --spp 256 "${sky[@]}" --out "$out/whitted-cpu.png"
vkrt --scene scenes/lights.gltf --width 512 --spp 256 --out "$out/lights-cpu.png"
vkrt --scene scenes/many-lights.gltf --width 512 --spp 256 --light-samples 4 --out "$out/many-lights-cpu.png"
vkrt --scene scenes/dof.gltf --width 512 --spp 256 --out "$out/dof-cpu.png"
vkrt --scene scenes/glossy.gltf --width 512 --spp 256 --light-samples 2 --out "$out/glossy-cpu.png"
vkrt --scene scenes/motion-blur.gltf --width 512 --spp 256 --out "$out/motion-blur-cpu.png"
vkrt --scene scenes/textures.gltf --width 512 --spp 256 "${sky[@]}" --out "$out/textures-cpu.png"
vkrt --scene scenes/environment.gltf --width 512 --spp 256 --environment scenes/sky.hdr \
    --environment-rotation 40 --environment-strength 1.5 --out "$out/environment-cpu.png"
vkrt --scene scenes/outdoor.gltf --width 512 --spp 256 --environment scenes/soft-sky.hdr --out "$out/outdoor-cpu.png"
# Beside Cycles' image of it (tests/references/README.md makes docs/images/outdoor-cycles.png): the sRGB curve,
# clamped, as Blender's Standard view transform.
vkrt --scene scenes/outdoor.gltf --width 128 --spp 1024 --environment scenes/soft-sky.hdr --tonemap clamp \
    --out "$out/outdoor-128-cpu.png"
vkrt --scene scenes/rough.gltf --width 192 --height 96 --spp 1024 --environment scenes/soft-sky.hdr --tonemap clamp \
    --out "$out/rough-192-cpu.png"
vkrt --scene scenes/tinted.gltf --width 128 --spp 1024 --environment scenes/soft-sky.hdr --tonemap clamp \
    --out "$out/tinted-128-cpu.png"
vkrt --scene scenes/lens.gltf --width 192 --spp 1024 --environment scenes/soft-sky.hdr --tonemap clamp \
    --out "$out/lens-192-cpu.png"
vkrt --scene scenes/lamps.gltf --width 128 --spp 1024 --tonemap clamp --out "$out/lamps-128-cpu.png"
vkrt --scene scenes/punctual.gltf --width 128 --spp 1024 --tonemap clamp --out "$out/punctual-128-cpu.png"
vkrt --scene scenes/streaks.gltf --width 192 --spp 1024 --tonemap clamp --out "$out/streaks-192-cpu.png"
vkrt --scene scenes/spots.gltf --width 128 --spp 1024 --tonemap clamp --out "$out/spots-128-cpu.png"
vkrt --scene scenes/surfaces.gltf --width 512 --spp 256 "${sky[@]}" --out "$out/surfaces-cpu.png"
vkrt --scene scenes/csg.gltf --width 512 --spp 256 --out "$out/csg-cpu.png"
vkrt --scene scenes/studio.gltf --width 512 --spp 16 --integrator whitted --out "$out/studio-whitted-cpu.png"
vkrt --scene scenes/studio.gltf --width 512 --spp 64 --out "$out/studio-cpu.png"
vkrt --scene scenes/deform.gltf --width 512 --spp 256 "${sky[@]}" --out "$out/deform-cpu.png"
vkrt --scene scenes/deform.gltf --width 512 --spp 256 "${sky[@]}" --shutter 0 1 --out "$out/deform-motion-cpu.png"

real=../shared/scenes-real
if [ -d "$real" ]; then
    asset() { vkrt --scene "$real/$1" --width 320 --height 320 --spp 256 --environment scenes/sky.hdr --out "$out/gallery/$2"; }
    asset khronos-NormalTangentTest/glTF/NormalTangentTest.gltf normal-tangent-test-cpu.png
    asset khronos-Avocado/glTF/Avocado.gltf avocado-cpu.png
    asset khronos-TransmissionRoughnessTest/TransmissionRoughnessTest.glb transmission-roughness-test-cpu.png
else
    echo "readme_pictures: $real is missing; the gallery is not rendered" >&2
fi
