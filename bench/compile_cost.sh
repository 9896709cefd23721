#!/usr/bin/env bash
# compile_cost.sh [--runs N] [--header H] [--out FILE]
#
# The compile cost of one StaticKernel (issue 18's goal: at most 2x the time
# and memory of the same unit without mollify). Compiles
# bench/compile_cost_unit.cpp with the project's flags (-std=c++20 -O2 -Wall
# -Wextra -Werror -fno-math-errno, object file only) with mollify (its table
# header H, default the per-kernel header mollify/tables/wendland/k_2_D3.hpp
# where it exists, else the family header mollify/tables/wendland.hpp) and
# without (the baseline: <cmath>, <array>, <span>, <cstdio>), N times each
# (default 5), alternating so that a change of the machine's load falls on
# both alike. /usr/bin/time measures wall time, CPU time (user + system) and
# max RSS of each compile; prints a Markdown table of the medians, the
# ratios, the load averages before and after (/proc/loadavg: the machine is
# shared), and writes it to FILE (default bench/results/compile_cost.md).
#
# Environment: CXX (default c++).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
runs=5 header="" out=$here/results/compile_cost.md
usage() {
    echo "usage: $0 [--runs N] [--header mollify/tables/...hpp] [--out FILE]" >&2
    exit 2
}
while [ $# -gt 0 ]; do
    case $1 in
    --runs) [ $# -ge 2 ] || usage; runs=$2; shift 2 ;;
    --header) [ $# -ge 2 ] || usage; header=$2; shift 2 ;;
    --out) [ $# -ge 2 ] || usage; out=$2; shift 2 ;;
    *) echo "$0: unknown argument '$1'" >&2; usage ;;
    esac
done
[[ $runs =~ ^[1-9][0-9]*$ ]] || { echo "$0: --runs '$runs' is not a positive integer" >&2; exit 2; }
if [ -z "$header" ]; then
    header=mollify/tables/wendland/k_2_D3.hpp
    [ -f "$root/generated/$header" ] || header=mollify/tables/wendland.hpp
fi
[ -f "$root/generated/$header" ] || { echo "$0: --header '$header' is not in $root/generated/" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "$0: /usr/bin/time (Debian package time) is needed" >&2; exit 2; }
cxx=${CXX:-c++}

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
flags=(-std=c++20 -O2 -Wall -Wextra -Werror -fno-math-errno -c "$here/compile_cost_unit.cpp")
mollify_flags=(-I"$root/include" -I"$root/generated" "-DMOLLIFY_TABLE_HEADER=<$header>")

measure() {  # NAME FLAGS...: appends "wall cpu rss_kb" to $tmp/NAME
    local name=$1
    shift
    /usr/bin/time -f "%e %U %S %M" -o "$tmp/time" "$cxx" "${flags[@]}" "$@" -o "$tmp/$name.o"
    read -r wall user sys rss < "$tmp/time"
    echo "$wall $(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }') $rss" >> "$tmp/$name"
}

median() {  # FILE COLUMN
    cut -d' ' -f"$2" "$1" | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}

load_before=$(cut -d' ' -f1-3 /proc/loadavg)
for ((i = 0; i < runs; ++i)); do
    measure baseline
    measure mollify "${mollify_flags[@]}"
done
load_after=$(cut -d' ' -f1-3 /proc/loadavg)

row() {  # NAME LABEL
    printf '| %s | %.2f | %.2f | %.0f |\n' "$2" "$(median "$tmp/$1" 1)" "$(median "$tmp/$1" 2)" \
        "$(awk -v kb="$(median "$tmp/$1" 3)" 'BEGIN { print kb / 1024 }')"
}
ratio() {  # COLUMN
    awk -v a="$(median "$tmp/mollify" "$1")" -v b="$(median "$tmp/baseline" "$1")" 'BEGIN { print a / b }'
}
preprocessed=$("$cxx" -std=c++20 -E "$here/compile_cost_unit.cpp" "${mollify_flags[@]}" | wc -c)

{
    echo "Compile cost of one \`StaticKernel\` (\`bench/compile_cost.sh\`, $(date -u '+%Y-%m-%d %H:%M UTC')):"
    echo "\`bench/compile_cost_unit.cpp\` compiled to an object file with \`-std=c++20 -O2\` ($($cxx --version | head -n 1)),"
    echo "with \`<$header>\` ($(du -k "$root/generated/$header" | cut -f1) kB; $((preprocessed / 1024)) kB preprocessed) and without mollify"
    echo "(\`<cmath>\`, \`<array>\`, \`<span>\`, \`<cstdio>\` only); medians of $runs runs each, alternating."
    echo "Machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores, shared;"
    echo "load average (1, 5, 15 min) $load_before before, $load_after after."
    echo
    echo "| unit | wall s | CPU s | max RSS MB |"
    echo "|---|---:|---:|---:|"
    row baseline "without mollify"
    row mollify "one StaticKernel"
    printf '| **ratio** (goal <= 2) | **%.2f** | **%.2f** | **%.2f** |\n' "$(ratio 1)" "$(ratio 2)" "$(ratio 3)"
} > "$tmp/table.md"

cat "$tmp/table.md"
mkdir -p "$(dirname "$out")"
cp "$tmp/table.md" "$out.tmp.$$"
mv "$out.tmp.$$" "$out"
echo "wrote $out" >&2
