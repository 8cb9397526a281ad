#!/usr/bin/env python3
"""Trial 5: wrong-input (and legit-different) fixtures under WORK/t5/fx, scenario copies under
WORK/t5/scen, and WORK/t5/cases.tsv (the committed cases.tsv beside this file is a copy).  Clean tables: WORK/base.
Usage: python3 gen.py [WORK]  (WORK default /tmp/mtwin-trials; run.sh calls it).
Columns of cases.tsv: tag, kind, class, command, wrong, truth, ref, expect
  ref    = which clean reference output (run by ref.sh into OUTDIR/_ref) the numbers are compared with,
           '-' when none applies (legitimately different numbers)
  expect = legit    : correct input, any refusal or caution is a FALSE-ALARM
           tolerant : correct-but-imperfect input (a dropout...): a caution is fine, a refusal is a FALSE-ALARM
           wrong    : wrong input
"""
import json, math, os, random, re, sys
HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True
sys.path.insert(0, os.path.join(HERE, '..', 'lib'))
from tab import Table
from trialpaths import REPO, WORK, BASE, MODELS, SCENARIOS, write_cases

T = os.path.join(WORK, 't5')       # this trial's generated data (never inside the repository)
B = BASE
FX = T + '/fx'

SC = T + '/scen'
M = MODELS
S = SCENARIOS
os.makedirs(FX, exist_ok=True)
os.makedirs(SC, exist_ok=True)
random.seed(5)
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
LY = B + '/est_laser_Y/positioning.csv'
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


def rows_where(t, **kw):
    out = []
    for r in t.rows:
        if all(r[t.col(k)] == v for k, v in kw.items()):
            out.append(r)
    return out


F = lambda x: '%.6f' % x

# ============================================================ analyze positioning (vmc3_iso230_2)
R_POS = 'an_pos'

# re-zeroed at the start of every pass (each run, each direction): preamble still says zero = once
t = L(POS)
first = {}
for r in t.rows:
    k = (r[1], r[2])
    if k not in first:
        first[k] = float(r[4])
    r[4] = F(float(r[4]) - first[k])
t.write(fx('pos_rezero_each_pass.csv'))
case('pos_rezero_each_pass', 'analyze positioning', 'offsets (re-zeroed)', ANP + fx('pos_rezero_each_pass.csv'),
     'laser re-zeroed at the first target of every pass (down passes start at 0 at 750 mm); preamble still says zero = once',
     'clean E 11.355 B 3.024 R 3.108; re-zeroed passes kill the reversal at 750 mm and shift B', R_POS)

# every field double-quoted (Excel "CSV with quotes")
t = L(POS)
write_raw('pos_quoted_legit.csv', t.pre, t.header, t.rows, quote=True)
case('pos_quoted_legit', 'analyze positioning', 'clean (legit different)', ANP + fx('pos_quoted_legit.csv'),
     'nothing wrong: every header and field double-quoted (spreadsheet "quote all" export)', 'clean figures', R_POS, 'legit')

# extra unknown columns
t = L(POS)
h = t.header + ['status', 'env_comp', 'comment']
rows = [r + ['OK', '1', ''] for r in t.rows]
write_raw('pos_extra_cols_legit.csv', t.pre, h, rows)
case('pos_extra_cols_legit', 'analyze positioning', 'clean (legit different)', ANP + fx('pos_extra_cols_legit.csv'),
     'nothing wrong: extra unknown columns status, env_comp, comment (empty)', 'clean figures', R_POS, 'legit')

# random row order
t = L(POS)
rows = t.rows[:]
random.shuffle(rows)
write_raw('pos_shuffled_legit.csv', t.pre, t.header, rows)
case('pos_shuffled_legit', 'analyze positioning', 'clean (legit different)', ANP + fx('pos_shuffled_legit.csv'),
     'nothing wrong: data rows in random order (time_min intact)', 'clean figures', R_POS, 'legit')

# tab-separated
t = L(POS)
write_raw('pos_tsv.csv', t.pre, t.header, t.rows, sep='\t')
case('pos_tsv', 'analyze positioning', 'format', ANP + fx('pos_tsv.csv'),
     'tab-separated export saved as .csv (Excel "Text (Tab delimited)")', 'clean figures or a clear refusal', R_POS)

# units row under the header (CARTO/LabVIEW style)
t = L(POS)
rows = [['', '', '', 'mm', 'um', 'min']] + t.rows
write_raw('pos_units_row.csv', t.pre, t.header, rows)
case('pos_units_row', 'analyze positioning', 'format', ANP + fx('pos_units_row.csv'),
     'a units row (",,,mm,um,min") under the header', 'clean figures or a clear refusal', R_POS)

# summary rows appended (not commented)
t = L(POS)
rows = t.rows + [['', '', '', '', '', ''], ['Max', '', '', '', '11.362', ''], ['Min', '', '', '', '0.007', ''], ['Mean', '', '', '', '6.5', '']]
write_raw('pos_footer_stats.csv', t.pre, t.header, rows)
case('pos_footer_stats', 'analyze positioning', 'format', ANP + fx('pos_footer_stats.csv'),
     'summary rows Max/Min/Mean appended after the data (spreadsheet footer)', 'clean figures or a clear refusal', R_POS)

# quoted decimal commas in a comma file
t = L(POS)
rows = [[r[0], r[1], r[2], '"%s"' % r[3].replace('.', ','), '"%s"' % r[4].replace('.', ','), '"%s"' % r[5].replace('.', ',')] for r in t.rows]
write_raw('pos_dec_comma_quoted.csv', t.pre, t.header, rows)
case('pos_dec_comma_quoted', 'analyze positioning', 'format', ANP + fx('pos_dec_comma_quoted.csv'),
     'comma-separated with quoted decimal-comma numbers ("113,722956")', 'clean figures or a clear refusal', R_POS)

# laser hold: run 4 down pass stuck at its first reading
t = L(POS)
rr = rows_where(t, run='4', direction='-')
v = rr[0][4]
for r in rr:
    r[4] = v
t.write(fx('pos_stuck_pass.csv'))
case('pos_stuck_pass', 'analyze positioning', 'stuck sensor', ANP + fx('pos_stuck_pass.csv'),
     'laser "hold" after a beam interruption: run 4 down pass repeats its first reading (11.36 um) at all 9 targets',
     'clean E 11.355 R 3.108; stuck pass inflates R and s_down at low targets', R_POS)

