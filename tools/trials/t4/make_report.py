#!/usr/bin/env python3
"""Builds report.md from OUTDIR/verdicts.tsv plus the hand notes below (printed vs true, detectability)."""
import csv, os, sys
HERE = os.path.dirname(os.path.abspath(__file__))
OUT = sys.argv[1] if len(sys.argv) > 1 else '/tmp/mtwin-trials/t4/res'
BINARY = (open(os.path.join(OUT, '..', '..', 'binary.txt')).read().strip() if os.path.exists(os.path.join(OUT, '..', '..', 'binary.txt')) else '?')
rows = list(csv.DictReader(open(OUT + '/verdicts.tsv'), delimiter='\t'))
cmds = {r['tag']: r['command'] for r in csv.DictReader(open(HERE + '/cases.tsv'), delimiter='\t')}

# tag: (printed vs true, detectable / comment)
N = {
 'pos_dev_is_reading': ('E 740.011 / A 740.011 "um", R 0.003 vs E 11.355, R 3.108', 'caution: readings repeat to 0 um, "mm in the um column?" (names a unit slip; the column is the position reading in mm)'),
 'pos_unidir_legit': ('E_up 8.372, R_up 0.102 = clean up-figures; note explains bidirectional figures absent', 'correct'),
 'pos_clock_time': ('identical to clean', 'correct'),
 'pos_runs_per_pass': ('E 11.355, R 3.108, B 3.024 (same); header says "10 runs"', 'immaterial'),
 'pos_glitch': ('R 268.300, A 268.300, E 38.294, B 32.993 um vs R 3.108, A 11.443, E 11.355, B 3.024', 'YES: one reading 150 um from its 4 siblings whose spread is 0.02 um (s_down at 383.37 = 67 um vs median s 0.02 um); a robust per-target outlier test (e.g. |x - median| > 20 x MAD of all targets, or Grubbs) should raise a CAUTION naming run/direction/target; ISO 230-2 keeps the reading, so caution not refusal'),
 'pos_warm_time_per_run': ('A 38.4, R 33.8 um with cautions: time restarts, not thermally stable', 'caution names the time restart'),
 'pos_bom_crlf': ('identical to clean', 'correct'),
 'pos_trailing_comma': ('refused: unknown column `` (empty header from a trailing comma)', 'an empty trailing header with empty cells is harmless; should be ignored (or a note), not a refusal'),
 'pos_dev_tenths': ('E 4.470, A 4.505, R 1.223, B 1.191 um vs 11.355, 11.443, 3.108, 3.024', 'weakly: all figures /2.54; nothing in a lone positioning table fixes the scale. Only the readings grid (laser 1 nm steps become 0.3937 nm steps) hints at it; the identify counterpart id_pos_tenths is detectable by chi2 (see there)'),
 'bb_abs_radius': ('G 0.008 um with caution "trace spans 0.0642 um, less than the 0.1 um a ball-bar resolves: mm in the um column?"', 'flagged; better: mean radial deviation = 150.000 = radius_mm/1000 identifies the measured-length column'),
 'bb_diametral': ('G ccw 16.465, G cw 23.794, squareness 40.03 um/m, backlash_x 8.0 vs 8.232, 11.897, 20.02, 4.0', 'weakly: everything x2. If the preamble/flags gave the instrument resolution (0.1 um), the readings all being even multiples of 0.1 um (0.2 um grid) reveal it; else not'),
 'bb_dev_tenths': ('G ccw 3.241, G cw 4.684, squareness 7.88 um/m, backlash_x 1.575 vs 8.232, 11.897, 20.02, 4.0', 'YES: every deviation is a whole multiple of 0.03937 um (= 0.1 um / 2.54): a grid check (the exporter\'s quantum) shows an inch conversion of a 0.1 um instrument; the same readings fitted in identify give chi2/dof 0.15'),
 'bb_plane_flag_wrong': ('XY data reported as YZ: backlash_y 4.000, backlash_z 2.000, squareness YZ 20.0 um/m (true: X backlash 4, Y backlash 2, XY squareness 20)', 'weakly: no caution although the preamble still says centre_mm 380 205 300 and the file is named ballbar_xy.csv; with time_s present and no plane in the preamble, the tool could at least note that the plane came from a flag only'),
 'clean_bb_yz': ('identical to analyze of the clean table', 'correct'),
 'id_bb_ccw_only_legit': ('refused ("the fit fails its own checks": only ccw sense measured, squareness may include servo mismatch); with --accept-implausible: EC0Y -19.999 +- 0.012 (truth -20), chi2/dof 0.99', 'correct input, correct fit: the one-sense limitation deserves a CAUTION in the report, not a refusal labelled as a failed fit (its "likely cause" text about copies/units is wrong here)'),
 'dr_time_offset_legit': ('same figures, windows shifted by 480 min', 'correct'),
 'dr_every2min_legit': ('ETVE X1 1.38 vs 1.40; A whole record -1.5 vs 2.2 urad (noise-level extreme of a 0.1-urad-noise tilt)', 'correct within sampling'),
 'dr_etve_600': ('no ETVE, caution: record 480 min shorter than the 600 min test', 'caution names it'),
 'dr_ambient_flag_wrong': ('dT column 0.300/0.290/... from temp_spindle_degc vs 0.630/0.660/... from air', 'partly: the chosen "ambient" column is named spindle (a name heuristic: ambient/air/room), and in this ETVE record it varies differently from the air sensor; a caution when --ambient-sensor names a column whose name is a machine part'),
 'sd_run_stop_swap': ('"t = 60 min" column: X1 -0.005, Z -1.554 um; stop 240 min vs t = 240 min: Z -1.751 um, stop 60', 'YES: temp_bearing_degc keeps rising until 240 min and falls after; the preamble says the spindle stopped at 60 min. Check the bearing/spindle temperature turning point (or the heat-up slope) against run_min'),
 'dr_z_sign': ('Z first 60 min -0.290, whole record -3.140 um vs +0.290, +3.140', 'no (a sense convention; only a documented sensor direction in the preamble could say)'),
 'dr_x1_frozen': ('X1 whole record -3.560 vs -6.340 um; B whole record -28.5 urad, ETVE B 11.8 urad vs -1.7, 1.7', 'YES: x1_um is bit-identical for the last 280 samples while every other channel (incl. its partner x2) keeps drifting and shows noise: a flat-line (stuck/saturated sensor) check, exactly zero variance over > N samples'),
 'dr_z_nm': ('Z 3140 um with cautions (rounded to 10 um; drift > 1000 um: nm in the um column?)', 'caution names it'),
 'sp_sep_cm': ('tilt x1-x2 LSC 16.570 urad (x10) vs 1.657; PC 49.69 vs 4.97', 'YES: preamble artefact = "cylinder 25 mm x 80 mm" while station_separation_mm = 8: the probes 8 mm apart on an 80 mm artefact; also the tilt fundamental (eccentricity difference) becomes 40 urad, implausible for 1-UPR of a 25 mm test bar'),
 'sp_rev_from1_legit': ('identical', 'correct'),
 'rt_names_swapped_an': ('block titled "CK1 A-45" shows the A=0 test (range X 33.033, radius 16.543) and vice versa', 'YES: the test name says A-45 while its a_deg column is 0 at every pose; the report does not print the fixed tilt, so the label is all the user sees'),
 'rt_sph_radius_an': ('only the set-up line shows "O 12.7 mm"; figures identical', 'immaterial for the figures'),
 'clean_h5_id': ('estimates identical to trial-3 reference; chi2/dof 1.71 note as before', 'correct'),
 'rt_point_from1_legit': ('estimates identical; provenance note (table edited)', 'correct'),
 'pr_plate_cal_typo': ('error max |100.5| um, RMS 24.0 um per placement vs 6.22, 1.94', 'YES: every centre-distance error involving ball 7 carries the same plate-frame offset (0.1 mm along plate x) in all three placements while the other balls agree to a few um; fit a per-ball calibration residual across placements: one ball off by the same vector in every placement is a calibration-table error, not the machine'),
 'pr_sph_cal254': ('radius error ~ -200 um with cautions per feature', 'caution names it'),
 'pr_ring_othercert': ('diameter error -8.573 vs +3.427 um', 'no (a 12 um certificate mix-up is inside what a ring gauge and a probe can show)'),
 'sph_rad_form_swap_id': ('estimates identical to clean (radius/form not used)', 'immaterial'),
 'sph_stylus_pre_id': ('estimates identical', 'immaterial'),
 'sph_drop3_legit': ('EB0C 37.9 +- 5.8 vs clean 31.3 +- 4.5 (truth within intervals)', 'correct'),
 'clean_sphh5_id': ('identical to trial-3 reference', 'correct'),
 'clean_el3_id': ('chi2/dof 1.15 as reference', 'correct'),
 'score_machine_copy': ('identical to reference score', 'correct'),
 'score_machine_edited': ('uncompensated RMS 35.367 vs 35.534 um, compensated 0.558 vs 0.557; no caution that --machine differs from the estimate\'s machine_file', 'immaterial here (0.5 %), but a hash check of --machine against the estimate\'s machine would be cheap'),
 'id_pos_glitch2': ('EXX[1] 0.0122 vs 0.0120 (in 95 %); chi2/dof 92.1 note, uncertainties scaled x9.6', 'flagged by the chi2 note (not naming the reading)'),
 'id_pos_tenths': ('EXX.polynomial[1] 0.0047 um/mm vs 0.0120 (score: error/u -398); chi2/dof 0.18 with 108 dof, no caution', 'YES: chi2/dof = 0.18 over 108 dof is impossible (p < 1e-15) if the laser sigma 0.02 um is right: residuals 2.4x smaller than the instrument noise means the deviations were scaled down (tenths, inch); add a lower chi2 bound (e.g. chi2/dof < 0.3 with dof > 50) as a CAUTION'),
 'id_bb_tenths': ('EC0Y -7.873 vs -20.00 urad, EA0Z 4.73 vs 12.0, EB0Z 5.92 vs 15.0 (score 0/3 covering); chi2/dof 0.15 with 113080 dof, no caution', 'YES: chi2/dof 0.15 over 113 080 dof (noise 2.5x below the ball-bar\'s 0.104 um) and a 0.03937 um readings grid: an inch conversion'),
 'sp_x2_stuck': ('6000 rpm: radial x2 0.0000 at every centre, tilt x1-x2 LSC 9.480 urad vs 0.782 um and 1.627 urad', 'YES: x2_um is exactly constant over 20 revolutions (zero synchronous and asynchronous motion) while the other four probes show 0.1-0.2 um async: a saturated/disconnected probe'),
 'rt_chip_an': ('CK1 A0 range X 43.812 vs 33.033 um, circle residual 2.744 vs 0.182 um, no caution', 'YES: one pose sits 30 um off the fitted circle while the others sit within 0.2 um (residual 15x the others\', or > 10 x robust sigma): caution naming test and point'),
 'rt_chip_id': ('estimates within 95 % of truth (score 8/8), chi2/dof 59.9 note, uncertainties x7.7; compensated RMS 0.849 vs 0.557 um', 'flagged by chi2 note (not naming the pose)'),
 'score_id_pos_glitch2': ('score reports correctly', 'correct'),
 'score_id_pos_tenths': ('score shows error/u -398, 1 of 3 covered', 'score correct (reveals the failure)'),
 'score_id_bb_tenths': ('score shows 0 of 3 covered', 'score correct (reveals the failure)'),
 'score_rt_chip': ('8 of 8 covered', 'correct'),
 'compare_other_test': ('RMS 4.29 um over 20 paired readings; note "90 measured and 70 simulated readings have no partner"', 'weakly flagged by the note; preambles differ (beam offset 0 0 0 vs 0 0 60, compensation none vs air, 11 vs 9 targets): a refusal or CAUTION when fewer than half the readings pair or the set-ups differ'),
 'scen_clean_iso230_2': ('identical to clean', 'correct'),
 'scen_exx_per_mm': ('check "ok", run A = 4387.862 um; analyze then cautions (span > 1000 um: nm in the um column?)', 'check/run accept a 1.2 % scale error silently; the analyze caution catches the output'),
 'scen_laser_noise_um': ('check "ok", R_up 0.000, B exactly 3.000; analyze cautions (noise-free simulation / runs identical)', 'check could refuse noise_nm below resolution_nm'),
}


