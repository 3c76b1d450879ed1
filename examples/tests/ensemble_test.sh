#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Tests of the ensemble runner over MPI (label mpi), run by ctest. The common arguments:
#   MPIRUN ENSEMBLE BINDIR PYTHON COMPARE: mpirun, the runner, the directory of the serial
#   example programs, a Python 3 and ensemble_compare.py (the held-out check).
#
#   ensemble_test.sh agree ... MODEL MEMBERS AT FLAGS...
#       P = 1, 2 (--chunk 1) and 3 (oversubscribed, --chunk 2) give the same file byte for
#       byte, and every member's row equals the serial program's numbers (ensemble_compare.py);
#       AT is the runner's --at, or - for none
#   ensemble_test.sh fail ... MODEL MEMBERS ROW FLAGS...
#       exit 0, member ROW failed (its status the program's reason), every other one ok, and
#       all of them as the serial program says
#   ensemble_test.sh bad ... MODEL MEMBERS LINE FLAGS...
#       exit 2, one message naming MEMBERS:LINE, no output file and no job file
#   ensemble_test.sh resume ... MODEL MEMBERS FLAGS...
#       the file of an uninterrupted run again from its prefixes cut anywhere (--resume), and
#       from a run killed midway; a job file of other flags refused (exit 2)
#   ensemble_test.sh certify ... MODEL WANT TOL FLAGS...
#       --certify on P = 1, 2, 3: the same lines whatever P, sup_neg_k equal to the serial
#       program's --certify within TOL relative and to WANT (by hand) within TOL relative
#   ensemble_test.sh progress ... MODEL MEMBERS FLAGS...
#       --quiet: nothing on stderr; --progress 0: a progress line per result and the last line
set -u
mode=$1 mpirun=$2 ens=$3 bindir=$4 python=$5 compare=$6 model=$7
shift 7
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
# Open MPI refuses root without these (CI runs as root); --oversubscribe: more ranks than cores
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

die() {
  echo "FAIL: $*" >&2
  exit 1
}

# run P ARGS...: the runner on P ranks
run() {
  p=$1
  shift
  "$mpirun" --oversubscribe -n "$p" "$ens" --model "$model" "$@"
}

rows() { echo $(($(wc -l <"$1") - 1)); }

case $mode in
agree)
  members=$1 at=$2
  shift 2
  [ "$at" = - ] && set -- "$@" || set -- --at "$at" "$@"
  run 1 --members "$members" --out "$dir/p1.csv" --quiet "$@" || die "P = 1: exit $?"
  run 2 --members "$members" --out "$dir/p2.csv" --quiet --chunk 1 "$@" || die "P = 2: exit $?"
  run 3 --members "$members" --out "$dir/p3.csv" --quiet --chunk 2 "$@" || die "P = 3: exit $?"
  cmp "$dir/p1.csv" "$dir/p2.csv" || die "P = 1 and P = 2 differ"
  cmp "$dir/p1.csv" "$dir/p3.csv" || die "P = 1 and P = 3 differ"
  [ "$(rows "$dir/p1.csv")" -eq "$(rows "$members")" ] || die "not a row per member"
  [ "$at" = - ] || shift 2
  "$python" "$compare" "$dir/p1.csv" "$members" "$bindir/$model" "$@" || die "not the serial numbers"
  ;;
fail)
  members=$1 row=$2
  shift 2
  run 2 --members "$members" --out "$dir/out.csv" --quiet "$@" || die "exit $?"
  awk -F, -v row="$row" 'NR > 1 { failed = $2 != "ok"; if (failed != ($1 == row)) bad = 1 }
    END { exit bad }' "$dir/out.csv" || die "not exactly member $row failed"
  "$python" "$compare" "$dir/out.csv" "$members" "$bindir/$model" "$@" || die "not the serial numbers"
  ;;
bad)
  members=$1 line=$2
  shift 2
  run 2 --members "$members" --out "$dir/out.csv" "$@" 2>"$dir/stderr"
  rc=$?
  cat "$dir/stderr" >&2
  [ "$rc" -eq 2 ] || die "exit code $rc, expected 2"
  [ "$(grep -c "^ensemble: $members:$line: " "$dir/stderr")" -eq 1 ] || die "no one line naming line $line"
  [ -e "$dir/out.csv" ] || [ -e "$dir/out.csv.job" ] && die "output left behind"
  exit 0
  ;;