# one reading missing (dropout)
t = L(POS)
rr = rows_where(t, run='3', direction='+')
t.rows.remove(rr[4])
t.write(fx('pos_dropout_legit.csv'))
case('pos_dropout_legit', 'analyze positioning', 'dropout (tolerant)', ANP + fx('pos_dropout_legit.csv'),
     'one reading missing (run 3, +, 383.37 mm): beam lost, the export skipped it', 'clean figures within noise; caution acceptable', R_POS, 'tolerant')

# overrun stops exported as readings (5 mm before + pass, 755 mm before - pass)
t = L(POS)
rows = []
for r in t.rows:
    if r[2] == '+' and r[3] == '10.000000':
        rows.append([r[0], r[1], '+', '5.000000', F(float(r[4]) - 0.06), F(float(r[5]) - 0.01)])
    rows.append(r)
    if r[2] == '+' and r[3] == '750.000000':
        rows.append([r[0], r[1], '-', '755.000000', F(float(r[4]) + 3.05), F(float(r[5]) + 0.01)])
write_raw('pos_overrun_rows.csv', t.pre, t.header, rows)
case('pos_overrun_rows', 'analyze positioning', 'duplicated/extra data', ANP + fx('pos_overrun_rows.csv'),
     'overrun stops (5 mm on the + side, 755 mm on the - side) exported as readings; preamble targets_mm has the 9 real targets',
     'clean E 11.355 A 11.443 R 3.108 B 3.024 (overrun points are not targets)', R_POS)

# deviation column in nm with an nm header
t = L(POS)
t.fmap('deviation_um', lambda x: x * 1000, '%.1f').rename('deviation_um', 'deviation_nm')
t.write(fx('pos_dev_nm_header.csv'))
case('pos_dev_nm_header', 'analyze positioning', 'units (named)', ANP + fx('pos_dev_nm_header.csv'),
     'deviation exported in nm with header deviation_nm (foreign export, unit in the name)', 'convert (clean figures) or refuse naming the column', R_POS)

# unicode minus (copied from a PDF/Word report) -- on the ball-bar table, half of whose readings are negative
t = L(BB)
neg = 0
for r in t.rows:
    if r[2].startswith('-'):
        r[2] = '\u2212' + r[2][1:]
        neg += 1
t.write(fx('bb_unicode_minus.csv'))
case('bb_unicode_minus', 'analyze ballbar', 'format', ANB + fx('bb_unicode_minus.csv'),
     'negative deviations written with the Unicode minus U+2212 (copy from a PDF report); %d such readings' % neg,
     'clean figures or a clear refusal', 'an_bb')

# spaces after commas
t = L(POS)
write_raw('pos_spaces_legit.csv', t.pre, t.header, t.rows, sep=', ')
case('pos_spaces_legit', 'analyze positioning', 'clean (legit different)', ANP + fx('pos_spaces_legit.csv'),
     'nothing wrong: ", " separator (space after every comma)', 'clean figures', R_POS, 'legit')

# time in seconds with a time_s header (foreign export)
t = L(POS)
t.fmap('time_min', lambda x: x * 60, '%.3f').rename('time_min', 'time_s')
t.write(fx('pos_time_s_legit.csv'))
case('pos_time_s_legit', 'analyze positioning', 'clean (legit different)', ANP + fx('pos_time_s_legit.csv'),
     'nothing wrong: time column time_s in seconds (unit in its name)', 'clean figures', R_POS, 'legit')

# runs numbered 0..4, lowercase axis
t = L(POS)
t.map('run', lambda s: str(int(s) - 1)).map('axis', lambda s: s.lower())
t.write(fx('pos_run0_lower_legit.csv'))
case('pos_run0_lower_legit', 'analyze positioning', 'clean (legit different)', ANP + fx('pos_run0_lower_legit.csv'),
     'nothing wrong: runs numbered 0..4, axis letter lower case', 'clean figures', R_POS, 'legit')

# target column holds the laser's actual position (target + deviation)
t = L(POS)
for r in t.rows:
    r[3] = F(float(r[3]) + float(r[4]) / 1000)
t.write(fx('pos_target_is_actual.csv'))
case('pos_target_is_actual', 'analyze positioning', 'swapped/renamed', ANP + fx('pos_target_is_actual.csv'),
     'target_mm holds the actual (measured) position target+dev, 6 decimals, so each target differs run to run by um',
     'group by nominal (clean figures) or refuse; 90 one-reading targets would be wrong', R_POS)

# one reading with its sign lost (typo)
t = L(POS)
rr = rows_where(t, run='2', direction='-', target_mm='383.368583')
rr[0][4] = F(-float(rr[0][4]))
t.write(fx('pos_sign_typo.csv'))
case('pos_sign_typo', 'analyze positioning', 'disturbed single reading', ANP + fx('pos_sign_typo.csv'),
     'one reading typed with its sign lost (run 2, -, 383.37 mm: -8.3 instead of +8.3; 16.6 um off)',
     'clean R 3.108 R_down 0.143; typo gives R_down ~ 20 um at that target', R_POS)

# run 5 down pass labelled +
t = L(POS)
for r in rows_where(t, run='5', direction='-'):
    r[2] = '+'
t.write(fx('pos_dir_mislabel.csv'))
case('pos_dir_mislabel', 'analyze positioning', 'renamed/labels', ANP + fx('pos_dir_mislabel.csv'),
     'run 5 down pass labelled + (export wrote the direction of the previous pass)', 'clean figures with 4 runs down or a caution; pooling the down pass into + gives R_up ~ 3 um', R_POS)

# warm-up record: runs numbered backwards (label order irrelevant, times intact)
t = L(WARM)
n = 7
t.map('run', lambda s: str(n + 1 - int(s)))
t.write(fx('warm_runs_desc_legit.csv'))
case('warm_runs_desc_legit', 'analyze positioning', 'clean (legit different)', ANP + fx('warm_runs_desc_legit.csv'),
     'nothing wrong: warm-up runs numbered 7..1 (times intact)', 'same figures as the clean warm-up analysis (caution about the thermal drift is the normal one)', 'an_pos_warm', 'legit')

# ============================================================ compare
case('compare_self_legit', 'compare', 'clean', '{BIN} compare ' + POS + ' ' + POS,
     'nothing wrong: a table compared with itself', 'RMS 0, no caution', '-', 'legit')
t = L(POS)
rows = t.rows[:]
random.shuffle(rows)
write_raw('cmp_shuffled.csv', t.pre, t.header, rows)
case('compare_shuffled_legit', 'compare', 'clean (legit different)', '{BIN} compare ' + fx('cmp_shuffled.csv') + ' ' + POS,
     'nothing wrong: measured rows shuffled against the simulated table', 'RMS 0', '-', 'legit')
