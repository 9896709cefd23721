# Shell functions of the peer benchmarks (bench/phantom_kernel_bench.sh,
# bench/swift_kernel_bench.sh, bench/gadget4_kernel_bench.sh), sourced by them.

# A path as the caller named it, absolute (the scripts then work from the
# repository's root).
absolute() { case $1 in /*) echo "$1" ;; *) echo "$PWD/$1" ;; esac; }
# The machine's load averages over 1, 5 and 15 minutes.
load() { cut -d' ' -f1-3 /proc/loadavg; }
# The median of the numbers on standard input, one a line; nan if any is nan
# (a timing the stock file cannot give).
median() {
  sort -g | awk '{a[NR] = $1; if ($1 ~ /nan/) nan = 1}
                 END {if (nan) print "nan"; else print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'
}
# The host and the compiler that builds the drivers, for a table's head: host_line COMPILER.
host_line() { echo "Host: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores; $("$1" --version | head -1)."; }
# A peer tree's commit, or that it has none (a snapshot without .git): tree_revision DIR.
tree_revision() { git -C "$1" rev-parse --short HEAD 2>/dev/null || echo "an unversioned tree"; }
# The word after KEY in a line "KEY value KEY value ...".
field() { awk -v k="$1" '{for (i = 1; i < NF; ++i) if ($i == k) print $(i + 1)}'; }
# |a - b| / |b|, for the two headers' or modules' sums.
relative_difference() { awk -v a="$1" -v b="$2" 'BEGIN {d = (a - b) / b; printf "%.1e", d < 0 ? -d : d}'; }
# a / b to two decimals; "—" where either is nan.
ratio() { case "$1$2" in *nan*) echo "—" ;; *) awk -v a="$1" -v b="$2" 'BEGIN {printf "%.2f", a / b}' ;; esac; }
# The table to OUT whole or not at all (a temporary file, then renamed), or
# to standard output without OUT: write_out OUT FUNCTION.
write_out() {
  if [ -n "$1" ]; then
    "$2" > "$1.tmp.$$"
    mv "$1.tmp.$$" "$1"
    echo "wrote $1"
  else
    "$2"
  fi
}
# peer_arguments NAME TREE_NAME MARKER COMPILER ARGS...: a peer benchmark's
# arguments TREE MOLLIFY_GEN [ROUNDS [OUT.md]] checked (a message naming the
# bad one, exit 2), made absolute, as tree, gen, rounds (3 by default) and
# out; then into the repository's root, where the benchmark works.
peer_arguments() {
  local name=$1 tree_name=$2 marker=$3 compiler=$4
  shift 4
  if [ $# -lt 2 ]; then
    echo "usage: bench/$name.sh $tree_name MOLLIFY_GEN [ROUNDS [OUT.md]]" >&2
    exit 2
  fi
  tree=$1 gen=$2 rounds=${3:-3} out=${4:-}
  [ -f "$tree/$marker" ] || { echo "$name: no source tree at $tree ($marker)" >&2; exit 2; }
  [ -x "$gen" ] || { echo "$name: not an executable: $gen" >&2; exit 2; }
  case $rounds in '' | *[!0-9]* | 0) echo "$name: ROUNDS must be a positive integer, not '$rounds'" >&2; exit 2 ;; esac
  command -v "$compiler" > /dev/null || { echo "$name: $compiler is needed" >&2; exit 2; }
  tree=$(absolute "$tree") gen=$(absolute "$gen")
  [ -z "$out" ] || out=$(absolute "$out")
  cd "$(dirname "${BASH_SOURCE[0]}")/../.."
}
# alternate_headers NAME SPEC STOCK_LABEL STOCK_BINARY MOLLIFY_BINARY ROWS SUMMARY:
# the two binaries of one kernel run alternating $rounds times, each printing
# "KEY value ..." with the caller's $timings keys (ns a point) and sum_w; a
# row of ROWS per run with the load before and after it, then a row of
# SUMMARY: for each timing the two medians and mollify over the stock, and
# the first round's sums' relative difference.
alternate_headers() {
  local name=$1 spec=$2 stock_label=$3 rows=$6 summary=$7 scratch r side line before after key row
  local -A binary=([s]=$4 [m]=$5)
  scratch=$(mktemp -d)
  for ((r = 1; r <= rounds; ++r)); do
    for side in s m; do
      before=$(load)
      line=$("${binary[$side]}")
      after=$(load)
      row="| $name | $r | $([ $side = s ] && echo "$stock_label" || echo "mollify $spec") |"
      for key in "${timings[@]}"; do
        echo "$line" | field "$key" >> "$scratch/${key}_$side"
        row+=" $(echo "$line" | field "$key") |"
      done
      echo "$row $(echo "$line" | field sum_w) | $before | $after |" >> "$rows"
      [ "$r" -gt 1 ] || echo "$line" | field sum_w > "$scratch/w_$side"
    done
  done
  row="| $name | $spec |"
  for key in "${timings[@]}"; do
    local ms mm
    ms=$(median < "$scratch/${key}_s") mm=$(median < "$scratch/${key}_m")
    row+=" $ms | $mm | $(ratio "$mm" "$ms") |"
  done
  echo "$row $(relative_difference "$(cat "$scratch/w_s")" "$(cat "$scratch/w_m")") |" >> "$summary"
  rm -rf "$scratch"
}
# compare_kernels STOCK_LABEL STOCK_FILE EMITTED_DIR PREFIX SUFFIX ROWS SUMMARY:
# for each "name macro spec" of the caller's $kernels, the stock STOCK_FILE
# ({name} replaced by the kernel's name) and mollify's
# EMITTED_DIR/<PREFIX><spec as an identifier>_D3<SUFFIX>, each built by the
# caller's `build BINARY FILE MACRO` into $work, then alternate_headers.
compare_kernels() {
  local stock_label=$1 stock=$2 emitted=$3 prefix=$4 suffix=$5 rows=$6 summary=$7 k name macro spec id
  : > "$rows"
  : > "$summary"
  for k in "${kernels[@]}"; do
    read -r name macro spec <<< "$k"
    id=$(ls "$emitted" | grep -i -F -x "$prefix$(echo "$spec" | sed 's/[:=,-]/_/g')_D3$suffix" || true)
    [ -n "$id" ] || { echo "mollify-gen wrote no file for $spec in $emitted" >&2; exit 1; }
    build "$work/s_$name" "${stock//\{name\}/$name}" "$macro"
    build "$work/m_$name" "$emitted/$id" "$macro"
    alternate_headers "$name" "$spec" "${stock_label//\{name\}/$name}" "$work/s_$name" "$work/m_$name" "$rows" "$summary"
  done
}
