#!/usr/bin/env python3
"""Trial 3: generate the wrong-input fixtures under WORK/t3/fx and WORK/t3/cases.tsv (the committed
cases.tsv beside this file is a copy of it).  Clean tables: WORK/base (made by run.sh).
The scratch scenarios est_*.toml, iso230_2_b.toml, t5_rtest_b.toml are in scen/ beside this file.
Usage: python3 gen.py [WORK]  (WORK default /tmp/mtwin-trials; run.sh calls it).
"""
import math, os, sys, copy, random
HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True
sys.path.insert(0, os.path.join(HERE, '..', 'lib'))
from tab import Table
from trialpaths import REPO, WORK, BASE, MODELS, SCENARIOS, write_cases

T = os.path.join(WORK, 't3')       # this trial's generated data (never inside the repository)
B = BASE
FX = T + '/fx'

M = MODELS
S = SCENARIOS
os.makedirs(FX, exist_ok=True)
cases = []


def case(tag, kind, klass, cmd, wrong, truth):
    assert '\t' not in cmd + wrong + truth
    cases.append((tag, kind, klass, cmd, wrong, truth))


def fx(n):
    return FX + '/' + n


def load(p):
    return Table(p)


def rows_where(t, name, pred):
    j = t.col(name)
    return [r for r in t.rows if pred(r[j])]


def fmt(v, f='%.6f'):
    return f % v


ANP = '{BIN} analyze positioning '
ANB = '{BIN} analyze ballbar '
AND = '{BIN} analyze drift '
ANS = '{BIN} analyze spindle '
ANR = '{BIN} analyze rtest '
ANPR = '{BIN} analyze probe '
IDV = '{BIN} identify --machine ' + M + '/vmc3.urdf --params %s %s --out {OUTDIR}/{TAG}'
IDT5 = '{BIN} identify --machine ' + M + '/trunnion5.urdf --params location %s --out {OUTDIR}/{TAG}'

POS = B + '/vmc3_iso230_2/positioning.csv'
POSB = B + '/iso230_2_b/positioning.csv'
LX = B + '/est_laser_X/positioning.csv'
LY = B + '/est_laser_Y/positioning.csv'
LZ = B + '/est_laser_Z/positioning.csv'
WARM = B + '/vmc3_warmup_laser/positioning.csv'

# ============================================================ positioning: analyze
# P1 deviations exported in micro-inches (inch-mode laser software) in the _um column
t = load(POS).fmap('deviation_um', lambda v: v / 0.0254, '%.3f')
p = t.write(fx('pos_dev_uin.csv'))
case('pos_dev_uin', 'analyze positioning', 'units', ANP + p,
     'deviation_um holds micro-inches (x39.37), inch-mode export; targets still mm',
     'clean: E 11.355 um, A 11.443 um, R 3.108 um, B 3.024 um (all x39.37 if the slip passes)')

# P2 only run 3 in mm (one run exported after a units toggle)
t = load(POS)
j = t.col('deviation_um'); jr = t.col('run')
for r in t.rows:
    if r[jr] == '3':
        r[j] = '%.9f' % (float(r[j]) / 1000)
p = t.write(fx('pos_run3_mm.csv'))
case('pos_run3_mm', 'analyze positioning', 'units', ANP + p,
     'run 3 only: deviation_um in mm (/1000), other runs in um',
     'clean: R 3.108 um, A 11.443 um; run 3 reads ~0 at every target')

# P3 rows re-sorted by target then direction then run (spreadsheet sort) - data intact
t = load(POS)
jt, jd, jr = t.col('target_mm'), t.col('direction'), t.col('run')
t.rows.sort(key=lambda r: (float(r[jt]), r[jd], int(r[jr])))
p = t.write(fx('pos_sorted_target.csv'))
case('pos_sorted_target', 'analyze positioning', 'reordered', ANP + p,
     'rows re-sorted by target, direction, run (labels intact, time_min no longer monotonic)',
     'clean figures (same readings): E 11.355, A 11.443, R 3.108, B 3.024 um')

# P4 deviations rounded to 1 um (coarse export of a 1 nm laser)
t = load(POS).fmap('deviation_um', lambda v: round(v), '%.0f')
p = t.write(fx('pos_round1um.csv'))
case('pos_round1um', 'analyze positioning', 'resolution', ANP + p,
     'deviation_um rounded to whole um (export resolution 1 um) on a 20 nm-noise laser',
     'clean: R_up 0.102 um, R_down 0.143 um, s ~0.02-0.03 um (rounded: s = 0 or ~0.4-0.5 um)')

# P5 '+' direction from test A (lost motion 3 um), '-' direction from test B (lost motion 5 um, other day)
ta, tb = load(POS), load(POSB)
jd = ta.col('direction')
assert len(ta.rows) == len(tb.rows)
rows = []
for ra, rb in zip(ta.rows, tb.rows):
    assert ra[:4] == rb[:4]
    rows.append(ra if ra[jd] == '+' else rb[:5] + ra[5:])
ta.rows = rows
p = ta.write(fx('pos_mixdir.csv'))
case('pos_mixdir', 'analyze positioning', 'mixed sources', ANP + p,
     '+ direction readings from one test (lost motion 3 um), - direction readings from another test of the same axis (lost motion 5 um); times of test A kept',
     'clean (test A): B 3.024 um, mean reversal -2.998 um; test B: its own B; mix reports neither')

# P6 +2 um offset on run 4 only (laser re-zeroed between runs)
t = load(POS)
j = t.col('deviation_um'); jr = t.col('run')
for r in t.rows:
    if r[jr] == '4':
        r[j] = '%.6f' % (float(r[j]) + 2.0)