case('compare_x_vs_y', 'compare', 'provenance', '{BIN} compare ' + LX + ' ' + LY,
     'X-axis laser table compared with the Y-axis one (wrong file picked)', 'caution/refusal expected: axis X vs Y', '-')
t = L(POS)
t.map('run', lambda s: str(int(s) + 5)).set_pre('runs', '5')
t.write(fx('cmp_runs_6to10.csv'))
case('compare_runs_renumbered', 'compare', 'renamed', '{BIN} compare ' + fx('cmp_runs_6to10.csv') + ' ' + POS,
     'measured runs numbered 6..10 (second test of the day) vs simulated 1..5', 'pair runs in order or say clearly they have no partner', '-', 'tolerant')

# ============================================================ analyze ballbar (vmc3_ballbar_xy)
R_BB = 'an_bb'
t = L(BB)
ccw = [r for r in t.rows if r[0] == 'ccw']
i = min(range(len(ccw)), key=lambda k: abs(float(ccw[k][1]) - 100.0))
ccw[i][2] = F(float(ccw[i][2]) + 40.0)
t.write(fx('bb_spike.csv'))
case('bb_spike', 'analyze ballbar', 'disturbed single reading', ANB + fx('bb_spike.csv'),
     'one sample +40 um at 100 deg in ccw (bar knocked / chip on the ball)', 'clean G ccw 8.232 F_max 5.601; spike gives G ccw ~ 45', R_BB)

t = L(BB)
cw = [r for r in t.rows if r[0] == 'cw']
i = min(range(len(cw)), key=lambda k: abs(float(cw[k][1]) - 200.0))
v = cw[i][2]
for r in cw[i:i + 500]:
    r[2] = v
t.write(fx('bb_stuck.csv'))
case('bb_stuck', 'analyze ballbar', 'stuck sensor', ANB + fx('bb_stuck.csv'),
     'cw transducer value frozen for 500 samples (2 s, ~33 deg) from 200 deg (logger repeated its last value)', 'clean diagnostics; caution expected', R_BB)

t = L(BB)
t.rows = [r for r in t.rows if not (r[0] == 'ccw' and 120.0 <= float(r[1]) < 130.0)]
t.write(fx('bb_gap10.csv'))
case('bb_gap10_tol', 'analyze ballbar', 'dropout (tolerant)', ANB + fx('bb_gap10.csv'),
     'ccw readings 120..130 deg missing (Bluetooth dropout)', 'clean figures nearly; a caution is acceptable', R_BB, 'tolerant')

t = L(BB)
rows = [r for r in t.rows if r[0] == 'cw'] + [r for r in t.rows if r[0] == 'ccw']
write_raw('bb_blocks_swapped_legit.csv', t.pre, t.header, rows)
case('bb_blocks_swapped_legit', 'analyze ballbar', 'clean (legit different)', ANB + fx('bb_blocks_swapped_legit.csv'),
     'nothing wrong: cw block written before the ccw block (time_s intact)', 'clean figures', R_BB, 'legit')

t = L(BB)
cw = [r for r in t.rows if r[0] == 'cw']
t0 = float(cw[0][3])
for r in cw:
    r[3] = '%.6f' % (float(r[3]) - t0)
t.write(fx('bb_time_restart_legit.csv'))
case('bb_time_restart_legit', 'analyze ballbar', 'clean (legit different)', ANB + fx('bb_time_restart_legit.csv'),
     'nothing wrong: time_s restarts at 0 for the cw capture (each run its own file, then joined)', 'clean figures', R_BB, 'legit')

t = L(BB)
t.fmap('angle_deg', lambda a: (a + 5.0) % 360.0)
t.write(fx('bb_start_5deg.csv'))
case('bb_start_5deg', 'analyze ballbar', 'angles', ANB + fx('bb_start_5deg.csv'),
     'angles counted from where capture started, 5 deg late (every angle +5 deg, time intact)', 'clean squareness 20.0 scale 12.2 backlash_x 4.0; rotation mixes them', R_BB)

t = L(BB)
t.map('direction', lambda s: 'ccw')
t.write(fx('bb_all_ccw.csv'))
case('bb_all_ccw', 'analyze ballbar', 'renamed/labels', ANB + fx('bb_all_ccw.csv'),
     'direction column says ccw for both runs (export lost the sense)', 'refusal or caution expected', R_BB)

t = L(BB)
write_raw('bb_crlf_quoted_legit.csv', t.pre, t.header, t.rows, eol='\r\n', quote=True)
case('bb_crlf_quoted_legit', 'analyze ballbar', 'clean (legit different)', ANB + fx('bb_crlf_quoted_legit.csv'),
     'nothing wrong: CRLF line ends and every field quoted', 'clean figures', R_BB, 'legit')

t = L(BB)
h = t.header + ['x_mm', 'y_mm', 'feed_mm_per_min', 'flag']
rows = []
for r in t.rows:
    a = math.radians(float(r[1]))
    rows.append(r + ['%.4f' % (150 * math.cos(a)), '%.4f' % (150 * math.sin(a)), '1000', '0'])
write_raw('bb_extra_cols_legit.csv', t.pre, h, rows)
case('bb_extra_cols_legit', 'analyze ballbar', 'clean (legit different)', ANB + fx('bb_extra_cols_legit.csv'),
     'nothing wrong: extra columns x_mm, y_mm, feed_mm_per_min, flag', 'clean figures', R_BB, 'legit')

t = L(BB)
t.del_pre()
t.write(fx('bb_nopre.csv'))
case('bb_nopre_flags_legit', 'analyze ballbar', 'clean (legit different)', ANB + fx('bb_nopre.csv') + ' --plane XY --radius-mm 150 --feed-mm-per-min 1000',
     'nothing wrong: no preamble, plane/radius/feed given by flags as the scenario comment shows', 'clean figures', R_BB, 'legit')

t = L(BB)
t.rows = t.rows[::5]
t.set_pre('sample_rate_hz', '50')
t.write(fx('bb_dec50_legit.csv'))
case('bb_dec50_legit', 'analyze ballbar', 'clean (legit different)', ANB + fx('bb_dec50_legit.csv'),
     'nothing wrong: every 5th sample (a 50 Hz export), preamble says 50 Hz', 'clean figures within a few %', R_BB, 'legit')

t = L(BB)
t.rows = t.rows[::5]
t.write(fx('bb_dec_pre250.csv'))
case('bb_dec_pre250', 'analyze ballbar', 'preamble contradicts', ANB + fx('bb_dec_pre250.csv'),
     'every 5th sample exported (50 Hz) while the preamble keeps sample_rate_hz = 250 (time_s at 20 ms steps)', 'clean figures (time_s governs) or a caution', R_BB)

