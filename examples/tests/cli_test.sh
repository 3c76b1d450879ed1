#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Command-line checks of the example programs, run by ctest.
#
#   cli_test.sh bad PROG ARGS...         bad input: exit 2, one line on stderr, nothing on
#                                        stdout, no output file (PROG runs with --out FILE first)
#   cli_test.sh help PROG                --help: exit 0, usage on stdout
#   cli_test.sh regress PROG EXPECTED ARGS...
#                                        exit 0 and the CSV equals EXPECTED: same header and rows,
#                                        every number but newton_iters within
#                                        |a - b| <= 1e-10 max(|a|, |b|) + 1e-13
#   cli_test.sh bound PROG EXPR TMIN LIMIT ARGS...
#                                        exit 0 and |EXPR| < LIMIT on every row with t >= TMIN;
#                                        EXPR is awk with the CSV columns as v["name"]
#   cli_test.sh fail PROG ARGS...        a failure mid-run: exit 1, one line on stderr naming the
#                                        step, the header and the rows so far kept in the file
#   cli_test.sh agree PROG OTHER PAIRS TOL ARGS...
#                                        PROG and OTHER both run with ARGS, exit 0, the same
#                                        rows (t); PAIRS "a=b,c=d" names a column of PROG and
#                                        the column of OTHER it must equal within |a - b| < TOL
#   cli_test.sh advance PROG X Y MIN ARGS...
#                                        exit 0 and the angle of (v[X], v[Y]), continued from
#                                        row to row, advances by more than MIN (radians)
#   cli_test.sh block MARKDOWN HEADING FILE
#                                        the first ```c block after the line HEADING in
#                                        MARKDOWN equals FILE without its first (SPDX) line
#   cli_test.sh value PROG CODE KEY WANT TOL ARGS...
#                                        exit CODE and a line "KEY: v" on stdout with
#                                        |v - WANT| <= TOL
# STABDAE_EMULATOR, when set, runs PROG and OTHER (a cross build's programs under qemu-user:
# CMAKE_CROSSCOMPILING_EMULATOR, which ctest applies only to a test's own command).
set -u
mode=$1
prog=$2
shift 2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
out=$dir/out.csv

die() {
  echo "FAIL: $*" >&2
  exit 1
}

# the CSV as awk sees it: v[name] holds the current row's columns
awk_with_columns() {
  awk -F, -v OFS=, "NR == 1 { for (i = 1; i <= NF; i++) name[i] = \$i; next }
    { for (i = 1; i <= NF; i++) v[name[i]] = \$i + 0 } $1" "$2"
}

case $mode in
bad)
  ${STABDAE_EMULATOR:-} "$prog" --out "$out" "$@" >"$dir/stdout" 2>"$dir/stderr"
  rc=$?
  cat "$dir/stderr" >&2
  [ "$rc" -eq 2 ] || die "exit code $rc, expected 2"
  [ "$(wc -l <"$dir/stderr")" -eq 1 ] || die "stderr is not exactly one line"
  [ -s "$dir/stdout" ] && die "output on stdout"
  [ -e "$out" ] && die "output file left behind"
  exit 0
  ;;
help)
  ${STABDAE_EMULATOR:-} "$prog" --help >"$dir/stdout" 2>"$dir/stderr" || die "exit code $?"
  grep -q '^usage:' "$dir/stdout" || die "no usage on stdout"
  exit 0
  ;;
regress)
  expected=$1
  shift
  ${STABDAE_EMULATOR:-} "$prog" --out "$out" "$@" || die "exit code $?"
  [ "$(head -n 1 "$out")" = "$(head -n 1 "$expected")" ] || die "headers differ"
  [ "$(wc -l <"$out")" -eq "$(wc -l <"$expected")" ] || die "row counts differ"
  paste -d '|' "$out" "$expected" | awk -F'|' 'NR > 1 {
      n = split($1, a, ","); split($2, b, ",")
      for (i = 1; i < n; i++) {   # the last column, newton_iters, depends on the solver
        x = a[i] + 0; y = b[i] + 0; d = x - y; if (d < 0) d = -d
        s = (x < 0 ? -x : x); t = (y < 0 ? -y : y); if (t > s) s = t
        if (d > 1e-10 * s + 1e-13) {
          printf "row %d column %d: %s vs %s\n", NR, i, a[i], b[i]; bad = 1
        }
      } } END { exit bad }' || die "values differ from $expected"
  exit 0
  ;;