p = t.write(fx('pos_run4_off2.csv'))
case('pos_run4_off2', 'analyze positioning', 'offsets', ANP + p,
     'run 4 only: +2 um offset at every target (laser re-zeroed before run 4), preamble zero = once',
     'clean: R_up 0.102 um, R_down 0.143 um, R 3.108 um')

# P7 header names of deviation_um and time_min swapped (columns reordered in the export, renamed)
t = load(POS).swap_cols('deviation_um', 'time_min')
p = t.write(fx('pos_dev_time_hdrswap.csv'))
case('pos_dev_time_hdrswap', 'analyze positioning', 'swapped', ANP + p,
     'header names deviation_um and time_min exchanged (deviation column holds the clock 0..35 min)',
     'clean: E 11.355 um; the "deviations" rise monotonically with row order')

# P8 direction column dropped (unidirectional export of a bidirectional test)
t = load(POS).drop('direction')
p = t.write(fx('pos_nodir.csv'))
case('pos_nodir', 'analyze positioning', 'missing column', ANP + p,
     'direction column dropped from a bidirectional test; each run visits every target twice',
     'clean: bidirectional, B 3.024 um, R 3.108 um')

# P9 columns reordered with renamed headers (foreign export: Position/Error), prefix used
t = load(POS).del_pre()
t.rename('target_mm', 'position_mm').rename('deviation_um', 'error_um')
p = t.write(fx('pos_renamed_hdr.csv'))
case('pos_renamed_hdr', 'analyze positioning', 'renamed columns', ANP + p,
     'foreign export, no preamble, headers position_mm / error_um instead of target_mm / deviation_um',
     'should be refused (required columns missing) or read correctly: E 11.355 um')

# P10 warm-up record: one temperature sensor in degF (only temp column)
t = load(WARM).fmap('temp_x_nut_degc', lambda v: v * 1.8 + 32, '%.6f')
p = t.write(fx('pos_temp_F.csv'))
case('pos_temp_F', 'analyze positioning', 'units', ANP + p,
     'temp_x_nut_degc in degF (68..77) in a warm-up laser record',
     'clean: x_nut 20..~25 degC, per-target um/degC sensitivities; in degF they shrink by 1.8')

# P11 preamble runs = 3 but 5 runs in data, preamble targets in a different order / subset
t = load(POS).set_pre('runs', '3')
p = t.write(fx('pos_pre_runs3.csv'))
case('pos_pre_runs3', 'analyze positioning', 'preamble contradicts', ANP + p,
     'preamble runs = 3 but the data hold 5 runs',
     'clean: 5 runs; figures should use 5 runs or note the contradiction')

# P12 X test table with its machine preamble saying trunnion5 (exported from the wrong job)
t = load(POS).set_pre('machine', 'trunnion5')
p = t.write(fx('pos_pre_machine_t5.csv'))
case('pos_pre_machine_t5_id', 'identify', 'provenance', IDV % ('EXX:2', p),
     'vmc3 X laser table whose preamble says machine = trunnion5, identified on vmc3.urdf',
     'refusal (machine mismatch) expected; data are vmc3 (lost motion -> chi2 door anyway)')

# ============================================================ positioning: identify
# I1 targets in workpiece coordinates (G54 zero at X = 380 mm): -370..370
t = load(LX).fmap('target_mm', lambda v: v - 380.0)
tg = [float(x) - 380 for x in [l for l in t.pre if l.startswith('# targets_mm')][0].split('=')[1].split(',')]
t.set_pre('targets_mm', ', '.join('%.6f' % x for x in tg))
p = t.write(fx('id_pos_g54.csv'))
case('id_pos_g54', 'identify', 'travel/coords', IDV % ('EXX:2', p),
     'laser targets in workpiece coordinates (G54 X zero at machine X 380): -370..+370 mm',
     'EXX.polynomial[1] 0.0120 um/mm, [2] -8.0e-6 um/mm^2 (machine coords 10..750)')

# I2 --sigma-um positioning=2 (MPE of the laser system given instead of the reading noise)
case('id_sigma_x100', 'identify', 'units', IDV % ('EXX:2 --sigma-um positioning=2', LX),
     '--sigma-um positioning=2 (2 um: an MPE, 100x the 0.02 um reading noise)',
     'EXX.polynomial[1] 0.0120 u 1.8e-5 um/mm (100x larger u with this flag)')

# I3 targets exported rounded to 0.1 mm and deviations to 0.01 um: mild, should be FINE
t = load(LX).fmap('target_mm', lambda v: round(v, 1), '%.1f').fmap('deviation_um', lambda v: round(v, 2), '%.2f')
p = t.write(fx('id_pos_round.csv'))
case('id_pos_round', 'identify', 'resolution', IDV % ('EXX:2', p),
     'targets rounded to 0.1 mm and deviations to 0.01 um in the export (preamble targets exact)',
     'EXX.polynomial[1] 0.0120 um/mm (tiny change expected)')

# I4 Y table with targets on negative machine Y (controller travel 0..-410) and deviation sign kept
t = load(LY).fmap('target_mm', lambda v: -v)
tg = [-float(x) for x in [l for l in t.pre if l.startswith('# targets_mm')][0].split('=')[1].split(',')]
t.set_pre('targets_mm', ', '.join('%.6f' % x for x in tg))
p = t.write(fx('id_posY_neg.csv'))
case('id_posY_neg', 'identify', 'travel/coords', IDV % ('EYY:2', p),
     'Y laser targets written as negative machine positions (0..-410, Fanuc-style negative travel)',
     'EYY.polynomial[1] -0.0100 um/mm, [2] 6.0e-6 um/mm^2')