t = L(BB)
for r in t.rows:
    if r[0] == 'cw':
        r[2] = F(float(r[2]) + 3.0)
t.write(fx('bb_cw_rezero.csv'))
case('bb_cw_rezero', 'analyze ballbar', 'offsets (re-zeroed)', ANB + fx('bb_cw_rezero.csv'),
     'bar re-zeroed in the calibrator between runs: cw deviations +3 um relative to ccw', 'clean G(b) 11.999 H 8.192 radius -0.046; offset between senses changes H, G(b)', R_BB)

# ---- identify with ball-bar tables
R_IDBB = 'id_bb3'
t = L(BB3['xy'])
ccw = [r for r in t.rows if r[0] == 'ccw']
i = min(range(len(ccw)), key=lambda k: abs(float(ccw[k][1]) - 100.0))
ccw[i][2] = F(float(ccw[i][2]) + 40.0)
t.write(fx('id_bb_spike_xy.csv'))
case('id_bb_spike', 'identify', 'disturbed single reading', IDV % (BBPAR, fx('id_bb_spike_xy.csv') + ' ' + BB3['yz'] + ' ' + BB3['zx']),
     'XY ball-bar table with one +40 um spike sample at 100 deg', 'clean EC0Y -19.996 EA0Z 12.01 EB0Z 15.04 urad', R_IDBB)

t = L(BB3['xy'])
t.fmap('angle_deg', lambda a: (a + 5.0) % 360.0)
t.write(fx('id_bb_start5_xy.csv'))
case('id_bb_start5', 'identify', 'angles', IDV % (BBPAR, fx('id_bb_start5_xy.csv') + ' ' + BB3['yz'] + ' ' + BB3['zx']),
     'XY table angles +5 deg (counted from late capture start)', 'clean EC0Y -19.996 urad, XY.centre -10.0/5.0', R_IDBB)

case('id_bb_two_planes_legit', 'identify', 'clean (legit different)', IDV % ('EC0Y,EA0Z,EXX:2,EYY:2,EZZ:2', BB3['xy'] + ' ' + BB3['yz']),
     'nothing wrong: XY and YZ tables only (ZX plane not measured), fitting EC0Y, EA0Z and the scales', 'EC0Y ~ -20.0, EA0Z ~ 12 urad (truth), no caution', '-', 'legit')

# ============================================================ analyze drift
R_ETVE = 'an_dr_etve'
t = L(ETVE)
for r in t.rows:
    if abs(float(r[0]) - 200.0) < 1e-6:
        r[t.col('z_um')] = F(float(r[t.col('z_um')]) + 15.0)
t.write(fx('dr_z_spike.csv'))
case('dr_z_spike', 'analyze drift', 'disturbed single reading', AND + fx('dr_z_spike.csv'),
     'one Z reading +15 um at 200 min (a knock on the nest)', 'clean Z ETVE 0.750 um, whole 3.14; spike gives ETVE ~15', R_ETVE)

t = L(ETVE)
t.map('temp_air_degc', lambda s: '20.010000')
t.write(fx('dr_air_stuck.csv'))
case('dr_air_stuck', 'analyze drift', 'stuck sensor', AND + fx('dr_air_stuck.csv'),
     'air temperature sensor stuck at 20.01 C for the whole 8 h (logger repeating)', 'clean dT ~0.6 C per window; stuck gives dT 0 (the ETVE environment unrecorded)', R_ETVE)

t = L(ETVE)
t.rows = [r for r in t.rows if not (200.0 <= float(r[0]) < 260.0)]
t.write(fx('dr_gap.csv'))
case('dr_gap_tol', 'analyze drift', 'dropout (tolerant)', AND + fx('dr_gap.csv'),
     'logger dropout: rows 200..259 min missing', 'figures near clean; caution acceptable', R_ETVE, 'tolerant')

t = L(ETVE)
rows = t.rows[:]
random.shuffle(rows)
write_raw('dr_shuffled_legit.csv', t.pre, t.header, rows)
case('dr_shuffled_legit', 'analyze drift', 'clean (legit different)', AND + fx('dr_shuffled_legit.csv'),
     'nothing wrong: rows in random order (time intact)', 'clean figures', R_ETVE, 'legit')

t = L(ETVE)
h = t.header + ['humidity_pct', 'pressure_hpa', 'date']
rows = [r + ['45.0', '1005.2', '2024-05-06'] for r in t.rows]
write_raw('dr_extra_cols_legit.csv', t.pre, h, rows)
case('dr_extra_cols_legit', 'analyze drift', 'clean (legit different)', AND + fx('dr_extra_cols_legit.csv'),
     'nothing wrong: extra columns humidity_pct, pressure_hpa, date', 'clean figures', R_ETVE, 'legit')

t = L(ETVE)
j = t.col('x2_um')
base = None
for r in t.rows:
    if float(r[0]) >= 240.0:
        if base is None:
            base = float(r[j])
        r[j] = F(float(r[j]) - base)
t.write(fx('dr_x2_rezero.csv'))
case('dr_x2_rezero', 'analyze drift', 'offsets (re-zeroed)', AND + fx('dr_x2_rezero.csv'),
     'X2 sensor re-zeroed at 240 min (someone pressed zero on the amplifier): step of %.2f um in X2 only' % -base,
     'clean X2 whole -6.34, B tilt -1.7 urad whole', R_ETVE)

t = L(ETVE)
t.fmap('y1_um', lambda x: -x)
t.write(fx('dr_y1_sign.csv'))
case('dr_y1_sign', 'analyze drift', 'angles/sense', AND + fx('dr_y1_sign.csv'),
     'Y1 sensor mounted reversed (sign of y1 only)', 'clean Y1 whole 3.55, A whole 2.2 urad; A = (Y1-Y2)/l becomes a sum -> ~70 urad', R_ETVE)

case('dr_etve30_legit', 'analyze drift', 'clean (legit different)', AND + ETVE + ' --etve-min 30',
     'nothing wrong: ETVE for a 30 min test', 'ETVE smaller than for 60 min; no caution', '-', 'legit')

t = L(SDR)
t.del_pre('spacing_mm')
t.write(fx('sd_nospacing.csv'))
case('sd_spacing_flag_legit', 'analyze drift', 'clean (legit different)', AND + fx('sd_nospacing.csv') + ' --spacing-mm 150',
     'nothing wrong: spacing_mm missing from preamble, given by --spacing-mm 150', 'clean spindle-drift figures', 'an_dr_sp', 'legit')

