#!/usr/bin/env bash
# usage: ref.sh BIN REFDIR BASE — clean reference outputs of the clean tables in BASE (bundled scenarios) with BIN (trial 6: + discover references)
set -u
BIN=${1:?usage: ref.sh BIN REFDIR BASE}; R=${2:?REFDIR}; B=${3:?BASE (WORK/base)}
M=$(cd "$(dirname "$0")/../../../models" && pwd)
mkdir -p "$R"
$BIN analyze positioning $B/vmc3_iso230_2/positioning.csv > $R/an_pos.txt 2>&1
$BIN analyze positioning $B/vmc3_warmup_laser/positioning.csv > $R/an_pos_warm.txt 2>&1
$BIN analyze ballbar $B/vmc3_ballbar_xy/ballbar_xy.csv > $R/an_bb.txt 2>&1
$BIN analyze drift $B/vmc3_iso230_3_etve/drift.csv > $R/an_dr_etve.txt 2>&1
$BIN analyze drift $B/vmc3_iso230_3_spindle/drift.csv > $R/an_dr_sp.txt 2>&1
$BIN analyze spindle $B/vmc3_spindle/spindle.csv > $R/an_sp.txt 2>&1
$BIN analyze spindle $B/trunnion5_c_axis/spindle.csv > $R/an_ca.txt 2>&1
$BIN analyze rtest $B/trunnion5_rtest/rtest.csv > $R/an_rt.txt 2>&1
$BIN analyze probe $B/vmc3_probe_ring_mesh/probe.csv > $R/an_pr_ring.txt 2>&1
$BIN analyze probe $B/trunnion5_probe_sphere/probe.csv > $R/an_pr_sph.txt 2>&1
$BIN analyze probe $B/vmc3_ballplate/probe.csv > $R/an_pr_plate.txt 2>&1
$BIN identify --machine $M/trunnion5.urdf --params location $B/trunnion5_rtest/rtest.csv --out $R/id_t5 > $R/id_t5.txt 2>&1
$BIN identify --machine $M/trunnion5.urdf --params location $B/trunnion5_probe_sphere/spheres.csv --out $R/id_sph > $R/id_sph.txt 2>&1
$BIN identify --machine $M/vmc3.urdf --params squareness,EXX:2,EYY:2,EZZ:2 $B/est_bb3/ballbar_xy.csv $B/est_bb3/ballbar_yz.csv $B/est_bb3/ballbar_zx.csv --out $R/id_bb3 > $R/id_bb3.txt 2>&1
$BIN identify --machine $M/vmc3.urdf --params EXX:2 $B/est_laser_X/positioning.csv --out $R/id_elx > $R/id_elx.txt 2>&1
$BIN score $R/id_t5/estimate.json $B/trunnion5_rtest/truth.json > $R/score_t5.txt 2>&1
$BIN score $R/id_sph/estimate.json $B/trunnion5_probe_sphere/truth.json > $R/score_sph.txt 2>&1
$BIN score $R/id_elx/estimate.json $B/est_laser_X/truth.json > $R/score_elx.txt 2>&1
$BIN score $R/id_bb3/estimate.json $B/est_bb3/truth.json > $R/score_bb3.txt 2>&1
$BIN analyze positioning $B/vmc3_warmup_laser/positioning.csv > $R/an_pos_warm.txt 2>&1
$BIN discover positioning $B/vmc3_warmup_laser/positioning.csv > $R/disc_pos_warm.txt 2>&1
$BIN discover ballbar $B/vmc3_ballbar_xy/ballbar_xy.csv > $R/disc_bb.txt 2>&1
$BIN discover spindle $B/vmc3_spindle/spindle.csv > $R/disc_sp.txt 2>&1