# I5 X table + Y table where the Y table carries +0.3 um offset on one direction only (mild) - skip
# I6 run 3 of est_laser_X in mm (/1000) in the identify path
t = load(LX)
j = t.col('deviation_um'); jr = t.col('run')
for r in t.rows:
    if r[jr] == '3':
        r[j] = '%.9f' % (float(r[j]) / 1000)
p = t.write(fx('id_pos_run3_mm.csv'))
case('id_pos_run3_mm', 'identify', 'units', IDV % ('EXX:2', p),
     'est_laser_X with run 3 deviations in mm (/1000)',
     'EXX.polynomial[1] 0.0120 um/mm')

# I7 est_laser_X with +0.1 um offset on run 3 only (slight re-zero) - honest: small
t = load(LX)
j = t.col('deviation_um'); jr = t.col('run')
for r in t.rows:
    if r[jr] == '3':
        r[j] = '%.6f' % (float(r[j]) + 0.1)
p = t.write(fx('id_pos_run3_off.csv'))
case('id_pos_run3_off', 'identify', 'offsets', IDV % ('EXX:2', p),
     'est_laser_X run 3 offset by +0.1 um (laser re-zeroed); preamble zero = once',
     'EXX.polynomial[1] 0.0120 um/mm; u should grow (Birge) or door')

# I8 est_laser_X with --scenario of est_laser_Y (compensate another scenario)
case('id_scen_other_laser', 'identify', 'provenance',
     IDV % ('EXX:2 --scenario ' + HERE + '/scen/est_laser_Y.toml', LX),
     'X laser table (with provenance) identified with --scenario of est_laser_Y (other scenario, same machine)',
     'compensated.toml should belong to est_laser_X; refusal or caution expected')

# I9 deviations in micro-inches, identify
t = load(LX).fmap('deviation_um', lambda v: v / 0.0254, '%.3f')
p = t.write(fx('id_pos_uin.csv'))
case('id_pos_uin', 'identify', 'units', IDV % ('EXX:2', p),
     'est_laser_X deviation_um holds micro-inches (x39.37)',
     'EXX.polynomial[1] 0.0120 um/mm (x39.37 -> 0.472)')

# I10 laser table of Z axis labelled X with x_mm preamble removed (foreign export of the other axis)
t = load(LZ)
t.set_pre('axis', 'X').del_pre('x_mm').del_pre('y_mm').del_pre('z_mm')
t.set_pre('y_mm', '205').set_pre('z_mm', '100')
t.map('axis', lambda s: 'X')
p = t.write(fx('id_posZ_as_X.csv'))
case('id_posZ_as_X', 'identify', 'provenance', IDV % ('EXX:2', p),
     'Z-axis laser table relabelled axis X (column+preamble) and its parking preamble rewritten to an X test (y 205, z 100)',
     'data are EZZ (0.015 um/mm, -4e-6); EXX truth 0.0120 um/mm, -8e-6')

# ============================================================ ballbar: analyze
BB = B + '/vmc3_ballbar_xy/ballbar_xy.csv'
# B1 radius in inches in preamble, time_s present
t = load(BB).set_pre('radius_mm', '5.905512')
p = t.write(fx('bb_radius_inch.csv'))
case('bb_radius_inch', 'analyze ballbar', 'units', ANB + p,
     'preamble radius_mm = 5.9055 (150 mm bar written in inches); time_s present (16.67 mm/s at 6.37 deg/s implies R 150)',
     'clean: squareness 20.016 um/m, scale 12.162 ppm')

# B2 radius 300 (circle diameter given) with time_s present
t = load(BB).set_pre('radius_mm', '300')
p = t.write(fx('bb_radius_diam.csv'))
case('bb_radius_diam', 'analyze ballbar', 'units', ANB + p,
     'preamble radius_mm = 300 (circle diameter given), time_s present: time and angle step imply R = 150',
     'clean: squareness 20.016 um/m, scale 12.162 ppm')

# B3 feed in mm/s in the mm/min field
t = load(BB).set_pre('feed_mm_per_min', '16.667')
p = t.write(fx('bb_feed_mms.csv'))
case('bb_feed_mms', 'analyze ballbar', 'units', ANB + p,
     'preamble feed_mm_per_min = 16.667 (mm/s written), time_s present and consistent with 1000 mm/min',
     'clean: servo mismatch -0.458 ms at 1000 mm/min')

# B4 sample rate wrong in preamble (1000 Hz) while time_s steps by 4 ms
t = load(BB).set_pre('sample_rate_hz', '1000')
p = t.write(fx('bb_rate1000.csv'))
case('bb_rate1000', 'analyze ballbar', 'preamble contradicts', ANB + p,
     'preamble sample_rate_hz = 1000 but time_s steps by 4 ms (250 Hz)',
     'clean figures (rate not needed when time_s is present) or a contradiction note')

# B5 ccw from vmc3_ballbar_xy (1000 mm/min), cw from est_bb3 XY (other machine state, 500 mm/min)
ta, tb = load(BB), load(B + '/est_bb3/ballbar_xy.csv')
jd = ta.col('direction')
ta.rows = [r for r in ta.rows if r[jd] == 'ccw'] + [r for r in tb.rows if r[jd] == 'cw']
p = ta.write(fx('bb_mix_two_tests.csv'))
case('bb_mix_two_tests', 'analyze ballbar', 'mixed sources', ANB + p,
     'ccw run from vmc3_ballbar_xy (1000 mm/min, backlash etc.), cw run from est_bb3 XY (500 mm/min, no lost motion, other seed); preamble of the first',
     'clean vmc3_ballbar_xy: backlash_x 4.0, servo mismatch -0.458 ms, G 11.999 um')