t = L(ETVE)
write_raw('dr_tsv.csv', t.pre, t.header, t.rows, sep='\t')
case('dr_tsv', 'analyze drift', 'format', AND + fx('dr_tsv.csv'),
     'tab-separated drift log saved as .csv', 'clean figures or clear refusal', R_ETVE)

# ============================================================ analyze spindle
R_SP = 'an_sp'
t = L(SP)
j = t.col('x1_um')
n = 0
for r in t.rows:
    if r[t.col('speed_rpm')] == '6000.000' and r[1] == '5':
        if n < 300:
            r[j] = '0.000000'
        n += 1
t.write(fx('sp_x1_dropout0.csv'))
case('sp_x1_dropout0', 'analyze spindle', 'dropout reading 0', ANS + fx('sp_x1_dropout0.csv'),
     'x1 reads 0.000 for 300 samples in revolution 5 at 6000 rpm (signal lost, amplifier outputs 0)', 'clean 6000 rpm x1 async small (~0.2 um); dropout makes async ~ several um', R_SP)

t = L(SP)
j = t.col('y1_um')
for r in t.rows:
    if r[t.col('speed_rpm')] == '2000.000' and r[1] == '7' and r[2] == '90.000000':
        r[j] = F(float(r[j]) + 3.0)
t.write(fx('sp_y1_spike.csv'))
case('sp_y1_spike', 'analyze spindle', 'disturbed single reading', ANS + fx('sp_y1_spike.csv'),
     'one y1 sample +3 um (electrical spike) at 2000 rpm rev 7, 90 deg', 'clean 2000 rpm y1 LSC total 0.684 async 0.138; spike -> async ~3', R_SP)

t = L(SP)
t.fmap('angle_deg', lambda a: (a + 37.0) % 360.0)
t.write(fx('sp_index37_legit.csv'))
case('sp_index37_legit', 'analyze spindle', 'clean (legit different)', ANS + fx('sp_index37_legit.csv'),
     'nothing wrong: angle zero at the encoder index, 37 deg from the previous zero (all angles +37 mod 360)', 'same error motion values', R_SP, 'legit')

t = L(SP)
h = t.header + ['temp_spindle_degc', 'sample']
rows = [r + ['22.5', str(k)] for k, r in enumerate(t.rows)]
write_raw('sp_extra_cols_legit.csv', t.pre, h, rows)
case('sp_extra_cols_legit', 'analyze spindle', 'clean (legit different)', ANS + fx('sp_extra_cols_legit.csv'),
     'nothing wrong: extra columns temp_spindle_degc and sample index', 'same values', R_SP, 'legit')

t = L(SP)
t.rows = [r for r in t.rows if r[1] != '19']
t.set_pre('revolutions', '19')
t.write(fx('sp_19rev_legit.csv'))
case('sp_19rev_legit', 'analyze spindle', 'clean (legit different)', ANS + fx('sp_19rev_legit.csv'),
     'nothing wrong: 19 revolutions per speed (last one not recorded), preamble says 19', 'values within a few % (async from 19 revs)', R_SP, 'legit')

t = L(SP)
j = t.col('speed_rpm')
for r in t.rows:
    s = float(r[j])
    r[j] = '%.1f' % (s + random.uniform(-0.6, 0.6) * s / 2000)
t.write(fx('sp_speed_jitter_legit.csv'))
case('sp_speed_jitter_legit', 'analyze spindle', 'clean (legit different)', ANS + fx('sp_speed_jitter_legit.csv'),
     'nothing wrong: speed_rpm holds the measured speed with 0.03 % jitter (1999.7, 2000.4 ...)', 'same values, 3 speeds', R_SP, 'legit')

t = L(SP)
j = t.col('speed_rpm')
sp_i = {'2000.000': 0, '6000.000': 1, '12000.000': 2}
t.map('revolution', lambda s: s)
for r in t.rows:
    r[1] = str(int(r[1]) + 20 * sp_i[r[j]])
t.write(fx('sp_rev_continuous_legit.csv'))
case('sp_rev_continuous_legit', 'analyze spindle', 'clean (legit different)', ANS + fx('sp_rev_continuous_legit.csv'),
     'nothing wrong: revolution numbered 0..59 through the record instead of restarting per speed', 'same values', R_SP, 'legit')

t = L(CA)
j = t.col('y_um')
for r in t.rows:
    if r[t.col('speed_rpm')] == '10.000' and int(r[1]) >= 10:
        r[j] = F(float(r[j]) * 0.5)
t.write(fx('ca_y_range_switch.csv'))
case('ca_y_range_switch', 'analyze spindle', 'units (one block)', ANS + fx('ca_y_range_switch.csv'),
     'y probe amplifier range switched mid-record: from rev 10 at 10 rpm y reads half (gain 0.5)', 'clean 10 rpm y values ~ 0.9 um LSC; half-gain block doubles async', 'an_ca')

# ============================================================ analyze rtest / identify rtest
R_RT = 'an_rt'
R_IDT5 = 'id_t5'


def rt_rezero(t):
    rr = [r for r in t.rows if r[0] == 'CK1 A0']
    b = [float(rr[18][t.col(c)]) for c in ('dx_um', 'dy_um', 'dz_um')]
    for r in rr[18:]:
        for k, c in enumerate(('dx_um', 'dy_um', 'dz_um')):
            r[t.col(c)] = '%.4f' % (float(r[t.col(c)]) - b[k])
    return b


t = L(RT)
b = rt_rezero(t)
t.write(fx('rt_rezero_mid.csv'))
case('rt_rezero_mid_an', 'analyze rtest', 'offsets (re-zeroed)', ANR + fx('rt_rezero_mid.csv'),
     'R-test re-zeroed at pose 18 of CK1 A0 (zero pressed mid-test; step %.1f %.1f %.1f um)' % tuple(b),
     'clean CK1 A0 range X 33.033 Y 32.806 radius 16.543', R_RT)
case('rt_rezero_mid_id', 'identify', 'offsets (re-zeroed)', IDT5 % fx('rt_rezero_mid.csv'),
     'same table, identify location', 'clean EX0C 11.94 EY0C -7.92 EA0C 25.1 ...', R_IDT5)

t = L(RT)
for name in ('CK1 A-45', 'AK1 C0', 'AC simultaneous'):
    rr = [r for r in t.rows if r[0] == name]
    t0 = float(rr[0][2])
    for r in rr:
        r[2] = '%.4f' % (float(r[2]) - t0)
