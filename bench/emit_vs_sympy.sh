#!/usr/bin/env bash
# emit_vs_sympy.sh MOLLIFY_GEN
#
# Times `MOLLIFY_GEN emit --out <fresh temp dir>` (5 runs) against the SymPy
# reference bench/sympy_wendland.py, which computes the same normalised Wendland
# coefficients (3 runs per SymPy method, or a single run if the first one takes
# longer than 60 s), and prints a Markdown table: tool, runs, median seconds.
#
# All times are wall-clock seconds of the whole process (interpreter start-up
# and imports included), so both sides are measured the same way; the SymPy
# script's own compute time (after the imports) is listed below the table.
#
# Environment: PYTHON (default python3), SYMPY_METHODS (default "integrate poly").
set -euo pipefail

usage() {
    echo "usage: $0 MOLLIFY_GEN   (path to the mollify-gen executable)" >&2
    exit 2
}

[[ $# -eq 1 ]] || usage
gen=$1
if [[ -z $gen ]]; then
    usage
fi
if [[ -d $gen || ! -e $gen ]]; then
    echo "$0: error: mollify-gen not found: '$gen' is not a file (build it first, e.g. cmake --build build --target mollify-gen)" >&2
    exit 2
fi
if [[ ! -x $gen ]]; then
    echo "$0: error: '$gen' is not executable" >&2
    exit 2
fi

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
sympy_script=$here/sympy_wendland.py
python=${PYTHON:-python3}
methods=${SYMPY_METHODS:-integrate poly}
gen_runs=5
sympy_runs=3
sympy_slow=60

tmpdirs=()
cleanup() { ((${#tmpdirs[@]})) && rm -rf -- "${tmpdirs[@]}"; return 0; }
trap cleanup EXIT

now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.6f", b - a }'; }
median() { printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END { if (NR % 2) m = v[(NR + 1) / 2]; else m = (v[NR / 2] + v[NR / 2 + 1]) / 2; printf "%.3f", m }'; }

rows=()
notes=()

# --- mollify-gen emit: the default catalogue, and the same 75 Wendland kernels as SymPy
time_emit() {  # label, extra arguments...
    local label=$1
    shift
    local times=() out t0 t1 i
    for ((i = 1; i <= gen_runs; i++)); do
        out=$(mktemp -d)
        tmpdirs+=("$out")
        t0=$(now)
        if ! "$gen" emit --out "$out" "$@" >/dev/null; then
            echo "$0: error: '$gen emit --out $out $*' failed (run $i)" >&2
            exit 1
        fi
        t1=$(now)
        times+=("$(elapsed "$t0" "$t1")")
    done
    rows+=("| $label | ${#times[@]} | $(median "${times[@]}") |")
}
time_emit "\`mollify-gen emit\` (default catalogue, all quantities, potentials, certificates)"
wendland_only=()
for k in 0 1 2 3 4; do for l in 0 1 2 3 4; do wendland_only+=(--only "wendland:k=$k,l=$l"); done; done
time_emit "\`mollify-gen emit --only\` the 75 Wendland kernels (with potentials, certificates)" "${wendland_only[@]}"

# --- SymPy ------------------------------------------------------------------
for method in $methods; do
    times=()
    inner=()
    for ((i = 1; i <= sympy_runs; i++)); do
        t0=$(now)
        if ! line=$("$python" "$sympy_script" --method "$method"); then
            echo "$0: error: $sympy_script --method $method failed (run $i)" >&2
            exit 1
        fi
        t1=$(now)
        times+=("$(elapsed "$t0" "$t1")")
        inner+=("$(sed -n 's/^elapsed: \([0-9.]*\) s.*/\1/p' <<<"$line")")
        if ((i == 1)) && awk -v t="${times[0]}" -v s="$sympy_slow" 'BEGIN { exit !(t > s) }'; then
            break  # too slow to repeat
        fi
    done
    rows+=("| SymPy \`sympy_wendland.py --method $method\` | ${#times[@]} | $(median "${times[@]}") |")
    notes+=("- SymPy --method $method: median compute time without start-up/imports $(median "${inner[@]}") s")
done

echo "| tool | runs | median s |"
echo "|---|--:|--:|"
printf '%s\n' "${rows[@]}"
echo
echo "Wall-clock seconds per process (start-up included); SymPy computes the 75 normalised"
echo "Wendland kernels d=1..3, k=0..4, l=0..4 ($("$python" -c 'import sympy; print("sympy", sympy.__version__)'))."
printf '%s\n' "${notes[@]}"
