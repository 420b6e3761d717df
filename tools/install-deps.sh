#!/usr/bin/env bash
# Installs everything vkrt needs to build, render and test on Debian 12, from Debian's own packages.
set -euo pipefail
packages=(
    cmake g++ make pkg-config python3
    libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools  # loader, lavapipe, validation
    glslang-dev glslang-tools spirv-tools                                   # run-time GLSL -> SPIR-V
    libglm-dev libtinygltf-dev nlohmann-json3-dev libstb-dev libtinyexr-dev # math, glTF, JSON, images
    libmeshoptimizer-dev libdraco-dev libwebp-dev                           # compressed meshes, WebP textures
    libcli11-dev                                                            # command line
    libgtest-dev                                                            # tests
    libopenmpi-dev openmpi-bin                                              # one render across processes (optional)
    clang libfuzzer-14-dev                                                  # fuzzing the loader
    libembree-dev                                                           # benchmark anchor (optional)
)
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update
$sudo apt-get install -y --no-install-recommends "${packages[@]}"