t.write(fx('rt_time_restart_legit.csv'))
case('rt_time_restart_legit', 'identify', 'clean (legit different)', IDT5 % fx('rt_time_restart_legit.csv'),
     'nothing wrong: time_s restarts at 0 for every test', 'clean estimates', R_IDT5, 'legit')

t = L(RT)
h = t.header + ['temp_degc', 'comment']
rows = [r + ['20.3', ''] for r in t.rows]
write_raw('rt_extra_cols_legit.csv', t.pre, h, rows)
case('rt_extra_cols_legit', 'analyze rtest', 'clean (legit different)', ANR + fx('rt_extra_cols_legit.csv'),
     'nothing wrong: extra columns temp_degc and (empty) comment', 'clean figures', R_RT, 'legit')

t = L(RT)
t.rows = [r for r in t.rows if r[0] != 'AC simultaneous']
t.write(fx('rt_no_ac_legit.csv'))
case('rt_no_ac_legit_id', 'identify', 'clean (legit different)', IDT5 % fx('rt_no_ac_legit.csv'),
     'nothing wrong: the AC simultaneous test not run (three K-tests: C at A0, C at A-45, A swing)', 'location estimates near clean (within their u)', R_IDT5, 'legit')

t = L(RT)
t.del_pre('sphere_mm')
t.write(fx('rt_nosphere.csv'))
case('rt_sphere_flag_legit_id', 'identify', 'clean (legit different)', IDT5 % fx('rt_nosphere.csv') + ' --rtest-sphere-mm 100,0,250',
     'nothing wrong: sphere_mm not in the preamble, given by --rtest-sphere-mm 100,0,250', 'clean estimates', R_IDT5, 'legit')

case('rt_free_setup_legit_id', 'identify', 'clean (legit different)', IDT5 % RT + ' --free-setup',
     'nothing wrong: --free-setup on the clean table', 'estimates near clean (larger u)', R_IDT5, 'legit')

t = L(RT)
rr = [r for r in t.rows if r[0] == 'CK1 A0']
t.rows.remove(rr[10])
t.write(fx('rt_pose_dropout.csv'))
case('rt_pose_dropout_id', 'identify', 'dropout (tolerant)', IDT5 % fx('rt_pose_dropout.csv'),
     'one pose (CK1 A0, C 100 deg) missing from the export', 'clean estimates within u', R_IDT5, 'tolerant')

t = L(RT)
rr = [r for r in t.rows if r[0] == 'CK1 A-45']
j = t.col('dy_um')
v = rr[20][j]
for r in rr[20:]:
    r[j] = v
t.write(fx('rt_dy_stuck.csv'))
case('rt_dy_stuck_id', 'identify', 'stuck sensor', IDT5 % fx('rt_dy_stuck.csv'),
     'dy stuck from pose 20 of CK1 A-45 (probe at the end of its range)', 'clean estimates; caution or refusal expected', R_IDT5)
case('rt_dy_stuck_an', 'analyze rtest', 'stuck sensor', ANR + fx('rt_dy_stuck.csv'),
     'dy stuck from pose 20 of CK1 A-45', 'clean CK1 A-45 range Y 20.855 radius 15.780', R_RT)

t = L(RT)
for c in ('x_mm', 'y_mm', 'z_mm'):
    t.fmap(c, lambda x: round(x), '%.0f')
t.write(fx('rt_xyz_round1mm.csv'))
case('rt_xyz_round1mm_id', 'identify', 'resolution/rounding', IDT5 % fx('rt_xyz_round1mm.csv'),
     'x_mm, y_mm, z_mm rounded to whole mm by the export (dx..dz intact)', 'clean estimates (positions are informative only) or a caution', R_IDT5)

t = L(RT)
for c in ('dx_um', 'dy_um', 'dz_um'):
    t.fmap(c, lambda x: x / 1000.0, '%.7f')
    t.rename(c, c.replace('_um', '_mm'))
t.write(fx('rt_dmm_header.csv'))
case('rt_dmm_header_id', 'identify', 'units (named)', IDT5 % fx('rt_dmm_header.csv'),
     'deviations exported in mm with headers dx_mm, dy_mm, dz_mm (unit in the name)', 'convert (clean) or refuse naming the columns', R_IDT5)

# ============================================================ analyze probe
t = L(PRR)
rr = [r for r in t.rows if r[1] == 'ring']
t.rows.remove(rr[7])
t.write(fx('pr_ring35_legit.csv'))
case('pr_ring35_legit', 'analyze probe', 'clean (legit different)', ANPR + fx('pr_ring35_legit.csv'),
     'nothing wrong: ring with 35 touches (one point skipped)', 'diameter error ~ +3.4 um, roundness ~2.3', 'an_pr_ring', 'legit')

t = L(PRS)
rr = [r for r in t.rows if r[2] == '3']
rr[0][t.col('x_mm')] = F(float(rr[0][t.col('x_mm')]) + 0.02)
t.write(fx('pr_sph_touch_glitch.csv'))
case('pr_sph_touch_glitch', 'analyze probe', 'disturbed single reading', ANPR + fx('pr_sph_touch_glitch.csv'),
     'one touch of sphere 3 (touch 1, approach along -x) latched 20 um off in x (swarf on the sphere)', 'clean sphere 3 centre (264.9933, 275.0237, 50.0016), form 0.012', 'an_pr_sph')

t = L(PRP)
cyc = [r for r in t.rows if r[0] == '2']
cols = [t.col(c) for c in ('cal_x_mm', 'cal_y_mm', 'cal_z_mm')]
cal = {}
for r in cyc:
    cal[int(r[2])] = [r[c] for c in cols]
for r in cyc:
    f = int(r[2])
    src = cal[f - 1] if f > 1 else cal[20]
    for k, c in enumerate(cols):
        r[c] = src[k]
t.write(fx('pr_plate_cal_shift.csv'))
case('pr_plate_cal_shift', 'analyze probe', 'preamble/cert contradicts', ANPR + fx('pr_plate_cal_shift.csv'),
     'cycle 2 certificate columns pasted one ball down (ball k gets ball k-1 calibrated centre)', 'clean cycle 2 max error 5.8 um; refusal/caution expected', 'an_pr_plate')

t = L(PRR)
write_raw('pr_ring_bom_crlf_legit.csv', t.pre, t.header, t.rows, eol='\r\n', bom=True)
case('pr_ring_bom_crlf_legit', 'analyze probe', 'clean (legit different)', ANPR + fx('pr_ring_bom_crlf_legit.csv'),
     'nothing wrong: BOM and CRLF', 'clean figures', 'an_pr_ring', 'legit')