# B6 plane written XZ for the ZX table (axis order reversed)
t = load(B + '/vmc3_ballbar_3planes/ballbar_zx.csv').set_pre('plane', 'XZ')
p = t.write(fx('bb_plane_XZ.csv'))
case('bb_plane_XZ', 'analyze ballbar', 'angles/sense', ANB + p,
     'ZX ball-bar table with preamble plane = XZ (axis order reversed: angle from +X toward +Z would mirror sense)',
     'clean ZX: squareness and backlash of the ZX analysis (ref an_bb3_zx)')

# B7 deviations rounded to 1 um
t = load(BB).fmap('deviation_um', lambda v: round(v), '%.0f')
p = t.write(fx('bb_round1um.csv'))
case('bb_round1um', 'analyze ballbar', 'resolution', ANB + p,
     'deviation_um rounded to whole um (coarse export of a 0.1 um ball-bar)',
     'clean: G 11.999, squareness 20.016 um/m, backlash_x 4.000 um (figures should survive, noise estimate rises)')

# B8 whole table sorted by angle (ccw and cw rows interleaved; time_s non-monotonic)
t = load(BB)
ja = t.col('angle_deg')
t.rows.sort(key=lambda r: float(r[ja]))
p = t.write(fx('bb_sorted_angle.csv'))
case('bb_sorted_angle', 'analyze ballbar', 'reordered', ANB + p,
     'rows sorted by angle_deg (ccw and cw interleaved; time_s no longer monotonic) - labels intact',
     'clean figures (same readings) or refusal on non-monotonic time')

# B9 deviation offset +40 um (bar length not calibrated: calibrator reference length wrong)
t = load(BB).fmap('deviation_um', lambda v: v + 40.0, '%.6f')
p = t.write(fx('bb_barlen40.csv'))
case('bb_barlen40', 'analyze ballbar', 'offsets', ANB + p,
     'every deviation +40 um (calibrator length wrong); G/squareness unaffected, radius deviation +40',
     'clean: radius deviation c0 and scale from ref; shape figures unchanged')

# B10 cw block deviations x10 only (second run exported in 0.1 um counts)
t = load(BB)
jd, jv = t.col('direction'), t.col('deviation_um')
for r in t.rows:
    if r[jd] == 'cw':
        r[jv] = '%.6f' % (float(r[jv]) * 10)
p = t.write(fx('bb_cw_x10.csv'))
case('bb_cw_x10', 'analyze ballbar', 'units', ANB + p,
     'cw run only: deviation in 0.1 um counts (x10), ccw run in um',
     'clean: G ccw 8.232 / cw 11.897 um, backlash_x 4.0 um')

# B11 identify: deviation sign flipped (inward +, foreign convention) in all three est_bb3 tables
fs = []
for pl in ('xy', 'yz', 'zx'):
    t = load(B + '/est_bb3/ballbar_%s.csv' % pl).fmap('deviation_um', lambda v: -v, '%.6f')
    fs.append(t.write(fx('bb_sign_%s.csv' % pl)))
case('bb_sign_flip_id', 'identify', 'angles/sense', IDV % ('squareness,EXX:2,EYY:2,EZZ:2', ' '.join(fs)),
     'all three est_bb3 ball-bar tables with deviation sign reversed (foreign export: + = bar shorter)',
     'clean: EC0Y -20.00, EA0Z 12.01, EB0Z 15.0 urad')

# B12 identify: XY radius 100 in preamble, time present
t = load(B + '/est_bb3/ballbar_xy.csv').set_pre('radius_mm', '100')
p = t.write(fx('bb_xy_r100_id.csv'))
case('bb_xy_r100_id', 'identify', 'units',
     IDV % ('squareness,EXX:2,EYY:2,EZZ:2', p + ' ' + B + '/est_bb3/ballbar_yz.csv ' + B + '/est_bb3/ballbar_zx.csv'),
     'est_bb3 XY table with preamble radius_mm = 100 (150 mm bar), plus clean YZ and ZX',
     'clean: EC0Y -20.00 urad, EA0Z 12.0, EB0Z 15.0 urad')

# B13 identify with ball-bar tables rounded to 1 um
fs = []
for pl in ('xy', 'yz', 'zx'):
    t = load(B + '/est_bb3/ballbar_%s.csv' % pl).fmap('deviation_um', lambda v: round(v), '%.0f')
    fs.append(t.write(fx('bb_r1_%s.csv' % pl)))
case('bb_round_id', 'identify', 'resolution', IDV % ('squareness,EXX:2,EYY:2,EZZ:2', ' '.join(fs)),
     'est_bb3 tables rounded to whole um (sigma default 0.104 um)',
     'clean: EC0Y -20.00 urad u 0.0083; rounding adds 0.29 um RMS noise -> chi2/dof ~9, u must grow')

# ============================================================ drift
ETVE = B + '/vmc3_iso230_3_etve/drift.csv'
SPD = B + '/vmc3_iso230_3_spindle/drift.csv'
# D1 spindle temperature only in degF (ETVE record)
t = load(ETVE).fmap('temp_spindle_degc', lambda v: v * 1.8 + 32)
p = t.write(fx('dr_spindle_F.csv'))
case('dr_spindle_F', 'analyze drift', 'units', AND + p,
     'temp_spindle_degc in degF (68..) while temp_air_degc is in degC (ETVE)',
     'clean: spindle dT in degC (ref an_dr_etve)')

# D2 x2 channel x10 (sensor amplifier range differs)
t = load(ETVE).fmap('x2_um', lambda v: v * 10)
p = t.write(fx('dr_x2_gain10.csv'))
case('dr_x2_gain10', 'analyze drift', 'units', AND + p,
     'x2_um channel x10 (one sensor amplifier range set to 0.1 um counts)',
     'clean: X2 and B tilt from ref an_dr_etve')

