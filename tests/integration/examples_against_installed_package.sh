#!/usr/bin/env bash
# The examples build and run as an outside project against the installed package, as a robot
# program would: install into a fresh prefix, configure <prefix>/share/doc/semantic-mapper/
# examples with find_package(semantic_mapper) (nothing of the build or source tree on any path),
# stream the installed sample recording into the mapper, then plan on the map it saved, the maps
# first made by MRPT's map factory from the installed semantic_maps.ini.
# Usage: examples_against_installed_package.sh BUILD_DIR WORK_DIR
set -euo pipefail
build="$1"
work="$2"
rm -rf "$work"
mkdir -p "$work"
prefix="$work/prefix"
cmake --install "$build" --prefix "$prefix" >/dev/null
examples="$prefix/share/doc/semantic-mapper/examples"
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
cmake -S "$examples" -B "$work/build" "${generator[@]}" -DCMAKE_PREFIX_PATH="$prefix" \
    >"$work/configure.log" 2>&1 || { cat "$work/configure.log"; echo "FAIL: configure"; exit 1; }
cmake --build "$work/build" >"$work/build.log" 2>&1 ||
    { cat "$work/build.log"; echo "FAIL: build"; exit 1; }

sample="$prefix/share/semantic-mapper/rawlogs/sample_walking_xyz.rawlog"
(cd "$work" && "$work/build/stream_observations" "$sample" "$work/maps") >"$work/stream.log" 2>&1 ||
    { tail -20 "$work/stream.log"; echo "FAIL: stream_observations"; exit 1; }
grep -q "^frame 199: ok " "$work/stream.log" || { tail "$work/stream.log"; echo "FAIL: frame 199 has no pose"; exit 1; }
grep -qF "loaded $prefix/share/semantic-mapper/models/" "$work/stream.log" ||
    { head "$work/stream.log"; echo "FAIL: the installed model was not loaded"; exit 1; }
for f in semantic_map.bin semantic_map.3Dscene semantic_points.ply; do
    [ -s "$work/maps/$f" ] || { echo "FAIL: no $f"; exit 1; }
done

(cd "$work" && "$work/build/plan_on_semantic_map" "$work/maps/semantic_map.bin" "$work/plan.png" \
    --maps "$examples/semantic_maps.ini") >"$work/plan.log" 2>&1 ||
    { cat "$work/plan.log"; echo "FAIL: plan_on_semantic_map"; exit 1; }
cat "$work/plan.log"
grep -q "declares: smap::maps::CSemanticOctoMap smap::maps::CSemanticPointsMap" "$work/plan.log" ||
    { echo "FAIL: MRPT's map factory did not make both maps"; exit 1; }
grep -q "^path avoids every occupied cell: yes" "$work/plan.log" || { echo "FAIL: path"; exit 1; }
[ "$(head -c 8 "$work/plan.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] ||
    { echo "FAIL: plan.png is not a PNG"; exit 1; }
echo "examples built against $prefix; the planner's path avoids every occupied cell"