t = L(PRR)
rows = t.rows[:]
random.shuffle(rows)
write_raw('pr_ring_shuffled_legit.csv', t.pre, t.header, rows)
case('pr_ring_shuffled_legit', 'analyze probe', 'clean (legit different)', ANPR + fx('pr_ring_shuffled_legit.csv'),
     'nothing wrong: touch rows in random order', 'clean figures', 'an_pr_ring', 'legit')

t = L(PRR)
t.del_pre('stylus_radius_mm')
t.write(fx('pr_ring_nostylus.csv'))
case('pr_ring_stylus_flag_legit', 'analyze probe', 'clean (legit different)', ANPR + fx('pr_ring_nostylus.csv') + ' --stylus-radius-mm 1.5',
     'nothing wrong: stylus radius by flag (preamble lacks it)', 'clean figures', 'an_pr_ring', 'legit')

t = L(PRR)
for r in t.rows:
    for c in ('i', 'j', 'k'):
        r[t.col(c)] = '%.6f' % (float(r[t.col(c)]) * 2.0)
t.write(fx('pr_ring_ijk_unnorm.csv'))
case('pr_ring_ijk_unnorm', 'analyze probe', 'format', ANPR + fx('pr_ring_ijk_unnorm.csv'),
     'approach vectors not normalised (|ijk| = 2: the export wrote the approach distance 2 mm along it)', 'normalise (clean figures) or refuse', 'an_pr_ring')

t = L(PRR)
rr = [r for r in t.rows if r[1] == 'ring']
rr[12][t.col('cal_diameter_mm')] = '50.500000'
t.write(fx('pr_ring_cal_row_typo.csv'))
case('pr_ring_cal_row_typo', 'analyze probe', 'disturbed single reading', ANPR + fx('pr_ring_cal_row_typo.csv'),
     'cal_diameter_mm differs on one row of the ring (50.5 on touch 13, 50.0 elsewhere)', 'clean error +3.427 um; which certificate value is used must be stated or refused', 'an_pr_ring')

# ============================================================ identify spheres
R_IDSPH = 'id_sph'
t = L(SPH)
for r in t.rows:
    if r[2] == '6':
        r[t.col('a_deg')] = '30.000000'
t.write(fx('sph_a_typo.csv'))
case('sph_a_typo_id', 'identify', 'disturbed single reading', IDT5 % fx('sph_a_typo.csv'),
     'sphere 6 a_deg typed 30 instead of -30 (centre measured at A -30)', 'clean EB0C 31.3 EX0C -7.94 ...; fit must fail its checks', R_IDSPH)

t = L(SPH)
rows = t.rows[:]
random.shuffle(rows)
write_raw('sph_shuffled_legit.csv', t.pre, t.header, rows)
case('sph_shuffled_legit_id', 'identify', 'clean (legit different)', IDT5 % fx('sph_shuffled_legit.csv'),
     'nothing wrong: sphere rows in random order', 'clean estimates', R_IDSPH, 'legit')

t = L(SPH)
h = t.header + ['operator']
rows = [r + ['JS'] for r in t.rows]
write_raw('sph_extra_col_legit.csv', t.pre, h, rows)
case('sph_extra_col_legit_id', 'identify', 'clean (legit different)', IDT5 % fx('sph_extra_col_legit.csv'),
     'nothing wrong: extra column operator', 'clean estimates', R_IDSPH, 'legit')

t = L(SPH)
for r in t.rows:
    if r[2] == '7':
        r[t.col('z_mm')] = F(float(r[t.col('z_mm')]) + 0.01)
t.write(fx('sph_one_z10.csv'))
case('sph_one_z10_id', 'identify', 'disturbed single reading', IDT5 % fx('sph_one_z10.csv'),
     'sphere 7 centre z 10 um high (swarf under the probe on one sphere)', 'clean estimates; 10 um on one of 8 spheres biases several', R_IDSPH)

# ============================================================ identify laser (est_laser_X)
R_IDL = 'id_elx'
t = L(LX)
rows = t.rows[:]
random.shuffle(rows)
write_raw('idl_shuffled_legit.csv', t.pre, t.header, rows)
case('idl_shuffled_legit', 'identify', 'clean (legit different)', IDV % ('EXX:2', fx('idl_shuffled_legit.csv')),
     'nothing wrong: laser rows in random order', 'clean EXX[1] 0.0120', R_IDL, 'legit')

t = L(LX)
write_raw('idl_crlf_quoted_legit.csv', t.pre, t.header, t.rows, eol='\r\n', quote=True)
case('idl_crlf_quoted_legit', 'identify', 'clean (legit different)', IDV % ('EXX:2', fx('idl_crlf_quoted_legit.csv')),
     'nothing wrong: CRLF, all fields quoted', 'clean EXX[1] 0.0120', R_IDL, 'legit')

t = L(LX)
first = {}
for r in t.rows:
    k = (r[1], r[2])
    if k not in first:
        first[k] = float(r[4])
    r[4] = F(float(r[4]) - first[k])
t.write(fx('idl_rezero_pass.csv'))
case('idl_rezero_pass', 'identify', 'offsets (re-zeroed)', IDV % ('EXX:2', fx('idl_rezero_pass.csv')),
     'laser re-zeroed at the start of every pass (down passes start at 0 at 750 mm), preamble zero = once',
     'clean EXX[1] 0.0120 EXX[2] -8e-6', R_IDL)

case('idl_sigma_legit', 'identify', 'clean (legit different)', IDV % ('EXX:2', LX) + ' --sigma-um positioning=0.03',
     'nothing wrong: --sigma-um positioning=0.03 (laser stated 30 nm)', 'same estimates, u x1.5', R_IDL, 'legit')

t = L(LX)
rr = rows_where(t, run='4', direction='-')
v = rr[0][4]
for r in rr:
    r[4] = v
t.write(fx('idl_stuck_pass.csv'))
case('idl_stuck_pass', 'identify', 'stuck sensor', IDV % ('EXX:2', fx('idl_stuck_pass.csv')),
     'laser hold: run 4 down pass repeats its first reading', 'clean EXX[1] 0.0120', R_IDL)

t = L(LX)
rows = []
for r in t.rows:
    if r[2] == '+' and r[3] == '10.000000':
        rows.append([r[0], r[1], '+', '5.000000', F(float(r[4]) - 0.06), F(float(r[5]) - 0.01)])
    rows.append(r)