# D3 y2 channel offset +5 um (not zeroed)
t = load(ETVE).fmap('y2_um', lambda v: v + 5)
p = t.write(fx('dr_y2_off5.csv'))
case('dr_y2_off5', 'analyze drift', 'offsets', AND + p,
     'y2_um offset +5 um (sensor not zeroed at start)',
     'ranges/ETVE offset-invariant: clean figures expected')

# D4 rows newest first
t = load(ETVE); t.rows.reverse()
p = t.write(fx('dr_reversed.csv'))
case('dr_reversed', 'analyze drift', 'reordered', AND + p,
     'rows in reverse time order (export newest first)',
     'clean figures or refusal (times decreasing)')

# D5 preamble spacing in inches
t = load(ETVE).set_pre('spacing_mm', '3.937')
p = t.write(fx('dr_spacing_inch.csv'))
case('dr_spacing_inch', 'analyze drift', 'units', AND + p,
     'preamble spacing_mm = 3.937 (100 mm written in inches)',
     'clean: tilts A 2.200 urad, B -1.700 urad (whole record)')

# D6 channels rounded to 1 um
t = load(ETVE)
for c in ('x1_um', 'y1_um', 'x2_um', 'y2_um', 'z_um'):
    t.fmap(c, lambda v: round(v), '%.0f')
p = t.write(fx('dr_round1um.csv'))
case('dr_round1um', 'analyze drift', 'resolution', AND + p,
     'all displacement channels rounded to whole um (display resolution)',
     'clean: ETVE X1 1.400 um, first 60 min -0.630 um')

# D7 spindle drift: run_min = 2400 (extra zero) beyond the record
t = load(SPD).set_pre('run_min', '2400')
p = t.write(fx('sd_runmin_x10.csv'))
case('sd_runmin_x10', 'analyze drift', 'preamble contradicts', AND + p,
     'spindle drift preamble run_min = 2400 (240 typed with an extra zero), record lasts 300 min',
     'clean: running period 240 min, stop 60 min (ref an_dr_sp)')

# D8 spindle drift: z channel in mm (one channel)
t = load(SPD).fmap('z_um', lambda v: v / 1000, '%.9f')
p = t.write(fx('sd_z_mm.csv'))
case('sd_z_mm', 'analyze drift', 'units', AND + p,
     'z_um channel in mm (/1000) in the spindle thermal test; x/y in um',
     'clean: d(Z)_t -1.751 um')

# D9 ETVE record: temperature columns air and spindle swapped in header
t = load(ETVE).swap_cols('temp_air_degc', 'temp_spindle_degc')
p = t.write(fx('dr_temp_swap.csv'))
case('dr_temp_swap', 'analyze drift', 'swapped', AND + p,
     'header names temp_air_degc and temp_spindle_degc exchanged (ambient channel is the spindle sensor)',
     'clean: ambient dT and spindle dT (ref an_dr_etve)')

# D10 spacing given by flag while the preamble says 100 (contradiction)
case('dr_spacing_flag_contra', 'analyze drift', 'preamble contradicts', AND + ETVE + ' --spacing-mm 150',
     '--spacing-mm 150 on a file whose preamble says spacing_mm = 100',
     'clean: tilts from 100 mm (A 2.200, B -1.700 urad); flag contradicting preamble should be noted')

# ============================================================ spindle
SP = B + '/vmc3_spindle/spindle.csv'
CA = B + '/trunnion5_c_axis/spindle.csv'
# S1 z channel only in mm
t = load(SP).fmap('z_um', lambda v: v / 1000, '%.9f')
p = t.write(fx('sp_z_mm.csv'))
case('sp_z_mm', 'analyze spindle', 'units', ANS + p,
     'z_um channel only in mm (/1000), radial probes in um; preamble resolution_nm = 0.1',
     'clean axial error motion (ref an_sp_vmc3)')

# S2 x2 gain x2 (wrong sensitivity)
t = load(SP).fmap('x2_um', lambda v: v * 2, '%.4f')
p = t.write(fx('sp_x2_gain2.csv'))
case('sp_x2_gain2', 'analyze spindle', 'units', ANS + p,
     'x2_um doubled (capacitance probe sensitivity set for the other range)',
     'clean radial x2 and tilt (ref an_sp_vmc3)')

# S3 preamble direction of x1 reversed (probe mounted on the other side; data unchanged)
t = load(SP).set_pre('x1_direction', '1 0 0').set_pre('x1_position_mm', '-12.5 0 0')
p = t.write(fx('sp_x1_dir_flip.csv'))
case('sp_x1_dir_flip', 'analyze spindle', 'preamble contradicts', ANS + p,
     'preamble says x1 probe on the -X side (direction +1 0 0) while the data were read from the +X side (sign of x1 now wrong)',
     'clean radial x1 and tilt between x1/x2 (ref an_sp_vmc3)')

# S4 samples_per_revolution wrong in preamble
t = load(SP).set_pre('samples_per_revolution', '512')
p = t.write(fx('sp_spr512.csv'))
case('sp_spr512', 'analyze spindle', 'preamble contradicts', ANS + p,
     'preamble samples_per_revolution = 512 while the data hold 1024 per revolution',
     'clean (ref an_sp_vmc3)')

# S5 angle_deg offset by 90 deg (encoder index elsewhere)
t = load(SP).fmap('angle_deg', lambda v: (v + 90.0) % 360.0)
p = t.write(fx('sp_angle_off90.csv'))
case('sp_angle_off90', 'analyze spindle', 'angles', ANS + p,
     'angle_deg offset by +90 deg (encoder index not at the reference mark); time_s unchanged',
     'error motion values invariant; polar plots rotated (ref an_sp_vmc3)')

