#!/usr/bin/env python3
import csv, os, sys
HERE = os.path.dirname(os.path.abspath(__file__))
OUT = sys.argv[1] if len(sys.argv) > 1 else '/tmp/mtwin-trials/t6/res'
BINARY = (open(os.path.join(OUT, '..', '..', 'binary.txt')).read().strip() if os.path.exists(os.path.join(OUT, '..', '..', 'binary.txt')) else '?')
rows = list(csv.reader(open(OUT + '/verdicts.tsv'), delimiter='\t'))[1:]
DET = dict(l.rstrip('\n').split('\t', 1) for l in open(HERE + '/details.tsv') if '\t' in l)
counts = {}
for r in rows:
    counts[r[5]] = counts.get(r[5], 0) + 1
o = []
o.append('# mtwin trial 6 — plausible-but-wrong inputs and false alarms\n')
o.append('Binary `' + BINARY + '`. %d cases, fixtures made by `gen.py` from the clean tables of WORK/base (`bash tools/trials/run.sh BIN WORK`; the summary and details were written for the trial-6 binary /tmp/t6bin/mtwin-s48); '
         'run with `./run_all.sh BIN OUTDIR` then `python3 verdicts.py OUTDIR` (numbers compared with the clean references ref.sh makes in OUTDIR/_ref; '
         'MANUAL entries in verdicts.py record the verdicts that needed judgement). `python3 make_report.py OUTDIR` rebuilds this file. `run_all.sh BIN OUTDIR [TAG-REGEX]` runs only the matching cases (references always). gen.py (with gen2.py) also simulates two R-test scenario copies into scen/ with $GENBIN (run.sh: the binary under test unless GENBIN is set), so the fixtures do not depend on the binary under test.\n' % len(rows))
o.append('## Counts\n')
o.append('| verdict | cases |\n|---|---|')
for k in sorted(counts):
    o.append('| %s | %d |' % (k, counts[k]))
o.append('| total | %d |\n' % len(rows))
o.append('Inputs: %d legit/tolerant (false-alarm probes), %d wrong. REFUSED-UPSTREAM = `score` follow-up whose estimate was never written because identify refused the wrong input.\n' %
         (sum(1 for r in rows if r[3] != 'wrong'), sum(1 for r in rows if r[3] == 'wrong')))
o.append(open(HERE + '/summary.md').read())
o.append('\n## All cases\n')
o.append('| tag | kind | class | input | exit | verdict | what was done | message / figures |\n|---|---|---|---|---|---|---|---|')
for r in rows:
    tag, kind, klass, expect, rc, v, wrong, truth, msg, note, diffs = r
    m = note or msg or diffs
    o.append('| %s | %s | %s | %s | %s | **%s** | %s | %s |' % (tag, kind, klass, expect, rc, v, wrong.replace('|', '/'), m.replace('|', '/')[:260]))
o.append('\n## Details: CONFIDENT-WRONG and FALSE-ALARM\n')
for r in rows:
    tag, kind, klass, expect, rc, v, wrong, truth, msg, note, diffs = r
    if v not in ('CONFIDENT-WRONG', 'FALSE-ALARM'):
        continue
    cmd = open(os.path.join(OUT, tag, 'cmd')).read().strip()
    o.append('### %s — %s (%s)\n' % (tag, v, klass))
    o.append('- input: %s' % wrong)
    o.append('- command: `%s`' % cmd)
    o.append('- expected: %s' % truth)
    if v == 'FALSE-ALARM':
        o.append('- got: exit %s — %s' % (rc, msg))
    else:
        o.append('- got: exit %s, no caution naming it; %s' % (rc, note or diffs))
    if tag in DET:
        o.append('- assessment: %s' % DET[tag])
    o.append('')
open(OUT + '/report.md', 'w').write('\n'.join(o) + '\n')
