#!/usr/bin/env bash
# usage: bash tools/trials/run.sh BIN [OUTDIR]
#   Re-runs the new-user trials 3-6 (plausible-but-wrong inputs and false-alarm probes) against BIN:
#   1. the clean base outputs: `BIN run --out OUTDIR/base/<name> <scenario>` for every scenario the generators read
#   2. every trial's fixtures: python3 tN/gen.py OUTDIR   (trial 6 also simulates two R-tests with $GENBIN, default BIN)
#   3. every case:            bash tN/run_all.sh BIN OUTDIR   -> OUTDIR/tN/res/<tag>/
#   4. the verdicts:          python3 tN/verdicts.py OUTDIR/tN/res   (+ make_report.py -> OUTDIR/tN/res/report.md)
#   and prints one summary table (also in OUTDIR/summary.txt).  A report, not a gate: exits 0 unless it cannot run.
#   Needs bash, coreutils (timeout) and python3 (standard library only).  OUTDIR default /tmp/mtwin-trials; it must lie
#   outside the repository.  Everything under OUTDIR/base and OUTDIR/tN is rewritten.
set -u
BIN=${1:?usage: bash tools/trials/run.sh BIN [OUTDIR]}
WORK=${2:-/tmp/mtwin-trials}
HERE=$(cd "$(dirname "$0")" && pwd)
REPO=$(cd "$HERE/../.." && pwd)
case "$BIN" in */*) ;; *) BIN=$(command -v "$BIN") || { echo "run.sh: no binary $1" >&2; exit 2; } ;; esac
BIN=$(cd "$(dirname "$BIN")" && pwd)/$(basename "$BIN")
[ -x "$BIN" ] || { echo "run.sh: $BIN is not an executable" >&2; exit 2; }
command -v python3 > /dev/null || { echo "run.sh: python3 is needed (standard library only)" >&2; exit 2; }
mkdir -p "$WORK"; WORK=$(cd "$WORK" && pwd)
case "$WORK/" in "$REPO"/*) echo "run.sh: OUTDIR $WORK is inside the repository; give one outside it" >&2; exit 2 ;; esac
export GENBIN=${GENBIN:-$BIN}
export PYTHONDONTWRITEBYTECODE=1   # keep the repository free of __pycache__
T0=$(date +%s)
echo "$BIN" > "$WORK/binary.txt"
log() { printf '[%3ds] %s\n' $(( $(date +%s) - T0 )) "$*"; }

# 1. base outputs: bundled scenarios (REPO/scenarios) and trial 3's scratch scenarios (t3/scen)
BUNDLED="headtable5_probe_sphere headtable5_rtest trunnion5_c_axis trunnion5_probe_sphere trunnion5_rtest
  vmc3_ballbar_3planes vmc3_ballbar_xy vmc3_ballplate vmc3_iso230_2 vmc3_iso230_3_etve vmc3_iso230_3_linear
  vmc3_iso230_3_spindle vmc3_probe_ring_mesh vmc3_spindle vmc3_warmup_laser"
SCRATCH="est_bb3 est_laser_X est_laser_Y est_laser_Z iso230_2_b t5_rtest_b"
log "base outputs -> $WORK/base"
rm -rf "$WORK/base"; mkdir -p "$WORK/base"
for s in $BUNDLED $SCRATCH; do
  f=$REPO/scenarios/$s.toml; [ -f "$f" ] || f=$HERE/t3/scen/$s.toml
  if ! "$BIN" run --out "$WORK/base/$s" "$f" > "$WORK/base/$s.log" 2>&1; then
    echo "run.sh: BIN run $f failed (see $WORK/base/$s.log); the fixtures need it" >&2; exit 2
  fi
done

# 2. fixtures
for t in t3 t4 t5 t6; do
  log "$t: fixtures"
  rm -rf "$WORK/$t"; mkdir -p "$WORK/$t"
  if ! python3 "$HERE/$t/gen.py" "$WORK" > "$WORK/$t/gen.log" 2>&1; then
    echo "run.sh: $t/gen.py failed (see $WORK/$t/gen.log)" >&2; tail -5 "$WORK/$t/gen.log" >&2; exit 2
  fi
  cmp -s "$WORK/$t/cases.tsv" "$HERE/$t/cases.tsv" ||
    echo "run.sh: note: $t/gen.py made a cases.tsv that differs from the committed $t/cases.tsv (the committed one runs)" >&2
done

# 3. cases (the four trials side by side) and 4. verdicts
for t in t3 t4 t5 t6; do
  ( bash "$HERE/$t/run_all.sh" "$BIN" "$WORK" > "$WORK/$t/run_all.log" 2>&1
    python3 "$HERE/$t/verdicts.py" "$WORK/$t/res" > "$WORK/$t/verdicts.txt" 2>&1
    [ -f "$HERE/$t/make_report.py" ] && python3 "$HERE/$t/make_report.py" "$WORK/$t/res" > /dev/null 2>&1
    log "$t: cases run, verdicts in $WORK/$t/res/verdicts.tsv" ) &
done
wait
SECS=$(( $(date +%s) - T0 ))

# summary table
python3 - "$WORK" "$SECS" "$BIN" <<'EOF' | tee "$WORK/summary.txt"
import csv, os, sys
work, secs, binary = sys.argv[1], int(sys.argv[2]), sys.argv[3]
trials = ['t3', 't4', 't5', 't6']
rows = {}
for t in trials:
    p = os.path.join(work, t, 'res', 'verdicts.tsv')
    rows[t] = list(csv.DictReader(open(p), delimiter='\t')) if os.path.exists(p) else []
verdicts = sorted({r['verdict'] for t in trials for r in rows[t]})
print('mtwin trials 3-6 with %s  (%d s; results in %s)' % (binary, secs, work))
print()
w = max([len(v) for v in verdicts] + [7])
print('%-*s' % (w, 'verdict') + ''.join('%7s' % t for t in trials) + '%8s' % 'all')
for v in verdicts:
    n = [sum(1 for r in rows[t] if r['verdict'] == v) for t in trials]
    print('%-*s' % (w, v) + ''.join('%7d' % x for x in n) + '%8d' % sum(n))
n = [len(rows[t]) for t in trials]
print('%-*s' % (w, 'total') + ''.join('%7d' % x for x in n) + '%8d' % sum(n))
for v in ('PANIC-HANG', 'CONFIDENT-WRONG', 'FALSE-ALARM'):
    hits = [(t, r) for t in trials for r in rows[t] if r['verdict'] == v]
    if not hits:
        continue
    print()
    print('%s (%d)' % (v, len(hits)))
    for t, r in hits:
        what = r.get('wrong', '')
        print('  %s %-30s %s' % (t, r['tag'], what[:110]))
for t in trials:
    if not rows[t]:
        print('\n%s: no verdicts (see %s/%s/run_all.log and verdicts.txt)' % (t, work, t))
EOF
exit 0