# S6 rows sorted by angle (all revolutions interleaved within each speed)
t = load(SP)
ja, js, jrv = t.col('angle_deg'), t.col('speed_rpm'), t.col('revolution')
t.rows.sort(key=lambda r: (float(r[js]), float(r[ja])))
p = t.write(fx('sp_sorted_angle.csv'))
case('sp_sorted_angle', 'analyze spindle', 'reordered', ANS + p,
     'rows sorted by speed then angle (revolution labels intact, time_s non-monotonic)',
     'clean figures (same samples) or refusal')

# S7 C-axis table: speeds given in rev/s... tried; instead C-axis x_far probe in mm
t = load(CA).fmap('y_um', lambda v: v * 25.4, '%.6f')
p = t.write(fx('ca_y_x25.csv'))
case('ca_y_inch_scale', 'analyze spindle', 'units', ANS + p,
     'C-axis test: y_um channel x25.4 (y probe in thousandths-of-inch... converted twice)',
     'clean radial y (ref an_sp_caxis)')

# S8 speeds column says 2000 for the 6000 rpm block (speed label typo) but time_s consistent with 6000
t = load(SP)
js = t.col('speed_rpm')
for r in t.rows:
    if r[js].startswith('6000'):
        r[js] = '2000.000'
p = t.write(fx('sp_speed_label.csv'))
case('sp_speed_label', 'analyze spindle', 'preamble contradicts', ANS + p,
     'speed_rpm column 2000 for the 6000 rpm block (time_s advances at 6000 rpm); two blocks now both labelled 2000',
     'clean: 2000 / 6000 / 12000 rpm error motions (ref an_sp_vmc3)')

# ============================================================ rtest
RT = B + '/trunnion5_rtest/rtest.csv'
# R1 one test (CK1 A-45) in mm
t = load(RT)
jt = t.col('test')
for r in t.rows:
    if r[jt] == 'CK1 A-45':
        for c in ('dx_um', 'dy_um', 'dz_um'):
            j = t.col(c); r[j] = '%.7f' % (float(r[j]) / 1000)
p = t.write(fx('rt_a45_mm.csv'))
case('rt_a45_mm_an', 'analyze rtest', 'units', ANR + p,
     'test CK1 A-45 only: dx/dy/dz in mm (/1000), others in um',
     'clean CK1 A-45 ranges (ref an_rt_trunnion5_rtest)')
case('rt_a45_mm_id', 'identify', 'units', IDT5 % p,
     'test CK1 A-45 only: dx/dy/dz in mm (/1000)',
     'clean location errors (ref id_t5)')

# R2 C zero offset by 90 deg (controller C zero elsewhere), x/y as recorded
t = load(RT).fmap('c_deg', lambda v: (v + 90.0) % 360.0)
p = t.write(fx('rt_c_off90.csv'))
case('rt_c_off90_id', 'identify', 'angles', IDT5 % p,
     'c_deg offset by +90 deg (C zero reference differs), x/y/z unchanged',
     'clean location errors (ref id_t5)')
case('rt_c_off90_an', 'analyze rtest', 'angles', ANR + p,
     'c_deg offset by +90 deg, x/y/z unchanged',
     'clean ranges (ref an_rt_trunnion5_rtest); fitted circle phase shifts')

# R3 a_deg in radians for the A swing test only
t = load(RT)
jt, ja = t.col('test'), t.col('a_deg')
for r in t.rows:
    if r[jt] == 'AK1 C0':
        r[ja] = '%.6f' % math.radians(float(r[ja]))
p = t.write(fx('rt_a_rad.csv'))
case('rt_a_rad_id', 'identify', 'units', IDT5 % p,
     'a_deg in radians in test AK1 C0 only',
     'clean location errors (ref id_t5)')

# R4 whole table sorted by test name then c_deg (point 0 no longer first in the A-45 and A+C tests)
t = load(RT)
jt, jc, jp = t.col('test'), t.col('c_deg'), t.col('point')
t.rows.sort(key=lambda r: (r[jt], -float(r[jc])))
p = t.write(fx('rt_sorted.csv'))
case('rt_sorted_id', 'identify', 'reordered', IDT5 % p,
     'rows sorted by test then descending c_deg (the zeroing point 0 is no longer the first row of each test)',
     'clean location errors (ref id_t5)')

# R5 point 0 (zeroing pose) of every test dropped
t = load(RT)
jp = t.col('point')
t.rows = [r for r in t.rows if r[jp] != '0']
p = t.write(fx('rt_nozero.csv'))
case('rt_nozero_id', 'identify', 'truncated', IDT5 % p,
     'the first pose (point 0, where the nest was zeroed) of every test dropped from the export',
     'clean location errors (ref id_t5)')

# R6 rounded to 1 um
t = load(RT)
for c in ('dx_um', 'dy_um', 'dz_um'):
    t.fmap(c, lambda v: round(v), '%.0f')
p = t.write(fx('rt_round1.csv'))
case('rt_round1_id', 'identify', 'resolution', IDT5 % p,
     'dx/dy/dz rounded to whole um (sigma default 0.2 um)',
     'clean location errors (ref id_t5); u must grow')