write_raw('idl_overrun.csv', t.pre, t.header, rows)
case('idl_overrun_rows', 'identify', 'duplicated/extra data', IDV % ('EXX:2', fx('idl_overrun.csv')),
     'overrun stop at 5 mm exported as a reading (its deviation 0.06 um low)', 'clean EXX or caution', R_IDL)

# ============================================================ score
case('score_pretty_legit', 'score', 'clean (legit different)',
     'python3 -c "import json,sys; [json.dump(json.load(open(a)),open(b,\'w\'),indent=4,sort_keys=True) for a,b in ((\'{OUTDIR}/_ref/id_t5/estimate.json\',\'{OUTDIR}/{TAG}.est.json\'),(\'' + B + '/trunnion5_rtest/truth.json\',\'{OUTDIR}/{TAG}.truth.json\'))]" && {BIN} score {OUTDIR}/{TAG}.est.json {OUTDIR}/{TAG}.truth.json',
     'nothing wrong: estimate.json and truth.json re-serialised (indent 4, keys sorted)', 'same as score_t5 (comp RMS 0.557)', 'score_t5', 'legit')
for tag, src, truth, ref in (('score_idl_rezero', 'idl_rezero_pass', B + '/est_laser_X/truth.json', 'score_elx'),
                              ('score_rt_rezero', 'rt_rezero_mid_id', B + '/trunnion5_rtest/truth.json', 'score_t5'),
                              ('score_id_bb_start5', 'id_bb_start5', B + '/est_bb3/truth.json', 'score_bb3'),
                              ('score_sph_one_z10', 'sph_one_z10_id', B + '/trunnion5_probe_sphere/truth.json', 'score_sph'),
                              ('score_idl_stuck', 'idl_stuck_pass', B + '/est_laser_X/truth.json', 'score_elx')):
    case(tag, 'score', 'follow-up', '{BIN} score {OUTDIR}/%s/out/estimate.json %s' % (src, truth),
         'score of the %s estimate (no estimate means the wrong input was stopped earlier)' % src, 'see %s' % ref, ref)


# ============================================================ scenarios (check + run + analyze)
def scen(name, src, subs, crlf=False):
    txt = open(S + '/' + src).read().replace('"../models/', '"' + M + '/')
    for a, b in subs:
        n = len(re.findall(a, txt, flags=re.M))
        assert n >= 1, (name, a)
        txt = re.sub(a, b, txt, count=1, flags=re.M)
    p = SC + '/' + name + '.toml'
    with open(p, 'w', newline='') as f:
        f.write(txt.replace('\n', '\r\n') if crlf else txt)
    return p


def scase(tag, klass, src, subs, analyze, wrong, truth, ref='-', expect='wrong', crlf=False):
    p = scen(tag, src, subs, crlf)
    cmd = '{BIN} check %s && {BIN} run --out {OUTDIR}/{TAG} %s && %s' % (p, p, analyze)
    case(tag, 'run/check scenario', klass, cmd, wrong, truth, ref, expect)


scase('scen_bb_crlf_legit', 'clean (legit different)', 'vmc3_ballbar_xy.toml', [], ANB + '{OUTDIR}/{TAG}/ballbar_xy.csv',
      'nothing wrong: copy of vmc3_ballbar_xy.toml with CRLF line ends (edited on Windows)', 'clean ball-bar figures', R_BB, 'legit', crlf=True)
scase('scen_bb_res_nm', 'units', 'vmc3_ballbar_xy.toml', [(r'^resolution_um = 0\.1', 'resolution_um = 100.0')], ANB + '{OUTDIR}/{TAG}/ballbar_xy.csv',
      'ball-bar resolution_um = 100 (100 nm meant): every reading quantised to 100 um', 'check should flag resolution >> noise / bar range', R_BB)
scase('scen_bb_feed_mms', 'units', 'vmc3_ballbar_xy.toml', [(r'^feed_mm_per_min = 1000\.0', 'feed_mm_per_min = 16.7')], ANB + '{OUTDIR}/{TAG}/ballbar_xy.csv',
      'ball-bar feed_mm_per_min = 16.7 (mm/s value): a 56 min circle', 'check could flag an implausibly slow ball-bar feed; analysis self-consistent', '-')
scase('scen_etve_hours', 'units', 'vmc3_iso230_3_etve.toml', [(r'duration_min = 480\.0', 'duration_min = 8.0')], AND + '{OUTDIR}/{TAG}/drift.csv',
      'ETVE duration_min = 8 (8 h meant)', 'check should flag an ETVE record shorter than the 60 min test; analyze should refuse ETVE', '-')
scase('scen_etve_sample_s', 'units', 'vmc3_iso230_3_etve.toml', [(r'sample_min = 1\.0', 'sample_min = 60.0')], AND + '{OUTDIR}/{TAG}/drift.csv',
      'ETVE sample_min = 60 (60 s meant): 9 samples over 8 h', 'check/analyze should flag too few samples for a 60 min window', '-')
scase('scen_iso_runs1', 'wrong flags', 'vmc3_iso230_2.toml', [(r'^runs = 5', 'runs = 1')], ANP + '{OUTDIR}/{TAG}/positioning.csv',
      'iso230_2 runs = 1 (one run) : R from one run is 0', 'analyze must not report R = 0 as a repeatability without a caution (ISO 230-2 needs 5)', '-')
scase('scen_rt_points2', 'wrong flags', 'trunnion5_rtest.toml', [(r'^points = 37', 'points = 2')], ANR + '{OUTDIR}/{TAG}/rtest.csv',
      'first R-test with points = 2 over 0..360 deg: both poses at C 0', 'check should flag a 360 deg test with 2 points (same pose twice)', '-')
scase('scen_ambient_K', 'units', 'vmc3_iso230_3_etve.toml', [(r'ambient_degc = 20\.0', 'ambient_degc = 293.15')], AND + '{OUTDIR}/{TAG}/drift.csv',
      'thermal ambient_degc = 293.15 (kelvin)', 'check should flag 293 C ambient', '-')
scase('scen_sp_bw_khz', 'units', 'vmc3_spindle.toml', [(r'^bandwidth_hz = 10000\.0', 'bandwidth_hz = 10.0')], ANS + '{OUTDIR}/{TAG}/spindle.csv',
      'probe bandwidth_hz = 10 (10 kHz written in kHz): below the 33 Hz rotation at 2000 rpm', 'check should flag bandwidth below the rotation frequency; error motions attenuated x10-100', '-')

write_cases(T + '/cases.tsv', ['tag', 'kind', 'class', 'command', 'wrong', 'truth', 'ref', 'expect'], cases, T, HERE)
print(len(cases), 'cases')