bound)
  expr=$1 tmin=$2 limit=$3
  shift 3
  ${STABDAE_EMULATOR:-} "$prog" --out "$out" "$@" || die "exit code $?"
  awk_with_columns "v[\"t\"] >= $tmin - 1e-12 { r = $expr; if (r < 0) r = -r; n++
      if (r > worst) worst = r; if (!(r < $limit)) bad = 1 }
    END { printf \"%.3g over %d rows\\n\", worst, n; exit (bad || n == 0) }" "$out" \
    >"$dir/bound" || die "bound $limit violated: max |$expr| = $(cat "$dir/bound") (t >= $tmin)"
  echo "max |$expr| for t >= $tmin: $(cat "$dir/bound") (limit $limit)"
  exit 0
  ;;
fail)
  ${STABDAE_EMULATOR:-} "$prog" --out "$out" "$@" 2>"$dir/stderr"
  rc=$?
  cat "$dir/stderr" >&2
  [ "$rc" -eq 1 ] || die "exit code $rc, expected 1"
  [ "$(wc -l <"$dir/stderr")" -eq 1 ] || die "stderr is not exactly one line"
  grep -q 'step [0-9]' "$dir/stderr" || die "the message does not name the step"
  [ "$(wc -l <"$out")" -ge 2 ] || die "the rows computed so far were not kept"
  exit 0
  ;;
agree)
  other=$1 pairs=$2 tol=$3
  shift 3
  ${STABDAE_EMULATOR:-} "$prog" --out "$out" "$@" || die "exit code $?"
  ${STABDAE_EMULATOR:-} "$other" --out "$dir/other.csv" "$@" || die "$other: exit code $?"
  awk -F, -v pairs="$pairs" -v tol="$tol" '
    FNR == 1 { for (i = 1; i <= NF; i++) col[FILENAME == ARGV[1], $i] = i; next }
    FILENAME == ARGV[1] { for (i = 1; i <= NF; i++) a[FNR, i] = $i; rows = FNR; next }
    { if (a[FNR, 1] != $1) { printf "row %d: t = %s vs %s\n", FNR, a[FNR, 1], $1; bad = 1 }
      n = split(pairs, p, ",")
      for (k = 1; k <= n; k++) {
        split(p[k], ab, "="); d = a[FNR, col[1, ab[1]]] - $(col[0, ab[2]]); if (d < 0) d = -d
        if (d > worst[k]) worst[k] = d
        if (!(d < tol)) bad = 1 } }
    END { if (FNR != rows) { print "row counts differ"; bad = 1 }
      for (k = 1; k <= n; k++) printf "max |%s| = %.3g\n", p[k], worst[k]; exit bad }' \
    "$out" "$dir/other.csv" || die "the programs differ by more than $tol"
  exit 0
  ;;
advance)
  x=$1 y=$2 min=$3
  shift 3
  ${STABDAE_EMULATOR:-} "$prog" --out "$out" "$@" || die "exit code $?"
  awk_with_columns "{ a = atan2(v[\"$y\"], v[\"$x\"]); pi = atan2(0, -1)
      if (n++) { d = a - prev; while (d > pi) d -= 2 * pi; while (d < -pi) d += 2 * pi; sum += d }
      prev = a }
    END { printf \"%.6g over %d rows\\n\", sum, n; exit !(sum > $min || -sum > $min) }" "$out" \
    >"$dir/advance" || die "the angle advanced by $(cat "$dir/advance"), not more than $min"
  echo "the angle of ($x, $y) advanced by $(cat "$dir/advance") (more than $min)"
  exit 0
  ;;
block)
  heading=$1 file=$2
  awk -v h="$heading" '$0 == h { found = 1; next }
    found && !inside && /^```c$/ { inside = 1; next }
    inside && /^```$/ { exit }
    inside { print }' "$prog" >"$dir/block"
  tail -n +2 "$file" | diff -u - "$dir/block" >&2 || die "the block under '$heading' differs from $file"
  exit 0
  ;;
value)
  code=$1 key=$2 want=$3 tol=$4
  shift 4
  ${STABDAE_EMULATOR:-} "$prog" "$@" >"$dir/stdout" 2>"$dir/stderr"
  rc=$?
  cat "$dir/stdout" "$dir/stderr" >&2
  [ "$rc" -eq "$code" ] || die "exit code $rc, expected $code"
  v=$(sed -n "s/^$key: \([^ ]*\).*/\1/p" "$dir/stdout")
  [ -n "$v" ] || die "no line '$key: ...'"
  awk -v v="$v" -v w="$want" -v t="$tol" 'BEGIN { d = v - w; if (d < 0) d = -d; exit !(d <= t) }' ||
    die "$key is $v, expected $want within $tol"
  exit 0
  ;;
*)
  die "unknown mode $mode"
  ;;
esac
