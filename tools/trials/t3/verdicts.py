#!/usr/bin/env python3
"""Trial 3 verdicts: python3 verdicts.py RESDIR  (after run_all.sh BIN WORK; RESDIR = WORK/t3/res).
Writes RESDIR/verdicts.tsv and prints counts.

Trial 3 judged its 90 cases by hand (recorded_verdicts.py, the findings of report.md).  This script re-derives a
verdict from a new run with the rules of trials 4-6, and prints the recorded one beside it:
  legit input (LEGIT)  : refusal or a caution -> FALSE-ALARM (JUSTIFIED refusals -> FINE), else FINE
  other input          : rc 101/124/134/137/139 or 'panicked' -> PANIC-HANG; rc != 0 -> REFUSED;
                         a caution that names the problem -> FLAGGED;
                         recorded CONFIDENT-WRONG and still exit 0 without such a caution -> CONFIDENT-WRONG;
                         else FINE.
Limit: the figures are not re-compared here; a recorded CONFIDENT-WRONG case that a binary now gets right
silently still reads CONFIDENT-WRONG (look at RESDIR/<tag>/stdout against the 'seen' column)."""
import csv, os, re, sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True
sys.path.insert(0, HERE)
from recorded_verdicts import RECORDED  # noqa: E402

OUT = sys.argv[1] if len(sys.argv) > 1 else '/tmp/mtwin-trials/t3/res'
PANIC = {101, 124, 134, 137, 139}
GENERIC = re.compile(r'does not name the scenario its tables came from|holds files this run does not write')

# correct (or legitimately different) inputs: any refusal or caution is a false alarm
LEGIT = {'clean_pos_an', 'clean_elx_id', 'clean_t5_id', 'clean_bb_an', 'clean_lin_exx1',
         'pos_sorted_target', 'bb_sorted_angle', 'pr_sph_sorted', 'rt_sorted_id', 'rt_nozero_id',
         'id_pos_target_round3', 'id_pos_target_round2'}
# legit inputs whose refusal trial 3 accepted (the model lacks thermal drift: a 240 min drift test cannot fit)
JUSTIFIED = {'clean_lin_exx1'}
# cautions that trial 3 found do not name the case's problem (tag -> regex of such caution lines)
NOT_NAMING = {
    'pos_run3_mm': r'drift',            # blames thermal drift for a run read in mm
    'pos_temp_F': r'warm|thermal|drift',  # the legitimate warm-up caution of the clean record
}


def read(p):
    try:
        return open(p, errors='replace').read()
    except OSError:
        return ''


def verdict(tag):
    d = os.path.join(OUT, tag)
    rc = int(read(d + '/rc').strip() or -1)
    out, err = read(d + '/stdout'), read(d + '/stderr')
    caut = [l.strip() for l in (out + '\n' + err).splitlines()
            if re.search(r'CAUTION|WARNING|^warning', l) and not GENERIC.search(l)]
    if tag in NOT_NAMING:
        caut = [l for l in caut if not re.search(NOT_NAMING[tag], l, re.I)]
    recorded = RECORDED[tag][0]
    if rc in PANIC or 'panicked' in err:
        v = 'PANIC-HANG'
    elif tag in LEGIT:
        if rc != 0:
            v = 'FINE' if tag in JUSTIFIED else 'FALSE-ALARM'
        else:
            v = 'FALSE-ALARM' if caut else 'FINE'
    elif rc != 0:
        v = 'REFUSED'
    elif caut:
        v = 'FLAGGED'
    elif recorded == 'CONFIDENT-WRONG':
        v = 'CONFIDENT-WRONG'
    else:
        v = 'FINE'
    first = (err.strip().splitlines() or [''])[0] if rc != 0 else (caut[0] if caut else '')
    return rc, v, recorded, first[:300]


def main():
    rows = list(csv.reader(open(HERE + '/cases.tsv'), delimiter='\t'))[1:]
    res, counts, changed = [], {}, 0
    for tag, kind, klass, cmd, wrong, truth in rows:
        rc, v, rec, first = verdict(tag)
        counts[v] = counts.get(v, 0) + 1
        changed += v != rec
        res.append((tag, kind, klass, str(rc), v, rec, wrong, truth, first))
    with open(os.path.join(OUT, 'verdicts.tsv'), 'w') as f:
        f.write('tag\tkind\tclass\texit\tverdict\trecorded\twrong\ttruth\tmessage\n')
        for r in res:
            f.write('\t'.join(x.replace('\t', ' ').replace('\n', ' ') for x in r) + '\n')
    for k in sorted(counts):
        print('%-16s %d' % (k, counts[k]))
    print('total', len(res), '(%d differ from the verdict recorded by trial 3)' % changed)
    for r in res:
        if r[4] in ('CONFIDENT-WRONG', 'FALSE-ALARM', 'PANIC-HANG'):
            print('%-16s %-28s recorded %s' % (r[4], r[0], r[5]))
    for r in res:
        if r[4] != r[5]:
            print('changed          %-28s %s -> %s' % (r[0], r[5], r[4]))


if __name__ == '__main__':
    main()
