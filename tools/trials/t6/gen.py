#!/usr/bin/env python3
"""Trial 6: wrong-input (and legit-different) fixtures under WORK/t6/fx, scenario/URDF copies under
WORK/t6/scen, and WORK/t6/cases.tsv (the committed cases.tsv beside this file is a copy).  Clean tables: WORK/base.
Usage: python3 gen.py [WORK]  (WORK default /tmp/mtwin-trials; run.sh calls it).
A few legit fixtures need new simulated data (an R-test turned the other way, a repeat R-test with other noise):
they are made here with $GENBIN (run.sh sets it; default REPO/target/release/mtwin) from scenario copies, so the fixtures do not
depend on the binary under test.
Columns of cases.tsv: tag, kind, class, command, wrong, truth, ref, expect
  ref    = which clean reference output (run by ref.sh into OUTDIR/_ref) the numbers are compared with, '-' for none
  expect = legit    : correct input, any refusal or caution is a FALSE-ALARM
           tolerant : correct-but-imperfect input: a caution is fine, a refusal is a FALSE-ALARM
           wrong    : wrong input (a refusal or a caution naming the problem is right)
"""
import bisect, cmath, json, math, os, random, re, subprocess, sys
HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True
sys.path.insert(0, os.path.join(HERE, '..', 'lib'))
from tab import Table
from trialpaths import REPO, WORK, BASE, MODELS, SCENARIOS, write_cases

T = os.path.join(WORK, 't6')       # this trial's generated data (never inside the repository)
B = BASE
FX = T + '/fx'

SC = T + '/scen'
M = MODELS
S = SCENARIOS
GENBIN = os.environ.get('GENBIN', os.path.join(REPO, 'target', 'release', 'mtwin'))
os.makedirs(FX, exist_ok=True)
os.makedirs(SC, exist_ok=True)
random.seed(6)
cases = []


def case(tag, kind, klass, cmd, wrong, truth, ref='-', expect='wrong'):
    assert '\t' not in cmd + wrong + truth, tag
    assert tag not in [c[0] for c in cases], tag
    cases.append((tag, kind, klass, cmd, wrong, truth, ref, expect))


def fx(n):
    return FX + '/' + n


ANP = '{BIN} analyze positioning '
ANB = '{BIN} analyze ballbar '
AND = '{BIN} analyze drift '
ANS = '{BIN} analyze spindle '
ANR = '{BIN} analyze rtest '
ANPR = '{BIN} analyze probe '
IDV = '{BIN} identify --machine ' + M + '/vmc3.urdf --params %s %s --out {OUTDIR}/{TAG}'
IDT5 = '{BIN} identify --machine ' + M + '/trunnion5.urdf --params location %s --out {OUTDIR}/{TAG}'

POS = B + '/vmc3_iso230_2/positioning.csv'
LX = B + '/est_laser_X/positioning.csv'
WARM = B + '/vmc3_warmup_laser/positioning.csv'
BB = B + '/vmc3_ballbar_xy/ballbar_xy.csv'
BB3 = {p: B + '/est_bb3/ballbar_%s.csv' % p for p in ('xy', 'yz', 'zx')}
ETVE = B + '/vmc3_iso230_3_etve/drift.csv'
SDR = B + '/vmc3_iso230_3_spindle/drift.csv'
SP = B + '/vmc3_spindle/spindle.csv'
CA = B + '/trunnion5_c_axis/spindle.csv'
RT = B + '/trunnion5_rtest/rtest.csv'
PRR = B + '/vmc3_probe_ring_mesh/probe.csv'
PRS = B + '/trunnion5_probe_sphere/probe.csv'
PRP = B + '/vmc3_ballplate/probe.csv'
SPH = B + '/trunnion5_probe_sphere/spheres.csv'
BBPAR = 'squareness,EXX:2,EYY:2,EZZ:2'
BB3ALL = ' '.join(BB3[p] for p in ('xy', 'yz', 'zx'))


def L(p):
    return Table(p)


def write_raw(name, pre, header, rows, sep=',', eol='\n', quote=False, bom=False):
    p = fx(name)
    q = (lambda s: '"%s"' % s) if quote else (lambda s: s)
    with open(p, 'w', newline='') as f:
        if bom:
            f.write('\ufeff')
        for l in pre:
            f.write(l + eol)
        f.write(sep.join(q(h) for h in header) + eol)
        for r in rows:
            f.write(sep.join(q(x) for x in r) + eol)
    return p


F = lambda x: '%.6f' % x
F4 = lambda x: '%.4f' % x

# ============================================================ analyze positioning (vmc3_iso230_2)
R_POS = 'an_pos'

# Renishaw CARTO-style wide table: one row per target, one column per run and direction
t = L(POS)
runs = sorted({r[1] for r in t.rows}, key=int)
tg = [x.strip() for x in [l for l in t.pre if l.startswith('# targets_mm')][0].split('=')[1].split(',')]
val = {(r[1], r[2], '%.6f' % float(r[3])): r[4] for r in t.rows}
hdr = ['Target (mm)'] + ['Run %s %s (um)' % (k, 'Fwd' if d == '+' else 'Rev') for k in runs for d in '+-']
rows = [[('%.4f' % float(x))] + [val[(k, d, '%.6f' % float(x))] for k in runs for d in '+-'] for x in tg]
write_raw('pos_wide_carto.csv', ['# axis = X'], hdr, rows)
case('pos_wide_carto', 'analyze positioning', 'format', ANP + fx('pos_wide_carto.csv'),
     'CARTO-style wide export: one row per target, columns "Run k Fwd (um)" / "Run k Rev (um)"', 'clean figures or a clear refusal', R_POS)

# unit-suffixed header cells (real exports: "Target (mm)", "Deviation (µm)")
t = L(POS)
h = ['Axis', 'Run', 'Direction', 'Target (mm)', 'Deviation (µm)', 'Time (min)']
write_raw('pos_unit_hdr.csv', t.pre, h, t.rows)
case('pos_unit_hdr', 'analyze positioning', 'format', ANP + fx('pos_unit_hdr.csv'),
     'headers with units in the cells: Target (mm), Deviation (µm), Time (min)', 'clean figures or a clear refusal', R_POS)

