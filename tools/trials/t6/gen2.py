# Trial 6, part 2 (exec'd by gen.py in its namespace): cases added after the first run's findings

# the same minus-first laser table, but zeroed at its first reading in time (750 mm): consistent with "zero = once"
t = minus_first(L(LX))
j = t.col('deviation_um')
z0 = float(t.rows[0][j])
t.fmap('deviation_um', lambda x: x - z0)
t.write(fx('idl_minus_first_zero750_legit.csv'))
case('idl_minus_first_zero750_legit', 'identify', 'clean (legit different)', IDV % ('EXX:2', fx('idl_minus_first_zero750_legit.csv')),
     'nothing wrong: minus pass first and the laser zeroed at that first reading (750 mm)', 'clean EXX (the datum is the first reading in time)', R_IDL, 'legit')


def bb_override(src, name, frac=0.9):
    t = L(src)
    blk = bb_blocks(t)
    rows = []
    for sense in ('ccw', 'cw'):
        rr = blk[sense]
        a = [float(r[1]) for r in rr]
        dv = [float(r[2]) for r in rr]
        s = a if sense == 'ccw' else [360 - x for x in a]
        if s[0] > s[-1]:
            rr, a, dv, s = rr[::-1], a[::-1], dv[::-1], s[::-1]
        for r, si in zip(rr, s):
            r2 = r[:]
            r2[2] = '%.1f' % interp(s, dv, frac * si)
            rows.append(r2)
    rows.sort(key=lambda r: float(r[3]))
    t.rows = rows
    return t.write(fx(name))


def bb_setup(src, name, ex, ey):
    t = L(src)
    R = float([l for l in t.pre if l.startswith('# radius_mm')][0].split('=')[1])
    j = t.col('deviation_um')
    for r in t.rows:
        th = math.radians(float(r[1]))
        d = float(r[j]) / 1000
        px, py = (R + d) * math.cos(th) + ex, (R + d) * math.sin(th) + ey
        r[j] = '%.1f' % ((math.hypot(px, py) - R) * 1000)
    return t.write(fx(name))


p = bb_setup(BB3['xy'], 'idbb_setup300_xy.csv', 0.300, -0.200)
case('idbb_setup300_legit', 'identify', 'clean (legit different)', IDV % (BBPAR, p + ' ' + BB3['yz'] + ' ' + BB3['zx']),
     'nothing wrong: XY ball-bar set up 300/-200 um off centre (exact bar-length geometry)', 'clean squareness and scales', R_IDBB, 'legit')
case('score_idbb_setup300_legit', 'score', 'follow-up', '{BIN} score {OUTDIR}/idbb_setup300_legit/out/estimate.json ' + B + '/est_bb3/truth.json',
     'score of the idbb_setup300_legit estimate', 'compensated RMS as the clean reference', 'score_bb3', 'legit')

p = bb_override(BB3['xy'], 'idbb_override90_xy.csv')
case('idbb_override90', 'identify', 'wrong test', IDV % (BBPAR, p + ' ' + BB3['yz'] + ' ' + BB3['zx']),
     'XY ball-bar run at 90 % feed override, angles assigned from time at the nominal feed (trace covers 324 deg labelled 360)',
     'a refusal or caution (reversal features 20 deg late); clean estimates', R_IDBB)

case('disc_bb_override90', 'discover ballbar', 'wrong test', '{BIN} discover ballbar ' + fx('bb_feed_override90.csv'),
     'ball-bar trace at 90 % feed override with angles from time at the nominal feed', 'a caution (reversals 20 deg late); clean effects', R_DB)

# data in the workpiece frame and the preamble saying so: legit if the tool's workpiece frame is this rotation
t = rot_wp(L(RT)).set_pre('frame', 'workpiece')
t.write(fx('rt_wpframe_pre_wp.csv'))
case('rt_wpframe_prewp_legit_id', 'identify', 'clean (legit different)', IDT5 % fx('rt_wpframe_pre_wp.csv'),
     'nothing wrong (if the tool\'s workpiece frame is Rz(-c)Rx(-a) of the machine frame): deviations in the rotating workpiece frame and preamble frame = workpiece',
     'location errors as clean', R_IDT5, 'legit')
case('rt_wpframe_prewp_legit_an', 'analyze rtest', 'clean (legit different)', ANR + fx('rt_wpframe_pre_wp.csv'),
     'nothing wrong: deviations in the workpiece frame, preamble frame = workpiece', 'ranges as clean if reported in machine axes', R_RT, 'legit')
