"""MuJoCo as the oracle of hopsim's imported scenes (run by tests/mujoco_dynamics.rs).

Reads a JSON request on stdin and prints a JSON answer:
- {"list": true}: the planar models shipped in the installed `gymnasium` and `dm_control`
  packages, as {"models": [paths], "missing": [packages], "mujoco": version};
- {"models": [{"path", "states": [[q, u], ...], "drop": {"q", "duration"} or null}]}: for
  each model and state, MuJoCo's mass matrix (`mj_fullM`) and `qfrc_passive − qfrc_bias`
  after `mj_forward`; a state `[q, u, ctrl]` also gets the actuators' `qfrc_actuator`
  under the controls `ctrl`; for a drop, MuJoCo's own run from `q` at rest for `duration` seconds:
  the final `qpos`, the deepest contact (`contact.dist`) and the total normal force.
- {"free": [{"path", "q", "u", "duration", "dt"}]}: MuJoCo's RK4 at `dt` from `(q, u)` with
  contacts, joint limits and joint friction disabled (a free motion): the final `qpos`,
  `qvel`.
Prints {"skip": reason} when mujoco cannot be imported.
"""
import json
import os
import sys

# The planar models and where they are found: hopsim-mjcf's oracle lists them.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "hopsim-mjcf", "tests"))
from mujoco_oracle import MODELS, package_dir  # noqa: E402

# Models whose scenes cannot be written (docs/mjcf.md): the swimmer's fluid forces.
UNCONVERTED = {"swimmer.xml"}


def listing(mujoco):
    models, missing = [], []
    for package, (folder, files) in MODELS.items():
        root = package_dir(package)
        if root is None:
            missing.append(package)
            continue
        models.extend(os.path.join(root, folder, f) for f in files if f not in UNCONVERTED)
    return {"models": models, "missing": missing, "mujoco": mujoco.__version__}


def dynamics(mujoco, np, request):
    m = mujoco.MjModel.from_xml_path(request["path"])
    d = mujoco.MjData(m)
    out = {"states": []}
    for state in request["states"]:
        q, u = state[0], state[1]
        d.qpos[:] = q
        d.qvel[:] = u
        d.ctrl[:] = state[2] if len(state) > 2 else 0.0
        mujoco.mj_forward(m, d)
        full = np.zeros((m.nv, m.nv))
        if hasattr(d, "qM"):
            mujoco.mj_fullM(m, full, d.qM)
        else:  # MuJoCo 4: mj_fullM(m, d, dst)
            mujoco.mj_fullM(m, d, full)
        out["states"].append({
            "mass_matrix": full.tolist(),
            "forces": (d.qfrc_passive - d.qfrc_bias).tolist(),
            "actuator_forces": d.qfrc_actuator.tolist(),
        })
    drop = request.get("drop")
    if drop:
        mujoco.mj_resetData(m, d)
        d.qpos[:] = drop["q"]
        steps = int(round(drop["duration"] / m.opt.timestep))
        for _ in range(steps):
            mujoco.mj_step(m, d)
        force = np.zeros(6)
        normal = 0.0
        for i in range(d.ncon):
            mujoco.mj_contactForce(m, d, i, force)
            normal += force[0] * d.contact[i].frame[2]
        out["drop"] = {
            "qpos": d.qpos.tolist(),
            "deepest": min((c.dist for c in d.contact[:d.ncon]), default=0.0),
            "vertical_force": normal,
            "weight": float(m.body_subtreemass[0] * -m.opt.gravity[2]),
        }
    return out


def free_motion(mujoco, request):
    m = mujoco.MjModel.from_xml_path(request["path"])
    m.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    m.opt.timestep = request["dt"]
    m.opt.disableflags |= (mujoco.mjtDisableBit.mjDSBL_CONTACT | mujoco.mjtDisableBit.mjDSBL_LIMIT
                           | mujoco.mjtDisableBit.mjDSBL_FRICTIONLOSS)
    d = mujoco.MjData(m)
    d.qpos[:] = request["q"]
    d.qvel[:] = request["u"]
    for _ in range(int(round(request["duration"] / request["dt"]))):
        mujoco.mj_step(m, d)
    return {"qpos": d.qpos.tolist(), "qvel": d.qvel.tolist(), "time": d.time}


def main():
    try:
        import mujoco
        import numpy as np
    except ImportError as e:
        print(json.dumps({"skip": f"cannot import mujoco: {e}"}))
        return
    request = json.load(sys.stdin)
    if request.get("list"):
        print(json.dumps(listing(mujoco)))
        return
    if "free" in request:
        print(json.dumps({"free": [free_motion(mujoco, r) for r in request["free"]]}))
        return
    print(json.dumps({"models": [dynamics(mujoco, np, r) for r in request["models"]]}))


if __name__ == "__main__":
    main()
