#!/usr/bin/env bash
# Installs every Debian 12 package semantic-mapper needs to build, test and run. Idempotent:
# installs only what is missing. Nothing is downloaded from anywhere but Debian's archive.
set -euo pipefail

packages=(
    # toolchain
    g++ cmake ninja-build ccache pkg-config
    # libraries
    libmrpt-dev libopencv-dev libeigen3-dev libceres-dev libgtest-dev libgmock-dev libbenchmark-dev zlib1g-dev
    # the semantic OctoMap (libs/maps)
    liboctomap-dev
    # MRPT's sample recordings (tests_rgbd.rawlog is the embedded default input)
    mrpt-common
    # headless OpenGL (EGL on Mesa) for the synthetic renderer
    libegl1 libegl-mesa0 libgl1-mesa-dri
    # tests (independent ATE reference) and developer checks (format, static analysis, fuzzing)
    python3 python3-numpy clang clang-format clang-tidy libclang-rt-14-dev universal-ctags
    # MRPT's own tools, to check that they read our annotated rawlogs (rawlog-edit, RawLogViewer)
    mrpt-apps
    # packaging: cpack -G DEB computes the package's dependencies with dpkg-shlibdeps
    dpkg-dev
)

missing=()
for p in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$p")
    fi
done

if [ ${#missing[@]} -eq 0 ]; then
    echo "install-deps: all ${#packages[@]} packages present"
    exit 0
fi

if [ "$(id -u)" -eq 0 ]; then
    sudo=()
elif command -v sudo >/dev/null 2>&1; then
    sudo=(sudo)
else
    echo "install-deps: missing packages: ${missing[*]}" >&2
    echo "install-deps: not root and sudo is not available; as root run:" >&2
    echo "    apt-get update && apt-get install -y --no-install-recommends ${missing[*]}" >&2
    exit 1
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -q
"${sudo[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