resume)
  members=$1
  shift
  n=$(rows "$members")
  run 2 --members "$members" --out "$dir/ref.csv" --quiet "$@" || die "exit $?"
  size=$(wc -c <"$dir/ref.csv")
  # prefixes: the header alone, cut inside the header, inside a row, at a row's end, whole
  header=$(head -n 1 "$dir/ref.csv" | wc -c)
  for cut in $header $((header - 3)) $((header + 5)) $((size / 2)) \
    $(head -n 4 "$dir/ref.csv" | wc -c) $size; do
    head -c "$cut" "$dir/ref.csv" >"$dir/out.csv"
    cp "$dir/ref.csv.job" "$dir/out.csv.job"
    run 2 --members "$members" --out "$dir/out.csv" --quiet --resume "$@" 2>"$dir/stderr"
    rc=$?
    if [ "$cut" -lt "$header" ]; then # not this job's header: refused
      [ "$rc" -eq 2 ] || die "a cut header: exit $rc, expected 2"
      continue
    fi
    [ "$rc" -eq 0 ] || die "resume after $cut bytes: exit $rc"
    cmp "$dir/ref.csv" "$dir/out.csv" || die "resumed after $cut bytes: not the same file"
  done
  # killed midway: whole rows kept, the rest run by --resume
  rm -f "$dir/out.csv"
  # mpirun itself in the background (not a subshell running it), so that the kill reaches it;
  # its ranks killed at once (Open MPI waits 1 s by default, when the job could end)
  "$mpirun" --mca odls_base_sigkill_timeout 0 --oversubscribe -n 2 "$ens" --model "$model" --members "$members" \
    --out "$dir/out.csv" --quiet --chunk 1 "$@" &
  pid=$!
  i=0
  while [ "$(cat "$dir/out.csv" 2>/dev/null | wc -l)" -lt 4 ] && [ $i -lt 600 ]; do
    sleep 0.05
    i=$((i + 1))
  done
  kill -TERM $pid
  wait $pid
  kept=$(rows "$dir/out.csv")
  [ "$kept" -lt "$n" ] || die "the run ended before it was killed ($kept rows)"
  run 2 --members "$members" --out "$dir/out.csv" --quiet --resume "$@" || die "resume: exit $?"
  cmp "$dir/ref.csv" "$dir/out.csv" || die "killed after $kept rows and resumed: not the same file"
  echo "killed with $kept of $n rows written; resumed to the same file"
  # another job's file
  run 2 --members "$members" --out "$dir/out.csv" --quiet --resume --T 0.002 "$@" 2>/dev/null
  [ $? -eq 2 ] || die "resume with other flags: not refused"
  ;;
certify)
  want=$1 tol=$2
  shift 2
  "$bindir/$model" --certify "$@" >"$dir/serial" || die "serial: exit $?"
  for p in 1 2 3; do
    run $p --certify "$@" >"$dir/p$p" || die "P = $p: exit $?"
  done
  cmp "$dir/p1" "$dir/p2" && cmp "$dir/p1" "$dir/p3" || die "the answer depends on P"
  cat "$dir/serial" "$dir/p1"
  s=$(sed -n 's/^sup_neg_k: //p' "$dir/serial")
  e=$(sed -n 's/^sup_neg_k: //p' "$dir/p1")
  awk -v s="$s" -v e="$e" -v w="$want" -v t="$tol" 'function a(x) { return x < 0 ? -x : x }
    BEGIN { exit !(e != "" && a(e - s) <= t * a(s) && a(e - w) <= t * a(w)) }' ||
    die "sup_neg_k $e: serial $s, by hand $want (tolerance $tol)"
  ;;
progress)
  members=$1
  shift
  run 2 --members "$members" --out "$dir/q.csv" --quiet "$@" 2>"$dir/quiet" || die "exit $?"
  [ -s "$dir/quiet" ] && die "--quiet printed: $(cat "$dir/quiet")"
  run 2 --members "$members" --out "$dir/p.csv" --progress 0 "$@" 2>"$dir/progress" || die "exit $?"
  n=$(rows "$members")
  cat "$dir/progress"
  grep -q "^ensemble: $n/$n members done (0 failed), .* members/s, ETA 0 s$" "$dir/progress" ||
    die "no progress line for the last member"
  grep -q "^ensemble: $n members in .* s (0 failed)" "$dir/progress" || die "no final line"
  cmp "$dir/q.csv" "$dir/p.csv" || die "the output depends on --progress"
  ;;
*)
  die "unknown mode $mode"
  ;;
esac
exit 0
