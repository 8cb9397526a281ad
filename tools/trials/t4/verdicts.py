#!/usr/bin/env python3
"""Trial 4 verdicts: python3 verdicts.py OUTDIR  (after run_all.sh BIN WORK; OUTDIR = WORK/t4/res).
Writes OUTDIR/verdicts.tsv and prints counts.  Rules:
  legit input (LEGIT): refusal or caution -> FALSE-ALARM, else FINE (JUSTIFIED: refusal accepted as FINE)
  other input: rc 101/124/134/137/139 -> PANIC-HANG; rc != 0 -> REFUSED; a caution (not the generic provenance one) or the
  tag's own flag pattern -> FLAGGED; else CONFIDENT-WRONG if the tag's wrong-number pattern WRONG[tag] matches, else FINE."""
import os, re, sys, csv

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = sys.argv[1] if len(sys.argv) > 1 else '/tmp/mtwin-trials/t4/res'

LEGIT = {'pos_unidir_legit', 'pos_clock_time', 'pos_bom_crlf', 'pos_trailing_comma', 'clean_bb_yz',
         'id_bb_ccw_only_legit', 'dr_time_offset_legit', 'dr_every2min_legit', 'sp_rev_from1_legit', 'clean_h5_id',
         'rt_point_from1_legit', 'sph_drop3_legit', 'clean_sphh5_id', 'clean_el3_id', 'score_machine_copy',
         'scen_clean_iso230_2', 'pos_runs_per_pass'}
JUSTIFIED = set()   # legit inputs whose refusal we accept (none: see report for id_bb_ccw_only_legit)

# printed-number patterns that show the confident wrong value (from the trial-4 binary)
WRONG = {
    'pos_glitch': r'repeatability R \(µm\)\s+268\.3',
    'pos_dev_tenths': r'systematic positional deviation E \(µm\)\s+4\.47',
    'bb_diametral': r'G ccw\s+16\.46',
    'bb_dev_tenths': r'G ccw\s+3\.24',
    'bb_plane_flag_wrong': r'backlash_y\s+4\.000',
    'dr_ambient_flag_wrong': r'X1 +-0\.630 µm +-6\.340 µm +1\.400 µm +123–183 +0\.300',
    'sd_run_stop_swap': r't = 60 min',
    'dr_z_sign': r'Z +-0\.290 µm',
    'dr_x1_frozen': r'B +-1\.300 µrad +-28\.500',
    'sp_sep_cm': r'tilt x1-x2\s+LSC\s+16\.57',
    'rt_names_swapped_an': r'CK1 A-45 \(37 poses[^\n]*\n\s+deviation range  X 33\.033',
    'pr_plate_cal_typo': r'error max \|100\.5',
    'pr_ring_othercert': r'error -8\.573',
    'id_pos_tenths': r'EXX\.polynomial\[1\]\s+0\.0047',
    'id_bb_tenths': r'EC0Y\s+-7\.87',
    'rt_chip_an': r'X 43\.812',
    'sp_x2_stuck': r'tilt x1-x2\s+LSC\s+9\.48',
}
# notes that name the problem though not worded as CAUTION
FLAG_EXTRA = {
    'compare_other_test': r'have no partner',
    'rt_chip_id': r'residuals exceed the stated uncertainties',
    'id_pos_glitch2': r'residuals exceed the stated uncertainties',
}
GENERIC = re.compile(r'does not name the scenario its tables came from')
PANIC = {101, 124, 134, 137, 139}


def read(p):
    try:
        return open(p, errors='replace').read()
    except OSError:
        return ''


def verdict(tag):
    d = os.path.join(OUT, tag)
    rc = int(read(d + '/rc').strip() or -1)
    out, err = read(d + '/stdout'), read(d + '/stderr')
    both = out + '\n' + err
    caut = [l for l in both.splitlines() if re.search(r'CAUTION|WARNING|^warning', l) and not GENERIC.search(l)]
    extra = FLAG_EXTRA.get(tag)
    flagged = bool(caut) or bool(extra and re.search(extra, both))
    if rc in PANIC or 'panicked' in err:
        v = 'PANIC-HANG'
    elif tag in LEGIT:
        if rc != 0:
            v = 'FINE' if tag in JUSTIFIED else 'FALSE-ALARM'
        else:
            v = 'FALSE-ALARM' if caut else 'FINE'
    elif rc != 0:
        v = 'REFUSED'
    elif flagged:
        v = 'FLAGGED'
    elif tag in WRONG and re.search(WRONG[tag], out):
        v = 'CONFIDENT-WRONG'
    else:
        v = 'FINE'
    first = (err.strip().splitlines() or [''])[0] if rc != 0 else (caut[0] if caut else '')
    return rc, v, first[:300]


def main():
    rows = list(csv.reader(open(HERE + '/cases.tsv'), delimiter='\t'))[1:]
    res, counts = [], {}
    for tag, kind, klass, cmd, wrong, truth in rows:
        rc, v, first = verdict(tag)
        counts[v] = counts.get(v, 0) + 1
        res.append((tag, kind, klass, str(rc), v, wrong, truth, first))
    with open(os.path.join(OUT, 'verdicts.tsv'), 'w') as f:
        f.write('tag\tkind\tclass\texit\tverdict\twrong\ttruth\tmessage\n')
        for r in res:
            f.write('\t'.join(x.replace('\t', ' ') for x in r) + '\n')
    for k in sorted(counts):
        print('%-16s %d' % (k, counts[k]))
    print('total', len(res))
    for r in res:
        if r[4] in ('CONFIDENT-WRONG', 'FALSE-ALARM', 'PANIC-HANG'):
            print('%-16s %s' % (r[4], r[0]))


if __name__ == '__main__':
    main()