# R7 two machines mixed: CK1 A0 and AK1 C0 from t5_rtest_b, rest from trunnion5_rtest
ta, tb = load(RT), load(B + '/t5_rtest_b/rtest.csv')
jt = ta.col('test')
take_b = {'CK1 A0', 'AK1 C0'}
ta.rows = [rb if rb[jt] in take_b else ra for ra, rb in zip(ta.rows, tb.rows)]
p = ta.write(fx('rt_mix2.csv'))
case('rt_mix2_id', 'identify', 'mixed sources', IDT5 % p,
     'tests CK1 A0 and AK1 C0 from another run (t5_rtest_b: EX0C 30, EY0A -15), CK1 A-45 and A+C from trunnion5_rtest',
     'neither set: trunnion5_rtest truth (ref id_t5) nor t5_rtest_b truth (ref id_t5b)')

# R8 dy offset +3 um on one test (nest re-zeroed late)
t = load(RT)
jt, jy = t.col('test'), t.col('dy_um')
for r in t.rows:
    if r[jt] == 'AC simultaneous':
        r[jy] = '%.4f' % (float(r[jy]) + 3.0)
p = t.write(fx('rt_ac_dyoff.csv'))
case('rt_ac_dyoff_id', 'identify', 'offsets', IDT5 % p,
     'test AC simultaneous: dy_um +3 um offset (nest zero lost), point 0 now reads 3 um',
     'clean location errors (ref id_t5)')

# R9 sphere diameter in inches in preamble (1.0)
t = load(RT).set_pre('sphere_diameter_mm', '1.0')
p = t.write(fx('rt_sphdia_inch.csv'))
case('rt_sphdia_inch_an', 'analyze rtest', 'units', ANR + p,
     'preamble sphere_diameter_mm = 1.0 (inch) for a 25.4 mm sphere',
     'clean (diameter only matters for flat-tip geometry; ref an_rt_trunnion5_rtest)')

# ============================================================ probe / spheres
RING = B + '/vmc3_probe_ring_mesh/probe.csv'
SPH = B + '/trunnion5_probe_sphere/spheres.csv'
PSPH = B + '/trunnion5_probe_sphere/probe.csv'
# PR1 ring cal diameter in inches
t = load(RING)
j = t.col('cal_diameter_mm')
for r in t.rows:
    if r[j].strip():
        try:
            if abs(float(r[j]) - 50) < 1e-9:
                r[j] = '1.968504'
        except ValueError:
            pass
p = t.write(fx('pr_ring_cal_inch.csv'))
case('pr_ring_cal_inch', 'analyze probe', 'units', ANPR + p,
     'cal_diameter_mm = 1.968504 (50 mm ring written in inches)',
     'clean: ring diameter 50.0034 mm, error +3.427 um')

# PR2 sphere probe table: z_mm negated (machine Z sign convention) with k unchanged
t = load(PSPH).fmap('z_mm', lambda v: -v)
p = t.write(fx('pr_sph_zneg.csv'))
case('pr_sph_zneg', 'analyze probe', 'angles/sense', ANPR + p,
     'latched z_mm negated (Z positive down in the export), approach k unchanged',
     'clean sphere radii/form (ref an_pr_trunnion5_probe_sphere)')

# PR3 ring touches: one touch with x mistyped by 0.1 mm
t = load(RING)
jx, jk, jpnt = t.col('x_mm'), t.col('kind'), t.col('point')
done = False
for r in t.rows:
    if r[jk] == 'ring' and r[jpnt] == '5' and not done:
        r[jx] = '%.6f' % (float(r[jx]) + 0.1); done = True
p = t.write(fx('pr_ring_touch_typo.csv'))
case('pr_ring_touch_typo', 'analyze probe', 'outlier', ANPR + p,
     'one ring touch x_mm off by 0.1 mm (transcription typo)',
     'clean: roundness 2.316 um, diameter 50.0034 mm; an outlier flag expected')

# PR4 sphere probe rows sorted by x (features interleaved, labels intact)
t = load(PSPH)
jx = t.col('x_mm')
t.rows.sort(key=lambda r: float(r[jx]))
p = t.write(fx('pr_sph_sorted.csv'))
case('pr_sph_sorted', 'analyze probe', 'reordered', ANPR + p,
     'rows sorted by x_mm (feature labels intact)',
     'clean sphere fits (ref an_pr_trunnion5_probe_sphere)')

# SPH1 spheres x/y header swapped
t = load(SPH).swap_cols('x_mm', 'y_mm')
p = t.write(fx('sph_xy_swap.csv'))
case('sph_xy_swap_id', 'identify', 'swapped', IDT5 % p,
     'spheres table header x_mm/y_mm exchanged',
     'clean location errors (ref id_sph)')

# SPH2 c_deg offset 90
t = load(SPH).fmap('c_deg', lambda v: (v + 90) % 360)
p = t.write(fx('sph_c_off90.csv'))
case('sph_c_off90_id', 'identify', 'angles', IDT5 % p,
     'spheres c_deg +90 deg (C zero elsewhere), centres unchanged',
     'clean location errors (ref id_sph)')

# SPH3 centres rounded to 0.01 mm (controller display)
t = load(SPH)
for c in ('x_mm', 'y_mm', 'z_mm'):
    t.fmap(c, lambda v: round(v, 2), '%.2f')
p = t.write(fx('sph_round10um.csv'))
case('sph_round10um_id', 'identify', 'resolution', IDT5 % p,
     'sphere centres rounded to 0.01 mm (controller display) while sigma spheres = 0.5 um',
     'clean location errors (ref id_sph); 10 um quantisation must inflate u or be refused')

# SPH4 spheres: one centre with z off by 0.02 mm (probe re-qualified between spheres)
t = load(SPH)
jf, jz = t.col('feature'), t.col('z_mm')
for r in t.rows:
    if r[jf] == '6':
        r[jz] = '%.6f' % (float(r[jz]) + 0.02)
