#!/usr/bin/env bash
# Installs what building, running and testing need on Debian 12 / Ubuntu 22.04+:
# the Vulkan loader, Mesa's lavapipe (a CPU Vulkan device), the Khronos validation layer,
# and the shaderc / glslang / SPIRV-Tools static libraries that build.rs links
# (see README, "Shader compiler"); for `ocean view`, the X11 libraries winit loads at run time;
# for its tests, Xvfb (an X server without a screen), openbox (a window manager: an X server
# alone ignores minimize requests) and xprop. Safe to run again.
set -euo pipefail
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
packages=(
    libvulkan1 libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers
    libshaderc-dev glslang-dev spirv-tools pkg-config
    libx11-6 libx11-xcb1 libxcursor1 libxrandr2 libxi6 libxkbcommon-x11-0
    xvfb xauth openbox x11-utils
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
echo "setup: Vulkan, lavapipe, validation layers, shaderc, X11 libraries, Xvfb and openbox are installed"
