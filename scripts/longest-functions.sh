#!/usr/bin/env bash
# Lists the longest functions in libs/ and apps/ (Universal Ctags: first to last line of each
# function body; lambdas count inside the function that holds them).
#   scripts/longest-functions.sh [--top N] [--max LINES]
# --max makes it a check: exit 1 when any function is longer than LINES lines.
set -euo pipefail
cd "$(dirname "$0")/.."

top=20
max=""
while [ $# -gt 0 ]; do
    case "$1" in
        --top) top="$2"; shift 2 ;;
        --max) max="$2"; shift 2 ;;
        *) echo "usage: $0 [--top N] [--max LINES]" >&2; exit 2 ;;
    esac
done

if ! ctags --version 2>/dev/null | grep -q "Universal Ctags"; then
    echo "longest-functions: needs Universal Ctags (apt-get install universal-ctags)" >&2
    exit 2
fi

mapfile -t files < <(find libs apps -name '*.cpp' -o -name '*.h' | sort)
# One row per named function: lines, file:line, qualified name.
table=$(ctags --languages=C++ --c++-kinds=f --fields=+neKZ --extras=+q -x \
            --_xformat='%{line} %{end} %{input} %{scope} %{name}' "${files[@]}" |
        awk '$5 !~ /__anon/ && $2 != "" {
                 scope = ($4 == "" || $4 == "-") ? "" : $4;
                 n = split(scope, parts, ":"); owner = parts[n];
                 name = (owner == "") ? $5 : owner "::" $5;
                 if (index($5, "::") > 0) name = $5;
                 printf "%d %s:%d %s\n", $2 - $1 + 1, $3, $1, name }' |
        sort -u | sort -k1,1nr -k2,2)

awk -v n="${top}" 'NR <= n { printf "%5d  %-55s %s\n", $1, $2, $3 }' <<<"${table}"
if [ -n "${max}" ]; then
    over=$(awk -v m="${max}" '$1 > m' <<<"${table}" | wc -l)
    if [ "${over}" -gt 0 ]; then
        echo "longest-functions: ${over} function(s) longer than ${max} lines" >&2
        exit 1
    fi
    echo "longest-functions: none longer than ${max} lines"
fi