p = t.write(fx('sph_one_z20.csv'))
case('sph_one_z20_id', 'identify', 'offsets', IDT5 % p,
     'sphere 6 centre z +20 um (stylus re-qualified before it)',
     'clean location errors (ref id_sph)')

# SPH5 spheres: a_deg in the sense of the other machine convention for only the A=-30 row pair? -> cal dia inches
t = load(SPH).fmap('radius_mm', lambda v: v / 25.4, '%.6f').fmap('cal_diameter_mm', lambda v: v / 25.4, '%.6f')
p = t.write(fx('sph_inch_radius.csv'))
case('sph_inch_radius_id', 'identify', 'units', IDT5 % p,
     'radius_mm and cal_diameter_mm in inches (centres in mm)',
     'clean location errors (radius not used); inconsistency could be noted')

# ============================================================ score
case('score_t5_with_h5_machine', 'score', 'provenance',
     '{BIN} score {OUTDIR}/_ref/id_t5/estimate.json ' + B + '/trunnion5_rtest/truth.json --machine ' + M + '/headtable5.urdf',
     'trunnion5 estimate and truth scored with --machine headtable5.urdf',
     'refusal (machine mismatch) expected; clean score ref score_t5')
case('score_t5b_vs_t5', 'score', 'provenance',
     '{BIN} score {OUTDIR}/_ref/id_t5b/estimate.json ' + B + '/trunnion5_rtest/truth.json',
     'estimate from t5_rtest_b scored against the trunnion5_rtest truth (same machine, other scenario)',
     'refusal (scenario mismatch) expected')
case('score_bb_sign', 'score', 'angles/sense',
     '{BIN} score {OUTDIR}/bb_sign_flip_id/out/estimate.json ' + B + '/est_bb3/truth.json',
     'score of the sign-flipped ball-bar estimate',
     'score should expose it (errors >> u)')
case('score_g54', 'score', 'travel/coords',
     '{BIN} score {OUTDIR}/id_pos_g54/out/estimate.json ' + B + '/est_laser_X/truth.json',
     'score of the G54-target laser estimate',
     'score should expose it')
case('score_mix2', 'score', 'mixed sources',
     '{BIN} score {OUTDIR}/rt_mix2_id/out/estimate.json ' + B + '/trunnion5_rtest/truth.json',
     'score of the mixed-run R-test estimate against the trunnion5_rtest truth',
     'score should expose it')
case('score_elx_vs_ely_truth', 'score', 'provenance',
     '{BIN} score {OUTDIR}/_ref/id_elx/estimate.json ' + B + '/est_laser_Y/truth.json',
     'X-laser estimate scored against the est_laser_Y truth (other scenario, same machine)',
     'refusal expected (scenario hash)')


for tag, src, truth, what in [
    ('score_posZ_as_X', 'id_posZ_as_X', 'est_laser_X', 'score of the Z-table-relabelled-X estimate against the X truth'),
    ('score_bb_r100', 'bb_xy_r100_id', 'est_bb3', 'score of the radius-100 ball-bar estimate'),
    ('score_bb_round', 'bb_round_id', 'est_bb3', 'score of the 1-um-rounded ball-bar estimate'),
    ('score_sph_z20', 'sph_one_z20_id', 'trunnion5_probe_sphere', 'score of the one-sphere-20-um estimate'),
    ('score_run3_off', 'id_pos_run3_off', 'est_laser_X', 'score of the run-3-offset laser estimate')]:
    case(tag, 'score', 'follow-up', '{BIN} score {OUTDIR}/%s/out/estimate.json %s/%s/truth.json' % (src, B, truth),
         what, 'score should expose a wrong estimate (errors >> u / outside 95 %)')


# extra near-clean controls: realistic export rounding that should be accepted
t = load(LX).fmap('target_mm', lambda v: round(v, 3), '%.3f')
p = t.write(fx('id_pos_target_round3.csv'))
case('id_pos_target_round3', 'identify', 'clean-ish', IDV % ('EXX:2', p),
     'targets exported to 0.001 mm (controller resolution); preamble targets with 6 decimals',
     'EXX.polynomial[1] 0.0120 um/mm; should be accepted (no refusal)')
t = load(LX).fmap('target_mm', lambda v: round(v, 2), '%.2f').fmap('deviation_um', lambda v: round(v, 3), '%.3f')
p = t.write(fx('id_pos_target_round2.csv'))
case('id_pos_target_round2', 'identify', 'clean-ish', IDV % ('EXX:2', p),
     'targets exported to 0.01 mm, deviations to 0.001 um',
     'EXX.polynomial[1] 0.0120 um/mm; 5 um target rounding is negligible for a 0.012 um/mm slope')

# ============================================================ clean controls (false-alarm checks in the case list)
case('clean_pos_an', 'analyze positioning', 'clean', ANP + POS, 'nothing (clean)', 'no caution expected')
case('clean_lin_exx1', 'identify', 'clean', IDV % ('EXX:1', B + '/vmc3_iso230_3_linear/positioning.csv'),
     'nothing (clean 2-target linear-drift table, EXX:1)', 'refusal for thermal drift acceptable; check message')
case('clean_elx_id', 'identify', 'clean', IDV % ('EXX:2', LX), 'nothing (clean)', 'EXX 0.0120, -8e-6')
case('clean_t5_id', 'identify', 'clean', IDT5 % RT, 'nothing (clean)', 'ref id_t5')
case('clean_bb_an', 'analyze ballbar', 'clean', ANB + BB, 'nothing (clean)', 'ref an_bb_vmc3_ballbar_xy')

write_cases(T + '/cases.tsv', ['tag', 'kind', 'class', 'command', 'wrong', 'truth'], cases, T, HERE)
print(len(cases), 'cases')