THEMES = """
## What the developers could implement (from the CONFIDENT-WRONG cases)

1. **Single-reading outliers** (pos_glitch, rt_chip_an; also rt_chip_id/id_pos_glitch2 only get a generic chi2 note): a robust
   per-group outlier test — a reading far (> ~20 robust sigma) from its siblings at the same target/direction (ISO 230-2) or off the
   fitted circle/line (R-test) — should produce a CAUTION naming run, direction and target (or test and point). The figures can stay
   ISO-conformant; the user must be told one reading makes R/A or the range.
2. **Stuck / flat-lined channels** (dr_x1_frozen, sp_x2_stuck): a channel bit-identical over many consecutive samples while the other
   channels show noise is a saturated or disconnected sensor. Zero asynchronous motion on one probe, or zero variance of one drift
   channel over > ~10 samples, is a cheap check.
3. **Residuals below the instrument noise** (id_pos_tenths chi2/dof 0.18 over 108 dof; id_bb_tenths 0.15 over 113 080 dof): identify
   already refuses chi2/dof > 100 but says nothing about chi2/dof far below 1, which over many degrees of freedom means the readings were
   scaled down (inch/tenths, diametral halves, wrong sigma). A lower bound (e.g. chi2/dof < 0.3 with dof > 50) deserves a CAUTION naming
   the table. The readings grid (multiples of 0.03937 um = 0.1 um / 2.54) is a second, analyze-side signal (bb_dev_tenths).
4. **Preamble facts not cross-checked against the data**: run_min/stop_min against the bearing-temperature turning point
   (sd_run_stop_swap); station_separation_mm against the artefact length in the same preamble (sp_sep_cm); an R-test test name
   "A-45" against an a_deg column that is 0 (rt_names_swapped_an).
5. **Calibration-table errors in ball plates** (pr_plate_cal_typo): one ball whose errors carry the same plate-frame offset in every
   placement is a certificate typo; report per-ball residuals across placements.
6. **Flags that override a missing preamble** (bb_plane_flag_wrong, dr_ambient_flag_wrong): accepted silently. At least echo as a
   note that the plane / ambient sensor came from a flag only, and caution when --ambient-sensor names a column called spindle,
   bearing, motor or nut.
7. Not detectable from the data (listed for completeness; the number is wrong and nothing can tell): pos_dev_tenths (weak grid hint),
   bb_diametral, dr_z_sign, pr_ring_othercert.

## False alarms

- pos_trailing_comma: a trailing comma on every line (an empty last column, common in spreadsheet exports) is refused with
  `unknown column ```. An empty header whose cells are all empty could be ignored.
- id_bb_ccw_only_legit: ball-bar tables with only the ccw sense are refused as "the fit fails its own checks" although the fit is
  good (chi2/dof 0.99, EC0Y -19.999 +- 0.012 against the true -20). The one-sense limitation (servo mismatch has the shape of a
  squareness) is real and deserves a CAUTION, but it is not a failed fit, and the "likely cause" text (copies, units) misleads.

## Notes on the rest

- In this run the refused cases (see counts) were refused with messages that name the file, line, column and the contradiction (e.g. direction words, decimal
  commas, two axes in one file, preamble targets, cw angles counted the other way, feed flag against time_s, first_direction,
  angle sense, truncated revolution, speed in deg/s, A sense reversed / G54 coordinates in the R-test, tip = ball, frame = workpiece,
  sphere flag against preamble, tables given twice, EYY on an X table, wrong prefix, score arguments swapped, and every scenario
  slip except the EXX-per-mm and noise-below-resolution ones, which `check` accepts but whose analysis cautions).
- score follow-ups (score_id_*): `score` reports the failure of the wrong estimates correctly (they are FINE as scores).
- score_machine_edited: `score --machine` with an edited copy of the URDF (C origin moved 50 mm) is accepted without a note; the
  effect here is 0.5 % and therefore counted FINE, but the estimate records its machine file and a hash comparison would be cheap.
"""

