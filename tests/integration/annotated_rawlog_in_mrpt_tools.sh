#!/usr/bin/env bash
# The annotated rawlog of a semantic-mapper run opens in MRPT's own tools once our classes are
# loaded: rawlog-edit (the same CRawlog reading as RawLogViewer) with libsmap_maps_plugin.so
# preloaded lists one SEMANTIC_RGBD observation per mapped keyframe; without it, none.
# Usage: annotated_rawlog_in_mrpt_tools.sh SEMANTIC_MAPPER PLUGIN WORKDIR
set -euo pipefail
mapper="$1" plugin="$2" work="$3"
if ! command -v rawlog-edit >/dev/null; then
    echo "rawlog-edit not found (Debian package mrpt-apps; scripts/install-deps.sh installs it)"
    [ "${CI:-}" = true ] && exit 1
    exit 77
fi
rm -rf "$work" && mkdir -p "$work"
"$mapper" --out "$work/out" --quiet --set input.max_frames=40 \
    --set segmentation.backend=none --set output.snapshots=false >/dev/null
mapped=$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['keyframes']['mapped'])" "$work/out/metrics.json")
echo "keyframes mapped: $mapped"
[ "$mapped" -gt 0 ]
without=$(rawlog-edit -i "$work/out/annotated.rawlog" --info 2>&1 || true)
if echo "$without" | grep -q "SEMANTIC_RGBD /"; then
    echo "unexpected: rawlog-edit read our observations without the plugin"
    exit 1
fi
with=$(LD_PRELOAD="$plugin" rawlog-edit -i "$work/out/annotated.rawlog" --info 2>&1)
echo "$with" | grep -E "Observations format|SEMANTIC_RGBD"
echo "$with" | grep -q "Observations format *: Yes"
count=$(echo "$with" | sed -n 's/.*SEMANTIC_RGBD \/ *\([0-9]*\) .*/\1/p')
[ "$count" = "$mapped" ] || { echo "rawlog-edit counted '$count' observations, expected $mapped"; exit 1; }
echo "ok: $count observations"
