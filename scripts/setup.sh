#!/usr/bin/env bash
# Installs what building, running and testing need on Debian 12 / Ubuntu 22.04+:
# the Vulkan loader, Mesa's lavapipe (a CPU Vulkan device), the Khronos validation layer,
# and the shaderc / glslang / SPIRV-Tools static libraries that build.rs links
# (see README, "Shader compiler"). Safe to run again.
set -euo pipefail
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
packages=(
    libvulkan1 libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers
    libshaderc-dev glslang-dev spirv-tools pkg-config
)
missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
    "${sudo_cmd[@]}" apt-get update
    DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y --no-install-recommends "${missing[@]}"
fi
if ! command -v cargo >/dev/null 2>&1; then
    echo "setup: cargo not found; install a Rust toolchain (rustup.rs), then run this again" >&2
    exit 1
fi
echo "setup: Vulkan, lavapipe, validation layers and shaderc are installed"
