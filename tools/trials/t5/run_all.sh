#!/usr/bin/env bash
# usage: run_all.sh BIN WORK [TAG-REGEX]
#   runs every case of cases.tsv (next to this script) with BIN; results go to WORK/tN/res/<tag>/{cmd,stdout,stderr,rc,secs},
#   the clean references (ref.sh) to WORK/tN/res/_ref.  The fixtures must exist: python3 gen.py WORK (run.sh does both).
#   TAG-REGEX: only the matching cases run (the references always).
set -u
BIN=${1:?usage: run_all.sh BIN WORK [TAG-REGEX]}; WORK=${2:?WORK}; ONLY=${3:-.}
HERE=$(cd "$(dirname "$0")" && pwd)
REPO=$(cd "$HERE/../../.." && pwd)
T=$(basename "$HERE")
case "$BIN" in */*) BIN=$(cd "$(dirname "$BIN")" && pwd)/$(basename "$BIN") ;; esac
mkdir -p "$WORK"; WORK=$(cd "$WORK" && pwd)
OUTDIR=$WORK/$T/res
[ -d "$WORK/$T/fx" ] || { echo "run_all.sh: $WORK/$T/fx missing: run python3 $HERE/gen.py $WORK first" >&2; exit 2; }
mkdir -p "$OUTDIR"
bash "$HERE/ref.sh" "$BIN" "$OUTDIR/_ref" "$WORK/base"
printf '%-30s %4s  %s\n' tag exit caution/refusal
tail -n +2 "$HERE/cases.tsv" | while IFS=$'\t' read -r tag kind class cmd rest; do
  [[ "$tag" =~ $ONLY ]] || continue
  d="$OUTDIR/$tag"; rm -rf "$d"; mkdir -p "$d"
  c=${cmd//\{BIN\}/$BIN}; c=${c//\{OUTDIR\}/$OUTDIR}; c=${c//\{TAG\}/$tag/out}
  c=${c//\{FX\}/$WORK/$T/fx}; c=${c//\{SCEN\}/$WORK/$T/scen}; c=${c//\{BASE\}/$WORK/base}
  c=${c//\{HERE\}/$HERE}; c=${c//\{MODELS\}/$REPO/models}; c=${c//\{SCENARIOS\}/$REPO/scenarios}
  printf '%s\n' "$c" > "$d/cmd"
  start=$(date +%s%N)
  timeout 300 bash -c "$c" > "$d/stdout" 2> "$d/stderr" < /dev/null
  rc=$?; echo $rc > "$d/rc"
  ms=$(( ($(date +%s%N) - start) / 1000000 )); printf '%d.%03d\n' $((ms / 1000)) $((ms % 1000)) > "$d/secs"
  if grep -qiE 'caution|refus|error|implausib|warning|cannot' "$d/stdout" "$d/stderr"; then flag=yes; else flag=no; fi
  printf '%-30s %4s  %s\n' "$tag" "$rc" "$flag"
done
