#!/bin/bash
# mtwin's pose against Pinocchio's C++ forward kinematics, side by side on this machine.
#
# Builds Pinocchio's timer (pin_fk.cpp: forwardKinematics + the `tool` and `workpiece` frames +
# their relative pose, nominal) with build_pin_fk.sh (by default from ../shared/bench; set
# PIN_FK_BUILD to another copy) and mtwin's (`benches/pose_timer.rs`: the nominal pose and the
# error-model pose of trunnion5 with the 15 errors of scenarios/trunnion5_volumetric.toml), then
# runs them in turn, Pinocchio then mtwin, ROUNDS times (default 7) over POSES poses each (default
# 2 000 000), and prints every round's figures, the medians and the median of the per-round
# ratios. Run it on an otherwise idle machine:
#
#   benches/pinocchio_side_by_side.sh [ROUNDS] [POSES]
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-7}
poses=${2:-2000000}
build=${PIN_FK_BUILD:-../shared/bench/build_pin_fk.sh}
pin=$(bash "$build")
cargo bench --quiet --bench pose_timer --no-run 2>/dev/null
out=$(mktemp)
trap 'rm -f "$out"' EXIT
for round in $(seq "$rounds"); do
  p=$("$pin" models/trunnion5.urdf "$poses" | awk '{print $2}')
  read -r n e < <(cargo bench --quiet --bench pose_timer -- "$poses" 2>/dev/null | awk '{print $2, $4}')
  echo "$round $p $n $e" | tee -a "$out"
done | awk 'BEGIN { print "round  pinocchio_nominal_ns  mtwin_nominal_ns  mtwin_errors_ns" }
            { printf "%5d  %20.1f  %16.1f  %15.1f\n", $1, $2, $3, $4 }'
sort_median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
echo "median  $(awk '{print $2}' "$out" | sort_median)  $(awk '{print $3}' "$out" | sort_median)  $(awk '{print $4}' "$out" | sort_median)"
echo "median of the per-round ratios, mtwin errors / Pinocchio nominal: $(awk '{printf "%.3f\n", $4 / $2}' "$out" | sort_median)"
echo "median of the per-round ratios, mtwin nominal / Pinocchio nominal: $(awk '{printf "%.3f\n", $3 / $2}' "$out" | sort_median)"
