#!/usr/bin/env bash
# Checks the libraries' link graph against docs/architecture.md: every smap library reaches
# (transitively, through CMake links) only the libraries below it.
#   scripts/check-link-graph.sh [BUILD_DIR]
# Prints each library's smap dependencies; exits 1 on a link that the design forbids.
set -euo pipefail
build=$(cd "${1:-build}" && pwd)
work=$(mktemp -d)
trap 'rm -rf "${work}"' EXIT
(cd "${work}" && cmake --graphviz=graph.dot "${build}" >/dev/null)

declare -A allowed=(
    [core]=""
    [io]="core"
    [eval]="core"
    [features]="core"
    [segmentation]="core"
    [maps]="core"
    [sim]="core io"
    [mapping]="core maps segmentation"
    [dynamic]="core features"
    [slam]="core features dynamic"
    [pipeline]="core io features dynamic slam segmentation maps mapping"
    [apps]="core io eval sim features dynamic slam segmentation maps mapping pipeline"
)

status=0
for lib in core io eval features segmentation maps sim mapping dynamic slam pipeline apps; do
    dot="${work}/graph.dot.smap_${lib}"
    [ -f "${dot}" ] || { echo "check-link-graph: no target smap_${lib}" >&2; exit 2; }
    reached=$(grep -o '(smap::[a-z]*)' "${dot}" | tr -d '()' | sed 's/smap:://' |
              { grep -vx "${lib}" || true; } | sort -u | tr '\n' ' ')
    printf '%-13s -> %s\n' "${lib}" "${reached:-(none)}"
    for dep in ${reached}; do
        if ! grep -qw "${dep}" <<<"${allowed[${lib}]}"; then
            echo "check-link-graph: smap::${lib} must not link smap::${dep}" >&2
            status=1
        fi
    done
done
exit ${status}