# time as hh:mm:ss clock strings
t = L(POS)
j = t.col('time_min')
for r in t.rows:
    s = float(r[j]) * 60 + 9 * 3600 + 15 * 60
    r[j] = '%02d:%02d:%02d' % (s // 3600, (s % 3600) // 60, s % 60)
t.write(fx('pos_hms_time.csv'))
case('pos_hms_time', 'analyze positioning', 'format', ANP + fx('pos_hms_time.csv'),
     'time_min column holds wall-clock strings 09:15:02 (logger time stamps)', 'clean figures or a clear refusal', R_POS)

# means only: the export holds x-bar per target and direction as run 1, preamble still runs = 5
t = L(POS)
acc = {}
for r in t.rows:
    acc.setdefault((r[2], r[3]), []).append(float(r[4]))
rows, seen = [], set()
for r in t.rows:
    if r[1] != '1':
        continue
    k = (r[2], r[3])
    rows.append([r[0], '1', r[2], r[3], F(sum(acc[k]) / len(acc[k])), r[5]])
write_raw('pos_means_only.csv', t.pre, t.header, rows)
case('pos_means_only', 'analyze positioning', 'wrong test', ANP + fx('pos_means_only.csv'),
     'only the mean of the 5 runs exported (one pass per direction labelled run 1), preamble still says runs = 5',
     'R must not be reported from one run (ISO 230-2 needs 5); clean R 3.108, R-up 0.102', R_POS)

# each run starts with the minus pass (approach from above first); times rebuilt in that order: legit


def minus_first(t):
    out = []
    runs = []
    for r in t.rows:
        if not runs or runs[-1][0] != r[1]:
            runs.append((r[1], []))
        runs[-1][1].append(r)
    tcol = t.col('time_min')
    clock = 0.0
    for k, rr in runs:
        plus = [r[:] for r in rr if r[2] == '+']
        minus = [r[:] for r in rr if r[2] == '-']
        ts = [float(r[tcol]) for r in rr]
        dt = [ts[i + 1] - ts[i] for i in range(len(ts) - 1)]
        seq = minus + plus
        for i, r in enumerate(seq):
            r[tcol] = F(ts[0] + sum(dt[:i]))
        out += seq
    t.rows = out
    return t


t = minus_first(L(POS))
t.write(fx('pos_minus_first_legit.csv'))
case('pos_minus_first_legit', 'analyze positioning', 'clean (legit different)', ANP + fx('pos_minus_first_legit.csv'),
     'nothing wrong: every run approaches from above first (minus pass 750->10, then plus pass), times in that order',
     'clean figures', R_POS, 'legit')

# negative machine coordinates (axis travel 0..-750): mirror targets, deviations and direction labels: legit
t = L(POS)
t.fmap('target_mm', lambda x: -x).fmap('deviation_um', lambda x: -x)
t.map('direction', lambda d: '-' if d == '+' else '+')
t.pre = [('# targets_mm = ' + ', '.join('-' + x for x in tg)) if l.startswith('# targets_mm') else l for l in t.pre]
t.write(fx('pos_neg_targets_legit.csv'))
case('pos_neg_targets_legit', 'analyze positioning', 'clean (legit different)', ANP + fx('pos_neg_targets_legit.csv'),
     'nothing wrong: axis with negative travel (targets -10..-750), same test seen in that coordinate (deviations and directions mirrored)',
     'same E, A, R, B magnitudes as clean', R_POS, 'legit')

# direction labels swapped for every run (export's "+" = toward minus)
t = L(POS)
t.map('direction', lambda d: '-' if d == '+' else '+')
t.write(fx('pos_dir_all_swapped.csv'))
case('pos_dir_all_swapped', 'analyze positioning', 'sign/convention', ANP + fx('pos_dir_all_swapped.csv'),
     'direction labels swapped in every run (+ written for the pass toward 10 mm); time_min shows the order',
     'B-bar sign flips (clean -2.998 -> +2.998: lost motion becomes negative); direction vs target order in time is checkable', R_POS)

# two files concatenated: est_laser_X (its own preamble lines become comments mid-file) appended after vmc3_iso230_2
t = L(POS)
u = L(LX)
with open(fx('pos_cat_two_files.csv'), 'w') as f:
    for l in t.pre:
        f.write(l + '\n')
    f.write(','.join(t.header) + '\n')
    for r in t.rows:
        f.write(','.join(r) + '\n')
    for l in u.pre:
        f.write(l + '\n')
    for r in u.rows:
        f.write(','.join(r) + '\n')
case('pos_cat_two_files', 'analyze positioning', 'concatenated', ANP + fx('pos_cat_two_files.csv'),
     'two laser files concatenated (second file est_laser_X, other test with 11 targets and no lost motion, its preamble lines left in the middle as comments)',
     'a refusal or caution: runs 1..5 repeated with other targets and times restarting', R_POS)

# environmental compensation off at 24 C air: +3.7 ppm scale, preamble compensation = none, temp_air 24.1 C logged
t = L(POS)
t.set_pre('compensation', 'none')
j = t.col('deviation_um')
jt = t.col('target_mm')
t.header.append('temp_air_degc')
for r in t.rows:
    r[j] = F(float(r[j]) + 3.7e-3 * float(r[jt]))
    r.append('24.10')
t.write(fx('pos_envoff_air24.csv'))
case('pos_envoff_air24', 'analyze positioning', 'instrument set-up', ANP + fx('pos_envoff_air24.csv'),
     'laser environmental compensation off (preamble compensation = none) with the air at 24.1 C logged: wavelength 3.7 ppm off, +2.8 um at 750 mm',
     'a caution that uncompensated air at 24 C makes a ~3.7 ppm scale error; E 11.355 -> ~14', R_POS)

# header line repeated before every run (per-run exports pasted together)
t = L(POS)
rows = []
for i, r in enumerate(t.rows):
    if i > 0 and r[1] != t.rows[i - 1][1]:
        rows.append(t.header[:])
    rows.append(r)
write_raw('pos_hdr_repeated.csv', t.pre, t.header, rows)
case('pos_hdr_repeated', 'analyze positioning', 'format', ANP + fx('pos_hdr_repeated.csv'),
     'header line repeated before every run (per-run exports pasted together)', 'clean figures or a clear refusal', R_POS)

# blank line between runs: legit export layout
t = L(POS)
with open(fx('pos_blank_lines_legit.csv'), 'w') as f:
    for l in t.pre:
        f.write(l + '\n')
    f.write(','.join(t.header) + '\n')
    for i, r in enumerate(t.rows):
        if i > 0 and r[1] != t.rows[i - 1][1]:
            f.write('\n')
        f.write(','.join(r) + '\n')
case('pos_blank_lines_legit', 'analyze positioning', 'clean (legit different)', ANP + fx('pos_blank_lines_legit.csv'),
     'nothing wrong: an empty line between runs', 'clean figures', R_POS, 'legit')

# two captures per target (laser captured twice during the dwell)
t = L(POS)
rows = []
for r in t.rows:
    rows.append(r)
    r2 = r[:]
    r2[4] = F(float(r[4]) + random.gauss(0, 0.015))
    r2[5] = F(float(r[5]) + 0.02)
    rows.append(r2)
write_raw('pos_two_captures.csv', t.pre, t.header, rows)
case('pos_two_captures', 'analyze positioning', 'duplicate readings', ANP + fx('pos_two_captures.csv'),
     'two captures per target per pass (dwell captured twice, 1.2 s apart), 180 readings for 5 runs x 9 targets x 2 directions',
     'a caution or refusal (ISO 230-2: one reading per target and pass), or the two averaged; not a repeatability from 10 readings', R_POS)

# warm-up record: temperature blank for run 3 (sensor unplugged)
t = L(WARM)
jt = t.col('temp_x_nut_degc')
for r in t.rows:
    if r[1] == '3':
        r[jt] = ''
t.write(fx('warm_temp_blank_run3.csv'))
case('warm_temp_blank_run3', 'analyze positioning', 'dropout', ANP + fx('warm_temp_blank_run3.csv'),
     'warm-up laser record: temp_x_nut_degc empty for all of run 3 (sensor unplugged)', 'figures of the runs; run 3 without temperature (a caution is fine)', 'an_pos_warm', 'tolerant')

# ============================================================ compare
case('compare_minus_first_legit', 'compare', 'clean (legit different)', '{BIN} compare ' + fx('pos_minus_first_legit.csv') + ' ' + POS,
     'nothing wrong: measured table with minus passes first (times in that order) vs the simulated clean table',
     'readings paired by run, direction and target: RMS 0 (times differ)', '-', 'legit')
case('compare_dir_swapped', 'compare', 'sign/convention', '{BIN} compare ' + fx('pos_dir_all_swapped.csv') + ' ' + POS,
     'measured table with every direction label swapped vs the simulated table', 'RMS ~3 um (the lost motion) or a refusal; not 0', '-')

# ============================================================ identify laser (est_laser_X)
R_IDL = 'id_elx'
t = L(LX)
t.rows = [r for r in t.rows if r[2] == '+']
t.write(fx('idl_unidir_legit.csv'))
case('idl_unidir_legit', 'identify', 'clean (legit different)', IDV % ('EXX:2', fx('idl_unidir_legit.csv')),
     'nothing wrong: unidirectional laser test (plus passes only)', 'EXX close to clean (0.0120, -8e-6)', R_IDL, 'legit')

t = minus_first(L(LX))
t.write(fx('idl_minus_first_legit.csv'))
case('idl_minus_first_legit', 'identify', 'clean (legit different)', IDV % ('EXX:2', fx('idl_minus_first_legit.csv')),
     'nothing wrong: every run approaches from above first, times in that order', 'clean EXX', R_IDL, 'legit')

t = L(LX)
j = t.col('deviation_um')
jt = t.col('target_mm')
t.header.append('temp_air_degc')
for r in t.rows:
    r[j] = F(float(r[j]) + 3.7e-3 * float(r[jt]))
    r.append('24.10')
t.write(fx('idl_envoff_air24.csv'))
case('idl_envoff_air24', 'identify', 'instrument set-up', IDV % ('EXX:2', fx('idl_envoff_air24.csv')),
     'laser without air compensation (preamble compensation = none) at 24.1 C logged: +3.7 ppm scale in every reading',
     'EXX.polynomial[1] 0.0120 -> 0.0157 (+31 %); the 24 C air with compensation none should be cautioned', R_IDL)

case('idl_mc_legit', 'identify', 'clean (legit different)', IDV % ('EXX:2', LX) + ' --monte-carlo 20000',
     'nothing wrong: --monte-carlo 20000 on the clean table', 'clean EXX', R_IDL, 'legit')

# ============================================================ identify ball-bar (est_bb3)
R_IDBB = 'id_bb3'
t = L(BB3['xy'])
t.set_pre('centre_mm', '280 205 300')
t.write(fx('idbb_centre_typo_xy.csv'))
case('idbb_centre_typo', 'identify', 'preamble typo', IDV % (BBPAR, fx('idbb_centre_typo_xy.csv') + ' ' + BB3['yz'] + ' ' + BB3['zx']),
     'XY table preamble centre_mm = 280 205 300 (x typed 280 for 380); YZ and ZX say 380 205 300',
     'EXX:2 evaluated 100 mm off on the XY circle; clean estimates', R_IDBB)

t = L(BB3['xy'])
t.set_pre('feed_mm_per_min', '8.333')
t.write(fx('idbb_feed_mms_xy.csv'))
case('idbb_feed_mms', 'identify', 'units', IDV % (BBPAR, fx('idbb_feed_mms_xy.csv') + ' ' + BB3['yz'] + ' ' + BB3['zx']),
     'XY table preamble feed_mm_per_min = 8.333 (500 mm/min written in mm/s); time_s consistent with 500 mm/min',
     'a refusal/caution (feed contradicts time_s), or clean estimates if feed unused', R_IDBB)

t = L(BB3['zx'])
t.set_pre('plane', 'XZ')
t.write(fx('idbb_zx_as_xz.csv'))
case('idbb_zx_as_xz', 'identify', 'convention', IDV % (BBPAR, BB3['xy'] + ' ' + BB3['yz'] + ' ' + fx('idbb_zx_as_xz.csv')),
     'ZX table with preamble plane = XZ (software that names the plane X then Z): angle sense mirrored if read as XZ',
     'a refusal (XZ is not a plane name the tool knows) or clean', R_IDBB)

# ============================================================ analyze ballbar (vmc3_ballbar_xy)
R_BB = 'an_bb'


def bb_blocks(t):
    d = {}
    for r in t.rows:
        d.setdefault(r[0], []).append(r)
    return d


def interp(xs, ys, x):
    i = bisect.bisect_left(xs, x)
    if i <= 0:
        return ys[0]
    if i >= len(xs):
        return ys[-1]
    x0, x1 = xs[i - 1], xs[i]
    return ys[i - 1] + (ys[i] - ys[i - 1]) * (x - x0) / (x1 - x0)


# feed override 90 %: angles derived from time at the nominal feed, machine at 90 %
t = L(BB)
blk = bb_blocks(t)
rows = []
for sense in ('ccw', 'cw'):
    rr = blk[sense]
    a = [float(r[1]) for r in rr]
    dv = [float(r[2]) for r in rr]
    if sense == 'ccw':
        s = a
    else:
        s = [360 - x for x in a]
    for r, si in zip(rr, s):
        r2 = r[:]
        r2[2] = '%.1f' % interp(s, dv, 0.9 * si)
        rows.append(r2)
t.rows = rows
t.write(fx('bb_feed_override90.csv'))
case('bb_feed_override90', 'analyze ballbar', 'wrong test', ANB + fx('bb_feed_override90.csv'),
     'feed override at 90 %: the software assigned angles from time at the nominal 1000 mm/min, so the trace covers 324 deg labelled 0..360; reversal steps appear at 200/100/300 deg',
     'reversal features not at the quadrants (lag ~ +20 deg = ~0.5 s) should be cautioned; clean G 8.2/11.9', R_BB)

t = L(BB)
t.fmap('deviation_um', lambda x: -x, '%.1f')
t.write(fx('bb_sign_flip_an.csv'))
case('bb_sign_flip_an', 'analyze ballbar', 'sign/convention', ANB + fx('bb_sign_flip_an.csv'),
     'deviation sign reversed (+ = bar shorter, software convention of the export)',
     'backlash steps become negative (bar shortening at reversals), squareness/scale sign flip: clean backlash_x +4.0, squareness +20.0', R_BB)

# big set-up offset (300, -200 um): exact bar-length geometry, legit
t = L(BB)
ex, ey = 0.300, -0.200
R = 150.0
j = t.col('deviation_um')
for r in t.rows:
    th = math.radians(float(r[1]))
    d = float(r[j]) / 1000
    px, py = (R + d) * math.cos(th) + ex, (R + d) * math.sin(th) + ey
    r[j] = '%.1f' % ((math.hypot(px, py) - R) * 1000)
t.write(fx('bb_setup300_legit.csv'))
case('bb_setup300_legit', 'analyze ballbar', 'clean (legit different)', ANB + fx('bb_setup300_legit.csv'),
     'nothing wrong: centre ball set 300 um / -200 um off (poor set-up, within the bar range), exact bar-length geometry',
     'G, F, H and diagnostics as clean; only the centre offsets grow by (300, -200) um', R_BB, 'legit')

t = L(BB)
t.fmap('time_s', lambda x: x * 1000, '%.1f')
t.write(fx('bb_time_ms.csv'))
case('bb_time_ms', 'analyze ballbar', 'units', ANB + fx('bb_time_ms.csv'),
     'time_s column in milliseconds (QC20 export counts ms)', 'a refusal/caution (time says 1 mm/min); else clean figures', R_BB)

t = L(BB)
t.map('direction', lambda d: d.upper())
t.set_pre('first_direction', 'CCW')
t.write(fx('bb_dir_upper_legit.csv'))
case('bb_dir_upper_legit', 'analyze ballbar', 'clean (legit different)', ANB + fx('bb_dir_upper_legit.csv'),
     'nothing wrong: direction written CCW / CW (upper case)', 'clean figures', R_BB, 'legit')

t = L(BB)
t.map('direction', lambda d: {'ccw': 'Anticlockwise', 'cw': 'Clockwise'}[d])
t.del_pre('first_direction')
t.write(fx('bb_dir_words.csv'))
case('bb_dir_words', 'analyze ballbar', 'format', ANB + fx('bb_dir_words.csv'),
     'direction column with Renishaw words Anticlockwise / Clockwise', 'clean figures or a clear refusal', R_BB)

# ============================================================ analyze drift (ETVE)
R_DR = 'an_dr_etve'
t = L(ETVE)
j = t.col('time_min')
for r in t.rows:
    s = float(r[j]) + 7 * 60 + 30
    r[j] = '%02d:%02d' % (s // 60, s % 60)
t.write(fx('dr_clock_hhmm.csv'))
case('dr_clock_hhmm', 'analyze drift', 'format', AND + fx('dr_clock_hhmm.csv'),
     'time_min column holds clock time hh:mm (07:30 ... 15:29)', 'clean figures or a clear refusal', R_DR)

# electronic levels: tilt columns in urad instead of sensor pairs
t = L(ETVE)
iy1, iy2, ix1, ix2 = t.col('y1_um'), t.col('y2_um'), t.col('x1_um'), t.col('x2_um')
h = ['time_min', 'z_um', 'a_urad', 'b_urad', 'temp_air_degc', 'temp_spindle_degc']
rows = []
for r in t.rows:
    A = (float(r[iy1]) - float(r[iy2])) / 100 * 1000
    Bt = (float(r[ix2]) - float(r[ix1])) / 100 * 1000
    rows.append([r[0], r[t.col('z_um')], '%.3f' % A, '%.3f' % Bt, r[t.col('temp_air_degc')], r[t.col('temp_spindle_degc')]])
pre = [l for l in t.pre if not l.startswith('# spacing_mm')]
write_raw('dr_urad_legit.csv', pre, h, rows)
case('dr_urad_legit', 'analyze drift', 'clean (legit different)', AND + fx('dr_urad_legit.csv'),
     'nothing wrong: tilts logged by electronic levels (a_urad, b_urad) with z_um, no sensor pairs',
     'Z, A and B rows as clean (A whole 2.2, B -1.7 urad)', R_DR, 'legit')

t = L(ETVE)
for c in ('x1_um', 'y1_um', 'x2_um', 'y2_um'):
    t.drop(c)
t.del_pre('spacing_mm')
t.write(fx('dr_z_only_legit.csv'))
case('dr_z_only_legit', 'analyze drift', 'clean (legit different)', AND + fx('dr_z_only_legit.csv'),
     'nothing wrong: one Z sensor only (spindle growth test), no spacing', 'Z row as clean (3.14 whole, ETVE 0.75)', R_DR, 'legit')

t = L(ETVE)
t.drop('temp_air_degc').drop('temp_spindle_degc')
t.del_pre('ambient_sensor')
t.write(fx('dr_no_temps.csv'))
case('dr_no_temps', 'analyze drift', 'missing channel', AND + fx('dr_no_temps.csv'),
     'no temperature columns (thermometer not logged)', 'drift ranges as clean; ETVE without ambient may be refused or cautioned', R_DR, 'tolerant')

t = L(ETVE)
t.fmap('time_min', lambda x: x - 10)
t.write(fx('dr_preroll_legit.csv'))
case('dr_preroll_legit', 'analyze drift', 'clean (legit different)', AND + fx('dr_preroll_legit.csv'),
     'nothing wrong: time counted from the test start with 10 min of pre-roll (-10 .. 469 min)', 'clean figures (windows shifted by 10 min)', R_DR, 'legit')

t = L(ETVE)
u = L(SDR)
rows = t.rows[:]
for r in u.rows[:200]:
    rows.append([r[u.col(c)] for c in ('time_min', 'x1_um', 'y1_um', 'x2_um', 'y2_um', 'z_um', 'temp_air_degc', 'temp_spindle_degc')])
write_raw('dr_concat_restart.csv', t.pre, t.header, rows)
case('dr_concat_restart', 'analyze drift', 'concatenated', AND + fx('dr_concat_restart.csv'),
     'a second logger file (spindle test of the other machine, 200 min) appended: time restarts at 0', 'a refusal (time goes back)', R_DR)

t = L(ETVE)
for r in t.rows[1:]:
    r[0] = F(float(r[0]) + random.uniform(-0.05, 0.05))
t.write(fx('dr_jitter_legit.csv'))
case('dr_jitter_legit', 'analyze drift', 'clean (legit different)', AND + fx('dr_jitter_legit.csv'),
     'nothing wrong: logger time stamps jitter by up to +-3 s around the 1 min period', 'clean figures', R_DR, 'legit')

t = L(ETVE)
t.drop('x2_um').drop('y2_um')
t.del_pre('spacing_mm')
t.write(fx('dr_single_sensors_legit.csv'))
case('dr_single_sensors_legit', 'analyze drift', 'clean (legit different)', AND + fx('dr_single_sensors_legit.csv'),
     'nothing wrong: one sensor per direction (x1, y1, z), no pairs, no spacing', 'X1, Y1, Z rows as clean', R_DR, 'legit')

# ============================================================ analyze spindle (vmc3_spindle)
R_SP = 'an_sp'
t = L(SP)
t.drop('speed_rpm')
t.write(fx('sp_nospeed_col.csv'))
case('sp_nospeed_col', 'analyze spindle', 'missing column', ANS + fx('sp_nospeed_col.csv'),
     'speed_rpm column not exported (optional per the help); preamble speeds_rpm = 2000 6000 12000, time_s present, revolution restarts per speed',
     'three speeds from time_s or the preamble, as clean; not one 60-revolution block', R_SP, 'tolerant')



def upr1(t, col):
    ja = t.col('angle_deg')
    j = t.col(col)
    s = 0j
    for r in t.rows:
        s += float(r[j]) * cmath.exp(-1j * math.radians(float(r[ja])))
    return 2 * s / len(t.rows)


# pure eccentricity of the artefact: x = E cos(theta + phi), y = E sin(theta + phi) at each height, phase of the
# record's own set-up eccentricity (x1 1-UPR at 160 deg, y1 at 71 deg: y lags x by 90 deg), E about 20 um
t = L(SP)
ja = t.col('angle_deg')
for cx, cy, E in (('x1_um', 'y1_um', 20.0), ('x2_um', 'y2_um', 21.0)):
    ph = cmath.phase(upr1(t, cx))
    jx, jy = t.col(cx), t.col(cy)
    for r in t.rows:
        th = math.radians(float(r[ja])) + ph
        r[jx] = '%.4f' % (float(r[jx]) + E * math.cos(th))
        r[jy] = '%.4f' % (float(r[jy]) + E * math.sin(th))
t.write(fx('sp_ecc20_legit.csv'))
case('sp_ecc20_legit', 'analyze spindle', 'clean (legit different)', ANS + fx('sp_ecc20_legit.csv'),
     'nothing wrong: artefact centred 10x worse (pure eccentricity of 20 um at the x1/y1 height, 21 um at x2/y2, in the phase of the record\'s own set-up eccentricity)',
     'LSC/MRS/MIC/MCC values as clean; PC and fundamental grow', R_SP, 'legit')

t = L(SP)
jr, js = t.col('revolution'), t.col('speed_rpm')
t.rows = [r for r in t.rows if not (r[jr] == '0' and float(r[ja]) < 180)]
t.write(fx('sp_partial_first_rev_legit.csv'))
case('sp_partial_first_rev_legit', 'analyze spindle', 'clean (legit different)', ANS + fx('sp_partial_first_rev_legit.csv'),
     'nothing wrong: capture started mid-revolution: revolution 0 of each speed holds only 180..360 deg',
     'figures as clean (a partial revolution dropped or used; a note is fine)', R_SP, 'tolerant')

t = L(SP)
jt = t.col('time_s')
first = {}
for r in t.rows:
    first.setdefault(r[js], float(r[jt]))
    r[jt] = F(float(r[jt]) - first[r[js]])
t.write(fx('sp_time_restart_legit.csv'))
case('sp_time_restart_legit', 'analyze spindle', 'clean (legit different)', ANS + fx('sp_time_restart_legit.csv'),
     'nothing wrong: time_s restarts at 0 for each speed (one capture per speed)', 'clean figures', R_SP, 'legit')

t = L(SP)
t.rows = [r for r in t.rows if round(float(r[ja]) / 0.3515625) % 4 == 0]
t.set_pre('samples_per_revolution', '256')
t.write(fx('sp_spr256_legit.csv'))
case('sp_spr256_legit', 'analyze spindle', 'clean (legit different)', ANS + fx('sp_spr256_legit.csv'),
     'nothing wrong: 256 samples per revolution (analyser set coarser), preamble says 256',
     'synchronous values as clean (asynchronous within a few %)', R_SP, 'legit')

t = L(SP)
t.map('y1_um', lambda s: s)
jx, jy = t.col('x1_um'), t.col('y1_um')
for r in t.rows:
    r[jy] = r[jx]
t.write(fx('sp_y1_dup_x1.csv'))
case('sp_y1_dup_x1', 'analyze spindle', 'wiring', ANS + fx('sp_y1_dup_x1.csv'),
     'y1 channel records the x1 signal (cable on the wrong input of the analyser): y1 identical to x1 sample for sample',
     'a caution (two probes 90 deg apart cannot read the same signal); rotating x1+y1 values meaningless', R_SP)

t = L(SP)
for c, off in (('x1_um', 25.0), ('y1_um', -40.0), ('z_um', 60.0)):
    t.fmap(c, lambda x, off=off: x + off, '%.4f')
t.write(fx('sp_dc_offset_legit.csv'))
case('sp_dc_offset_legit', 'analyze spindle', 'clean (legit different)', ANS + fx('sp_dc_offset_legit.csv'),
     'nothing wrong: probes not zeroed (stand-off offsets x1 +25, y1 -40, z +60 um)', 'clean figures (offsets do not enter error motion)', R_SP, 'legit')

# ============================================================ R-test (trunnion5)
R_RT = 'an_rt'
R_IDT5 = 'id_t5'
t = L(RT)
for c in ('dx_um', 'dy_um', 'dz_um'):
    t.fmap(c, lambda x: -x, '%.4f')
t.write(fx('rt_sign_all.csv'))
case('rt_sign_all_an', 'analyze rtest', 'sign/convention', ANR + fx('rt_sign_all.csv'),
     'dx, dy, dz all negated (sphere relative to the tool: the other software convention); probe1..3 columns unchanged',
     'circle centres and cos/sin flip sign: clean CK1 A0 centre (-8.28, 14.05, 1.44); probe columns contradict', R_RT)
case('rt_sign_all_id', 'identify', 'sign/convention', IDT5 % fx('rt_sign_all.csv'),
     'dx, dy, dz all negated (sphere relative to tool); probe columns unchanged', 'every location error sign flips: clean EX0C 12, EY0C -8 ...', R_IDT5)


def rot_wp(t):
    ja_, jc_ = t.col('a_deg'), t.col('c_deg')
    jx_, jy_, jz_ = t.col('dx_um'), t.col('dy_um'), t.col('dz_um')
    for r in t.rows:
        a, c = math.radians(float(r[ja_])), math.radians(float(r[jc_]))
        x, y, z = float(r[jx_]), float(r[jy_]), float(r[jz_])
        # into the tilted (A) then turned (C) workpiece frame
        y, z = y * math.cos(a) + z * math.sin(a), -y * math.sin(a) + z * math.cos(a)
        x, y = x * math.cos(c) + y * math.sin(c), -x * math.sin(c) + y * math.cos(c)
        r[jx_], r[jy_], r[jz_] = '%.4f' % x, '%.4f' % y, '%.4f' % z
    return t


t = rot_wp(L(RT))
t.write(fx('rt_wpframe.csv'))
case('rt_wpframe_an', 'analyze rtest', 'frame', ANR + fx('rt_wpframe.csv'),
     'dx, dy, dz exported in the rotating workpiece (table) frame while the preamble says frame = machine',
     'a 1-UPR circle becomes a constant offset: clean CK1 A0 radius 16.5 um, range X 33.0', R_RT)
case('rt_wpframe_id', 'identify', 'frame', IDT5 % fx('rt_wpframe.csv'),
     'dx, dy, dz in the rotating workpiece frame, preamble frame = machine', 'clean location errors (EX0C 12 ...); wrong frame should fail the fit', R_IDT5)

t = L(RT)
t.set_pre('sphere_mm', '100 250 0')
t.write(fx('rt_sphere_yz_swap.csv'))
case('rt_sphere_yz_swap_id', 'identify', 'preamble typo', IDT5 % fx('rt_sphere_yz_swap.csv'),
     'preamble sphere_mm = 100 250 0 (y and z exchanged) while x_mm.. of pose 0 place it at 100 0 250', 'a refusal (sphere contradicts the poses) or clean', R_IDT5)


def scen(name, src, subs, crlf=False):
    txt = open(S + '/' + src).read().replace('"../models/', '"' + M + '/')
    for a, b in subs:
        n = len(re.findall(a, txt, flags=re.M))
        assert n >= 1, (name, a)
        txt = re.sub(a, b, txt, count=0, flags=re.M)
    p = SC + '/' + name + '.toml'
    with open(p, 'w', newline='') as f:
        f.write(txt.replace('\n', '\r\n') if crlf else txt)
    return p


def simulate(name, src, subs):
    p = scen(name, src, subs)
    out = SC + '/' + name
    r = subprocess.run([GENBIN, 'run', '--out', out, p], capture_output=True, text=True)
    assert r.returncode == 0, (name, r.stderr)
    return out


# C turned the other way (0 .. -360) in the two CK1 tests: legit
o = simulate('t5_rt_cneg', 'trunnion5_rtest.toml', [(r'to_deg = \{ C = 360\.0 \}', 'to_deg = { C = -360.0 }')])
RTN = o + '/rtest.csv'
case('rt_cneg_legit_an', 'analyze rtest', 'clean (legit different)', ANR + RTN,
     'nothing wrong: C turned 0 .. -360 deg in the K-tests (simulated that way)', 'ranges and circle radii as clean', R_RT, 'legit')
case('rt_cneg_legit_id', 'identify', 'clean (legit different)', IDT5 % RTN,
     'nothing wrong: C turned 0 .. -360 deg in the K-tests', 'location errors as clean', R_IDT5, 'legit')

# a repeat R-test (same machine, other noise): both tables given together, test names with " #2": legit
o = simulate('t5_rt_rep', 'trunnion5_rtest.toml', [(r'^seed = 7', 'seed = 8'), (r'^name = "(.*)"', r'name = "\1 #2"')])
RTR = o + '/rtest.csv'
case('rt_repeat_legit_id', 'identify', 'clean (legit different)', IDT5 % (RT + ' ' + RTR),
     'nothing wrong: the R-test repeated (other noise), both tables given; names of the second carry " #2"',
     'location errors as clean, smaller u', R_IDT5, 'legit')

# ============================================================ identify spheres: tilted working plane
R_IDSPH = 'id_sph'
t = L(SPH)
ja, jy, jz = t.col('a_deg'), t.col('y_mm'), t.col('z_mm')
for r in t.rows:
    a = float(r[ja])
    if a != 0:
        al = math.radians(a)   # undo the +30 deg turn about (y 275, z -50) that A -30 applies
        y, z = float(r[jy]) - 275, float(r[jz]) + 50
        y, z = y * math.cos(al) - z * math.sin(al), y * math.sin(al) + z * math.cos(al)
        r[jy], r[jz] = F(y + 275), F(z - 50)
t.write(fx('sph_tilted_plane.csv'))
case('sph_tilted_plane_id', 'identify', 'frame', IDT5 % fx('sph_tilted_plane.csv'),
     'A -30 sphere centres exported in the tilted working plane (PLANE/TCPM active in the probing cycle): they read like the A 0 centres',
     'clean location errors; wrong frame should fail the fit', R_IDSPH)

# ============================================================ analyze probe


def precomp(t, r_mm):
    ji, jj, jk = t.col('i'), t.col('j'), t.col('k')
    jx, jy, jz = t.col('x_mm'), t.col('y_mm'), t.col('z_mm')
    for r in t.rows:
        for jc, jn in ((jx, ji), (jy, jj), (jz, jk)):
            r[jc] = F(float(r[jc]) + r_mm * float(r[jn]))
    return t


t = precomp(L(PRR), 1.5)
t.write(fx('pr_ring_precomp.csv'))
case('pr_ring_precomp', 'analyze probe', 'double compensation', ANPR + fx('pr_ring_precomp.csv'),
     'latched points already stylus-compensated (surface points), preamble stylus_radius_mm = 1.5 kept', 'diameter 53.0 mm vs cal 50: a caution/refusal', 'an_pr_ring')

t = precomp(L(PRR), 1.5).set_pre('stylus_radius_mm', '0')
t.write(fx('pr_ring_precomp_r0_legit.csv'))
case('pr_ring_precomp_r0_legit', 'analyze probe', 'clean (legit different)', ANPR + fx('pr_ring_precomp_r0_legit.csv'),
     'nothing wrong: surface points (controller compensated the stylus), preamble stylus_radius_mm = 0', 'ring 50.0034, error +3.43, roundness 2.32', 'an_pr_ring', 'legit')

t = precomp(L(PRS), 3.0)
t.write(fx('pr_sph_precomp.csv'))
case('pr_sph_precomp', 'analyze probe', 'double compensation', ANPR + fx('pr_sph_precomp.csv'),
     'sphere touches already stylus-compensated, preamble stylus_radius_mm = 3 kept', 'R 9.5 mm vs cal 12.5: a caution', 'an_pr_sph')

t = L(PRR).set_pre('stylus_radius_mm', '3')
t.write(fx('pr_ring_stylus_diam.csv'))
case('pr_ring_stylus_diam', 'analyze probe', 'units', ANPR + fx('pr_ring_stylus_diam.csv'),
     'preamble stylus_radius_mm = 3 (the 3 mm ball diameter)', 'diameter 53 vs cal 50: a caution', 'an_pr_ring')

t = L(PRR)
for c in ('i', 'j', 'k'):
    t.fmap(c, lambda x: -x, '%.9f')
t.write(fx('pr_ring_ijk_neg.csv'))
case('pr_ring_ijk_neg', 'analyze probe', 'sign/convention', ANPR + fx('pr_ring_ijk_neg.csv'),
     'approach vectors i j k negated (surface normal into the material vs approach direction: other controller convention)',
     'read as a plug: diameter 47 - 3 = 44 mm vs cal 50: a caution', 'an_pr_ring')

t = L(PRS)
for c in ('i', 'j', 'k'):
    t.fmap(c, lambda x: -x, '%.9f')
t.write(fx('pr_sph_ijk_neg.csv'))
case('pr_sph_ijk_neg', 'analyze probe', 'sign/convention', ANPR + fx('pr_sph_ijk_neg.csv'),
     'sphere approach vectors negated (outward normals instead of approach directions)', 'R 18.5 (or 12.5 by luck) vs cal 12.5: a caution', 'an_pr_sph')

# plug gauge made from the ring: stylus centres at R + r, approach toward the centre
t = L(PRR)
ji, jj, jk = t.col('i'), t.col('j'), t.col('k')
jx, jy = t.col('x_mm'), t.col('y_mm')
for r in t.rows:
    if r[1] != 'ring':
        continue
    n = (float(r[ji]), float(r[jj]))
    sx, sy = float(r[jx]) + 1.5 * n[0], float(r[jy]) + 1.5 * n[1]
    r[jx], r[jy] = F(sx + 1.5 * n[0]), F(sy + 1.5 * n[1])
    r[ji], r[jj] = '%.9f' % -n[0], '%.9f' % -n[1]
t.write(fx('pr_plug_legit.csv'))
case('pr_plug_legit', 'analyze probe', 'clean (legit different)', ANPR + fx('pr_plug_legit.csv'),
     'nothing wrong: the same 50 mm feature probed as a plug gauge (stylus centres outside, approach toward the centre)',
     'plug diameter 50.0034, error +3.43, roundness 2.32', 'an_pr_ring', 'legit')

t = L(PRP)
for c, off in (('cal_x_mm', 10.0), ('cal_y_mm', -20.0), ('cal_z_mm', 5.0)):
    t.fmap(c, lambda x, off=off: x + off)
t.write(fx('pr_plate_cal_origin_legit.csv'))
case('pr_plate_cal_origin_legit', 'analyze probe', 'clean (legit different)', ANPR + fx('pr_plate_cal_origin_legit.csv'),
     'nothing wrong: certificate coordinates from another plate origin (all shifted by 10, -20, 5 mm)', 'same distance errors as clean', 'an_pr_plate', 'legit')

t = L(PRP)
jcx, jcy = t.col('cal_x_mm'), t.col('cal_y_mm')
for r in t.rows:
    x, y = float(r[jcx]), float(r[jcy])
    r[jcx], r[jcy] = F(-y), F(x)
t.write(fx('pr_plate_cal_rot90_legit.csv'))
case('pr_plate_cal_rot90_legit', 'analyze probe', 'clean (legit different)', ANPR + fx('pr_plate_cal_rot90_legit.csv'),
     'nothing wrong: certificate coordinates in the plate frame, the plate turned 90 deg on the table (distances unchanged)', 'same distance errors as clean', 'an_pr_plate', 'legit')

# ============================================================ discover
R_DP = 'disc_pos_warm'
t = L(WARM)
t.fmap('temp_x_nut_degc', lambda x: x * 1.8 + 32)
t.write(fx('disc_warm_temp_F.csv'))
case('disc_pos_temp_F', 'discover positioning', 'units', '{BIN} discover positioning ' + fx('disc_warm_temp_F.csv'),
     'warm-up record with temp_x_nut_degc in degF (68 .. 77)', 'a refusal (68 C nut) or the clean model; not a thermal_scale fitted to 1.8x temperature rises', R_DP)
case('disc_pos_alpha_alu', 'discover positioning', 'wrong flags', '{BIN} discover positioning --expansion-ppm-per-degc 23 ' + WARM,
     '--expansion-ppm-per-degc 23 (aluminium) for the steel screw', 'model effects as clean with thermal_scale absorbing the difference (-3.6 -> ~-14.9 ppm/C); a user error, no check possible', R_DP)
t = minus_first(L(WARM))
t.write(fx('disc_warm_minus_first_legit.csv'))
case('disc_pos_minus_first_legit', 'discover positioning', 'clean (legit different)', '{BIN} discover positioning ' + fx('disc_warm_minus_first_legit.csv'),
     'nothing wrong: warm-up runs with the minus pass first (times in that order)', 'same effects as clean (reversal, thermal_lag, thermal_scale)', R_DP, 'legit')
t = L(WARM)
t.map('direction', lambda d: '-' if d == '+' else '+')
t.write(fx('disc_warm_dir_swapped.csv'))
case('disc_pos_dir_swapped', 'discover positioning', 'sign/convention', '{BIN} discover positioning ' + fx('disc_warm_dir_swapped.csv'),
     'warm-up record with every direction label swapped', 'lost motion -3.96 um (negative backlash) should be cautioned', R_DP)

R_DB = 'disc_bb'
t = L(BB).set_pre('feed_mm_per_min', '16.667')
t.write(fx('disc_bb_feed_mms.csv'))
case('disc_bb_feed_mms', 'discover ballbar', 'units', '{BIN} discover ballbar ' + fx('disc_bb_feed_mms.csv'),
     'preamble feed_mm_per_min = 16.667 (mm/s written) while time_s shows 1000 mm/min', 'a refusal/caution, or servo_mismatch 60x too big', R_DB)
case('disc_bb_setup300_legit', 'discover ballbar', 'clean (legit different)', '{BIN} discover ballbar ' + fx('bb_setup300_legit.csv'),
     'nothing wrong: centre ball set 300/-200 um off', 'same effects as clean', R_DB, 'legit')

R_DS = 'disc_sp'
case('disc_sp_ecc20_legit', 'discover spindle', 'clean (legit different)', '{BIN} discover spindle ' + fx('sp_ecc20_legit.csv'),
     'nothing wrong: artefact eccentricity of 20 um (pure 1-UPR in x and y)', 'same effects as clean', R_DS, 'legit')
t = L(SP).set_pre('samples_per_revolution', '512')
t.write(fx('disc_sp_spr512.csv'))
case('disc_sp_spr512', 'discover spindle', 'preamble wrong', '{BIN} discover spindle ' + fx('disc_sp_spr512.csv'),
     'preamble samples_per_revolution = 512 while the data hold 1024 per revolution', 'a refusal (samples per revolution contradict angle_deg) or clean', R_DS)
case('disc_sp_y1_dup', 'discover spindle', 'wiring', '{BIN} discover spindle ' + fx('sp_y1_dup_x1.csv'),
     'y1 channel records the x1 signal', 'a caution', R_DS)

# ============================================================ URDF / scenario check


def urdf(name, src, subs):
    txt = open(M + '/' + src).read()
    for a, b in subs:
        assert a in txt, (name, a)
        txt = txt.replace(a, b, 1)
    p = SC + '/' + name + '.urdf'
    open(p, 'w').write(txt)
    return p


p = urdf('urdf_limit_deg', 'trunnion5.urdf', [('lower="-1.9198621771937625" upper="1.9198621771937625"', 'lower="-110" upper="110"')])
case('urdf_limit_deg', 'check urdf', 'units', '{BIN} check ' + p,
     'A joint limits written in degrees (-110, 110) in the radian field of the URDF', 'check should flag a revolute limit of 110 rad (17 turns)')
p = urdf('urdf_origin_mm', 'trunnion5.urdf', [('<origin xyz="0 0 0.25" rpy="0 0 0"/>', '<origin xyz="0 0 250" rpy="0 0 0"/>')])
case('urdf_origin_mm', 'check urdf', 'units', '{BIN} check ' + p + ' && ' + ('{BIN} identify --machine %s --params location %s --out {OUTDIR}/{TAG}' % (p, RT)),
     'A joint origin written in mm (0 0 250) instead of metres (0.25): A axis 250 m above the table', 'check should flag; identify must not fit on it', R_IDT5)
p = urdf('urdf_axis_unnorm', 'trunnion5.urdf', [('<axis xyz="0 0 -1"/>', '<axis xyz="0 0.0001 -1"/>')])
case('urdf_axis_tilted_legit', 'check urdf', 'clean (legit different)', '{BIN} check ' + p,
     'nothing wrong: C axis direction with a 100 urad nominal tilt (0 0.0001 -1, not unit length by 5e-9)', 'accepted', '-', 'legit')

# scenario: laser targets given from the far end: legit
p = scen('scen_targets_desc_legit', 'vmc3_iso230_2.toml', [(r'^targets_mm = \{ from = 10\.0, to = 750\.0, count = 9 \}', 'targets_mm = { from = 750.0, to = 10.0, count = 9 }')])
case('scen_targets_desc_legit', 'run/check scenario', 'clean (legit different)',
     '{BIN} check %s && {BIN} run --out {OUTDIR}/{TAG} %s && %s{OUTDIR}/{TAG}/positioning.csv' % (p, p, ANP),
     'nothing wrong: scenario targets given from the far end (from = 750, to = 10)', 'same figures as clean, or a clear refusal', R_POS, 'tolerant')

# ============================================================ score follow-ups
for tag, src, truth, ref in (('score_idl_envoff', 'idl_envoff_air24', B + '/est_laser_X/truth.json', 'score_elx'),
                              ('score_rt_sign_all', 'rt_sign_all_id', B + '/trunnion5_rtest/truth.json', 'score_t5'),
                              ('score_rt_wpframe', 'rt_wpframe_id', B + '/trunnion5_rtest/truth.json', 'score_t5'),
                              ('score_idbb_centre', 'idbb_centre_typo', B + '/est_bb3/truth.json', 'score_bb3'),
                              ('score_rt_cneg_legit', 'rt_cneg_legit_id', SC + '/t5_rt_cneg/truth.json', 'score_t5'),
                              ('score_rt_repeat_legit', 'rt_repeat_legit_id', B + '/trunnion5_rtest/truth.json', 'score_t5'),
                              ('score_sph_tilted', 'sph_tilted_plane_id', B + '/trunnion5_probe_sphere/truth.json', 'score_sph'),
                              ('score_idl_unidir_legit', 'idl_unidir_legit', B + '/est_laser_X/truth.json', 'score_elx')):
    leg = 'legit' if 'legit' in tag else 'wrong'
    case(tag, 'score', 'follow-up', '{BIN} score {OUTDIR}/%s/out/estimate.json %s' % (src, truth),
         'score of the %s estimate (no estimate means identify stopped the input)' % src, 'compensated RMS as the clean reference', ref, leg)

print(len(cases), 'cases so far (part 1)')
exec(open(HERE + '/gen2.py').read())

write_cases(T + '/cases.tsv', ['tag', 'kind', 'class', 'command', 'wrong', 'truth', 'ref', 'expect'], cases, T, HERE)
print(len(cases), 'cases')
