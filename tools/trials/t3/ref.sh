#!/usr/bin/env bash
# usage: ref.sh BIN REFDIR BASE — clean reference outputs of the clean tables in BASE with BIN (trial 3: the score cases read
# the estimates id_t5, id_t5b and id_elx written here)
set -u
BIN=${1:?usage: ref.sh BIN REFDIR BASE}; R=${2:?REFDIR}; B=${3:?BASE (WORK/base)}
M=$(cd "$(dirname "$0")/../../../models" && pwd)
mkdir -p "$R"
$BIN analyze positioning $B/vmc3_iso230_2/positioning.csv > $R/an_pos.txt 2>&1
$BIN analyze positioning $B/est_laser_X/positioning.csv > $R/an_pos_elx.txt 2>&1
$BIN analyze ballbar $B/vmc3_ballbar_xy/ballbar_xy.csv > $R/an_bb.txt 2>&1
$BIN analyze drift $B/vmc3_iso230_3_etve/drift.csv > $R/an_dr_etve.txt 2>&1
$BIN analyze spindle $B/vmc3_spindle/spindle.csv > $R/an_sp.txt 2>&1
$BIN analyze rtest $B/trunnion5_rtest/rtest.csv > $R/an_rt.txt 2>&1
$BIN analyze probe $B/trunnion5_probe_sphere/probe.csv > $R/an_pr_sph.txt 2>&1
$BIN identify --machine $M/trunnion5.urdf --params location $B/trunnion5_rtest/rtest.csv --out $R/id_t5 > $R/id_t5.txt 2>&1
$BIN identify --machine $M/trunnion5.urdf --params location $B/t5_rtest_b/rtest.csv --out $R/id_t5b > $R/id_t5b.txt 2>&1
$BIN identify --machine $M/vmc3.urdf --params EXX:2 $B/est_laser_X/positioning.csv --out $R/id_elx > $R/id_elx.txt 2>&1
$BIN identify --machine $M/vmc3.urdf --params squareness,EXX:2,EYY:2,EZZ:2 $B/est_bb3/ballbar_xy.csv $B/est_bb3/ballbar_yz.csv $B/est_bb3/ballbar_zx.csv --out $R/id_bb3 > $R/id_bb3.txt 2>&1
$BIN score $R/id_t5/estimate.json $B/trunnion5_rtest/truth.json > $R/score_t5.txt 2>&1
$BIN score $R/id_elx/estimate.json $B/est_laser_X/truth.json > $R/score_elx.txt 2>&1
