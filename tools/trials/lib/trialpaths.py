"""Paths shared by the trial generators (tools/trials/tN/gen.py).

REPO  the repository root, found from this file's location (tools/trials/lib/ -> ../../..)
WORK  where generated data goes: argv[1] of the generator, else $MTWIN_TRIALS_OUT, else /tmp/mtwin-trials.
      Never inside the repository.
BASE  WORK/base: the clean outputs of `mtwin run` that run.sh makes (one folder per scenario).

cases.tsv holds placeholders instead of these paths; run_all.sh fills them in:
  {BIN} {OUTDIR} {TAG}  the binary, the trial's result folder, TAG/out (as in the original trials)
  {BASE} WORK/base   {FX} WORK/tN/fx   {SCEN} WORK/tN/scen   {HERE} tools/trials/tN   {MODELS} REPO/models
"""
import os
import sys

LIB = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.abspath(os.path.join(LIB, '..', '..', '..'))
WORK = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.environ.get('MTWIN_TRIALS_OUT', '/tmp/mtwin-trials'))
BASE = os.path.join(WORK, 'base')
MODELS = os.path.join(REPO, 'models')
SCENARIOS = os.path.join(REPO, 'scenarios')

if WORK == REPO or WORK.startswith(REPO + os.sep):
    sys.exit('trials: the output directory %s is inside the repository; give one outside it' % WORK)


def placeholders(trial_work, here):
    """(real path, placeholder) pairs, most specific first"""
    return [(os.path.join(trial_work, 'fx'), '{FX}'), (os.path.join(trial_work, 'scen'), '{SCEN}'),
            (BASE, '{BASE}'), (here, '{HERE}'), (MODELS, '{MODELS}'), (SCENARIOS, '{SCENARIOS}')]


def write_cases(path, header, cases, trial_work, here):
    """write cases.tsv with the machine-specific paths turned into placeholders"""
    subs = placeholders(trial_work, here)
    with open(path, 'w') as f:
        f.write('\t'.join(header) + '\n')
        for c in cases:
            row = []
            for x in c:
                for real, ph in subs:
                    x = x.replace(real, ph)
                row.append(x)
            f.write('\t'.join(row) + '\n')