cnt = {}
for r in rows:
    cnt[r['verdict']] = cnt.get(r['verdict'], 0) + 1
L = []
L.append('# Trial 4 — plausible-but-wrong inputs for `mtwin` (binary %s)\n' % BINARY)
L.append('Reproduce: `bash tools/trials/run.sh BIN WORK` (this file: WORK/t4/res/report.md). The per-case notes and themes were written by hand for the trial-4 binary (/tmp/t4bin/mtwin-start); see tools/trials/t4/report.md. '
         'Fixtures come from the clean bundled-scenario tables in WORK/base; clean references are recomputed by ref.sh into OUTDIR/_ref. '
         'Verdicts are automated by verdicts.py (rc, CAUTION lines, and per-tag patterns of the wrong printed number), then checked by hand.\n')
L.append('## Counts\n')
L.append('| verdict | n |\n|---|---|')
for k in ('CONFIDENT-WRONG', 'FLAGGED', 'REFUSED', 'FINE', 'FALSE-ALARM', 'PANIC-HANG'):
    L.append('| %s | %d |' % (k, cnt.get(k, 0)))
L.append('| total | %d |\n' % len(rows))
L.append('Legitimately-different or clean inputs (false-alarm checks): %d.\n' % sum(1 for r in rows if r['class'].startswith('clean') or r['tag'] == 'pos_runs_per_pass'))
L.append('## All cases\n')
L.append('| tag | kind | class | exit | verdict | what is wrong | printed vs true / message | detectable? |\n|---|---|---|---|---|---|---|---|')
esc = lambda s: s.replace('|', '\\|').replace('\n', ' ')
for r in rows:
    pv, det = N.get(r['tag'], (r['message'] or '-', 'message names it' if r['verdict'] == 'REFUSED' else '-'))
    L.append('| %s | %s | %s | %s | **%s** | %s | %s | %s |' % tuple(esc(x) for x in (r['tag'], r['kind'], r['class'], r['exit'], r['verdict'], r['wrong'], pv, det)))
L.append('\n## Details: CONFIDENT-WRONG and FALSE-ALARM\n')
for want in ('CONFIDENT-WRONG', 'FALSE-ALARM'):
    for r in rows:
        if r['verdict'] != want:
            continue
        pv, det = N.get(r['tag'], ('', ''))
        c = open(os.path.join(OUT, r['tag'], 'cmd')).read().strip()
        L.append('### %s — %s (%s)\n' % (r['tag'], want, r['kind']))
        L.append('- wrong input: %s' % r['wrong'])
        L.append('- command: `%s`' % c)
        L.append('- printed vs true: %s' % pv)
        L.append('- can the data reveal it: %s\n' % det)
L.append(THEMES)
open(OUT + '/report.md', 'w').write('\n'.join(L) + '\n')
print(OUT + '/report.md written')
