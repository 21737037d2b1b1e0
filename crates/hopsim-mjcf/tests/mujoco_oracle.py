"""MuJoCo as the oracle of hopsim-mjcf (run by tests/mujoco_oracle.rs).

Finds the planar models shipped in the installed `gymnasium` and `dm_control` packages,
compiles each with MuJoCo twice (as written, and with static bodies fused into their
parents, MuJoCo's own composition of welded bodies) and prints, as JSON, what MuJoCo
computed: bodies (mass, world centre of mass and world inertia tensor at qpos0), joints
(qpos address, world axis and anchor, ranges and parameters), actuators and options.
Prints {"skip": reason} when mujoco cannot be imported.
"""
import importlib.util
import json
import os
import sys

MODELS = {
    "gymnasium": ("envs/mujoco/assets", ["hopper.xml", "walker2d_v5.xml", "half_cheetah.xml",
                  "inverted_pendulum.xml", "inverted_double_pendulum.xml", "reacher.xml",
                  "swimmer.xml"]),
    "dm_control": ("suite", ["hopper.xml", "walker.xml", "cheetah.xml", "cartpole.xml",
                   "acrobot.xml", "pendulum.xml"]),
}


def package_dir(name):
    spec = importlib.util.find_spec(name)
    if spec is None or not spec.submodule_search_locations:
        return None
    return list(spec.submodule_search_locations)[0]


def bodies(mujoco, m):
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    out = []
    for b in range(1, m.nbody):
        r = d.ximat[b].reshape(3, 3)
        inertia = r @ (m.body_inertia[b][:, None] * r.T)
        out.append({
            "name": m.body(b).name,
            "mass": float(m.body_mass[b]),
            "dofs": int(m.body_dofnum[b]),
            "xpos": d.xpos[b].tolist(),
            "xipos": d.xipos[b].tolist(),
            "inertia": inertia.tolist(),
        })
    return out, d


def describe(mujoco, path):
    m = mujoco.MjModel.from_xml_path(path)
    unfused, d = bodies(mujoco, m)
    spec = mujoco.MjSpec.from_file(path)
    spec.compiler.fusestatic = True
    fused, _ = bodies(mujoco, spec.compile())
    joints = []
    for j in range(m.njnt):
        joints.append({
            "name": m.joint(j).name,
            "type": int(m.jnt_type[j]),
            "qpos": int(m.jnt_qposadr[j]),
            "xaxis": d.xaxis[j].tolist(),
            "xanchor": d.xanchor[j].tolist(),
            "limited": bool(m.jnt_limited[j]),
            "range": m.jnt_range[j].tolist(),
            "ref": float(m.qpos0[m.jnt_qposadr[j]]),
            "springref": float(m.qpos_spring[m.jnt_qposadr[j]]),
            "stiffness": float(m.jnt_stiffness[j]),
            "damping": float(m.dof_damping[m.jnt_dofadr[j]]),
            "armature": float(m.dof_armature[m.jnt_dofadr[j]]),
            "frictionloss": float(m.dof_frictionloss[m.jnt_dofadr[j]]),
        })
    actuators = []
    for a in range(m.nu):
        actuators.append({
            "joint": m.joint(int(m.actuator_trnid[a][0])).name,
            "gear": float(m.actuator_gear[a][0]),
            "ctrllimited": bool(m.actuator_ctrllimited[a]),
            "ctrlrange": m.actuator_ctrlrange[a].tolist(),
            "forcelimited": bool(m.actuator_forcelimited[a]),
            "forcerange": m.actuator_forcerange[a].tolist(),
            "gain": float(m.actuator_gainprm[a][0]),
            "bias": m.actuator_biasprm[a][:3].tolist(),
        })
    return {
        "path": path,
        "bodies": unfused,
        "fused": fused,
        "joints": joints,
        "actuators": actuators,
        "timestep": float(m.opt.timestep),
        "gravity": m.opt.gravity.tolist(),
    }


def main():
    try:
        import mujoco
    except ImportError as e:
        print(json.dumps({"skip": f"mujoco cannot be imported ({e})"}))
        return
    models, missing = [], []
    for package, (folder, names) in MODELS.items():
        root = package_dir(package)
        if root is None:
            missing.append(package)
            continue
        for name in names:
            path = os.path.join(root, folder, name)
            if not os.path.exists(path):
                missing.append(f"{package}/{folder}/{name}")
                continue
            models.append(describe(mujoco, path))
    print(json.dumps({"mujoco": mujoco.__version__, "models": models, "missing": missing}))


if __name__ == "__main__":
    sys.exit(main())
