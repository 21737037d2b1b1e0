"""MuJoCo as the oracle of imported closed chains (crates/hopsim-sim/tests/mjcf_loops.rs).

Reads one JSON request on stdin, prints one JSON answer on stdout:

- {"path", "q", "u", "duration", "dt"}: the model at `path` from `(q, u)` by MuJoCo's RK4
  at `dt` for `duration`, contacts and joint limits off. Answers the final `qpos`, `qvel`
  and, at the start (after `mj_forward`) and at the end, the world positions of each
  `connect` equality's anchor on body1 and on body2 (`eq_data[0:3]`, `eq_data[3:6]`).

Without the `mujoco` package it answers {"skip": why}.
"""

import json
import sys


def anchors(mujoco, np, m, d):
    out = []
    for i in range(m.neq):
        if m.eq_type[i] != mujoco.mjtEq.mjEQ_CONNECT:
            continue
        ends = []
        for body, data in ((m.eq_obj1id[i], m.eq_data[i][0:3]), (m.eq_obj2id[i], m.eq_data[i][3:6])):
            ends.append(list(d.xpos[body] + d.xmat[body].reshape(3, 3) @ data))
        out.append(ends)
    return out


def main():
    request = json.load(sys.stdin)
    try:
        import mujoco
        import numpy as np
    except ImportError as e:
        print(json.dumps({"skip": f"the mujoco package is not installed ({e})"}))
        return
    m = mujoco.MjModel.from_xml_path(request["path"])
    m.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    m.opt.timestep = request["dt"]
    m.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT | mujoco.mjtDisableBit.mjDSBL_LIMIT
    d = mujoco.MjData(m)
    d.qpos[:] = request["q"]
    d.qvel[:] = request["u"]
    mujoco.mj_forward(m, d)
    start = anchors(mujoco, np, m, d)
    for _ in range(int(round(request["duration"] / request["dt"]))):
        mujoco.mj_step(m, d)
    mujoco.mj_forward(m, d)
    print(json.dumps({
        "qpos": list(d.qpos),
        "qvel": list(d.qvel),
        "start": start,
        "end": anchors(mujoco, np, m, d),
        "version": mujoco.__version__,
    }))


if __name__ == "__main__":
    main()
