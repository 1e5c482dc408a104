#!/usr/bin/env bash
# cpack -G DEB makes semantic-mapper_<version>_amd64.deb holding the programs, the libraries, the
# model, config/, the headers and the CMake package, with its run-time dependencies declared; dpkg
# unpacks it into a fresh root (an empty dpkg database: what a new machine has, less the
# dependencies, which are this machine's), and the semantic-mapper it installed runs the main job
# on 20 frames of the sample it installed.
# Usage: debian_package.sh BUILD_DIR WORK_DIR
set -euo pipefail
build="$1"
work="$2"
for tool in cpack dpkg dpkg-deb dpkg-shlibdeps; do
    command -v "$tool" >/dev/null || { echo "SKIP: $tool not found (apt-get install dpkg-dev)"; exit 77; }
done
rm -rf "$work"
mkdir -p "$work"
cpack --config "$build/CPackConfig.cmake" -G DEB -B "$work/package" >"$work/cpack.log" 2>&1 ||
    { cat "$work/cpack.log"; echo "FAIL: cpack"; exit 1; }
deb=$(ls "$work"/package/semantic-mapper_*_amd64.deb)
echo "$(basename "$deb"): $(du -k "$deb" | cut -f1) KiB"
dpkg-deb -c "$deb" | awk '{print $6}' >"$work/contents.txt"
for f in ./usr/bin/semantic-mapper ./usr/bin/smap-eval ./usr/lib/libsmap_pipeline.so \
    ./usr/lib/libsmap_maps_plugin.so \
    ./usr/share/semantic-mapper/models/espnetv2-voc/espnetv2_s2.0_voc_320x240.onnx \
    ./usr/share/semantic-mapper/config/default.ini \
    ./usr/share/semantic-mapper/rawlogs/sample_walking_xyz.rawlog \
    ./usr/include/smap/pipeline/SemanticMapper.h ./usr/include/smap/maps/CSemanticOctoMap.h \
    ./usr/lib/cmake/semantic_mapper/semantic_mapperConfig.cmake \
    ./usr/lib/cmake/semantic_mapper/semantic_mapperTargets.cmake \
    ./usr/share/doc/semantic-mapper/embedding.md \
    ./usr/share/doc/semantic-mapper/examples/CMakeLists.txt; do
    grep -qxF "$f" "$work/contents.txt" || { echo "FAIL: $f is not in the package"; exit 1; }
done
depends=$(dpkg-deb -f "$deb" Depends)
for d in libmrpt-obs2.5 libopencv-dnn406 liboctomap1.9 libc6; do
    echo "$depends" | grep -q "$d" || { echo "Depends: $depends"; echo "FAIL: $d not declared"; exit 1; }
done

root="$work/root"
mkdir -p "$root/var/lib/dpkg/info" "$root/var/lib/dpkg/updates"
touch "$root/var/lib/dpkg/status"
dpkg --root="$root" --force-depends --force-not-root --log=/dev/null --unpack "$deb" >/dev/null
dpkg --root="$root" -l semantic-mapper | grep -q "^iU  semantic-mapper" ||
    { dpkg --root="$root" -l; echo "FAIL: dpkg does not list the unpacked package"; exit 1; }
out=$(cd "$work" && "$root/usr/bin/semantic-mapper" --out "$work/out" --set input.max_frames=20 \
    --set output.snapshots=false 2>&1) || { echo "$out"; echo "FAIL: semantic-mapper"; exit 1; }
echo "$out" | grep -qF "loaded $root/usr/share/semantic-mapper/models/" ||
    { echo "$out"; echo "FAIL: the packaged model was not loaded"; exit 1; }
grep -q '"frames": 20' "$work/out/metrics.json" || { echo "FAIL: metrics.json"; exit 1; }
echo "the package's semantic-mapper ran the sample from $root/usr"
