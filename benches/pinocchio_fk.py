#!/usr/bin/env python3
"""Pinocchio's nominal forward kinematics on models/trunnion5.urdf, the reference for
`cargo bench --bench kinematics` (`nominal/single`, `errors/single`).

mtwin's pose is `workpiece_from_tool`: the links `tool` and `workpiece` are the ends of the
two branches (src/machine/mod.rs). The Pinocchio equivalent timed here is one
`pin.forwardKinematics(model, data, q)` followed by one `pin.updateFramePlacements(model,
data)` (every frame, the `tool` and `workpiece` ones among them), per pose, over 1000 random
configurations within the joint limits (`pin.randomConfiguration`, seeded; the continuous C
and S joints are drawn over a whole turn). No batch or all-terms entry point is used.

Each figure is the median over repeats (`timeit`) of the time per pose of a tight Python
loop over the 1000 configurations. Python and Boost.Python cost something per call, so the
script also times the same two calls on an empty model (no joint, one frame): that is the
call overhead, and the raw figure minus it is Pinocchio's own work, the figure comparable
with criterion's ns per pose of a Rust function called in a loop (the raw figure is what a
Python user pays). For context it also prints the variant that updates only the two frames
mtwin uses (`pin.updateFramePlacement` for `tool` and for `workpiece`: one more Python call,
so more overhead), and checks the frames against the URDF's home pose.

Not run in CI. To run it (no other build or benchmark running, for stable figures):

    python3 -m venv ~/.cache/mtwin-pin && ~/.cache/mtwin-pin/bin/pip install pin
    ~/.cache/mtwin-pin/bin/python benches/pinocchio_fk.py [--repeat 31]
"""
import argparse
import os
import platform
import statistics
import timeit

import numpy as np
import pinocchio as pin

POSES = 1000
URDF = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "models", "trunnion5.urdf")


def median_ns_per_pose(statement, namespace, repeat):
    """Median over `repeat` runs of `statement` (one pass over POSES poses), in ns per pose."""
    timer = timeit.Timer(statement, globals=namespace)
    timer.timeit(number=3)  # warm-up
    runs = timer.repeat(repeat=repeat, number=5)
    return statistics.median(runs) / (5 * POSES) * 1e9


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=31, help="timed repeats (median taken)")
    args = parser.parse_args()

    model = pin.buildModelFromUrdf(URDF)
    data = model.createData()
    tool, workpiece = model.getFrameId("tool"), model.getFrameId("workpiece")
    assert tool < model.nframes and workpiece < model.nframes, "tool and workpiece frames"
    pin.seed(1)
    configurations = [pin.randomConfiguration(model) for _ in range(POSES)]

    # The same two calls on an empty model: what Python and Boost.Python cost per pose.
    empty = pin.Model()
    empty_data = empty.createData()
    empty_q = pin.neutral(empty)
    empty_configurations = [empty_q.copy() for _ in range(POSES)]

    namespace = dict(
        pin=pin,
        model=model,
        data=data,
        tool=tool,
        workpiece=workpiece,
        qs=configurations,
        empty=empty,
        empty_data=empty_data,
        empty_qs=empty_configurations,
    )
    full = (
        "for q in qs:\n"
        "    pin.forwardKinematics(model, data, q)\n"
        "    pin.updateFramePlacements(model, data)"
    )
    overhead = (
        "for q in empty_qs:\n"
        "    pin.forwardKinematics(empty, empty_data, q)\n"
        "    pin.updateFramePlacements(empty, empty_data)"
    )
    two_frames = (
        "for q in qs:\n"
        "    pin.forwardKinematics(model, data, q)\n"
        "    pin.updateFramePlacement(model, data, tool)\n"
        "    pin.updateFramePlacement(model, data, workpiece)"
    )
    two_frames_overhead = (
        "for q in empty_qs:\n"
        "    pin.forwardKinematics(empty, empty_data, q)\n"
        "    pin.updateFramePlacement(empty, empty_data, 0)\n"
        "    pin.updateFramePlacement(empty, empty_data, 0)"
    )
    empty_loop = "for q in qs:\n    pass"

    raw = median_ns_per_pose(full, namespace, args.repeat)
    calls = median_ns_per_pose(overhead, namespace, args.repeat)
    raw_two = median_ns_per_pose(two_frames, namespace, args.repeat)
    calls_two = median_ns_per_pose(two_frames_overhead, namespace, args.repeat)
    loop = median_ns_per_pose(empty_loop, namespace, args.repeat)

    # The relative pose, to check the frames against mtwin: at all axes zero the tool tip is at
    # (-325, -275, 100) mm from the workpiece (models/trunnion5.urdf).
    pin.forwardKinematics(model, data, pin.neutral(model))
    pin.updateFramePlacements(model, data)
    home = data.oMf[workpiece].actInv(data.oMf[tool]).translation * 1e3
    assert np.allclose(home, [-325.0, -275.0, 100.0]), home

    print(f"pinocchio {pin.__version__} on {platform.python_implementation()} "
          f"{platform.python_version()}, {platform.machine()}; model {model.name}: "
          f"{model.njoints - 1} joints (nq = {model.nq}), {model.nframes} frames; "
          f"{POSES} random configurations, median of {args.repeat} repeats")
    print(f"  empty Python loop:                                   {loop:7.1f} ns/pose")
    print(f"  forwardKinematics + updateFramePlacements, raw:      {raw:7.1f} ns/pose")
    print(f"  the same two calls on an empty model (overhead):     {calls:7.1f} ns/pose")
    print(f"  forwardKinematics + updateFramePlacement(tool, workpiece), raw: "
          f"{raw_two:7.1f} ns/pose, overhead {calls_two:.1f}, net {raw_two - calls_two:.1f}")
    print(f"README: Pinocchio {pin.__version__} nominal forward kinematics of trunnion5 "
          f"(forwardKinematics + updateFramePlacements): {raw - calls:.0f} ns per pose net of "
          f"Python call overhead ({raw:.0f} ns raw, {calls:.0f} ns overhead), "
          f"the figure comparable with `cargo bench --bench kinematics`")


if __name__ == "__main__":
    main()
