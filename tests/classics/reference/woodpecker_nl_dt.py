import sys
import numpy as np
from woodpecker_nl import WoodpeckerNL
from woodpecker import run, summarize
dt = float(sys.argv[1]); T = float(sys.argv[2])
q0 = np.array([0, -0.000107, 0.00312]); u0 = np.array([-0.3505, 31.81, 14.44])
traj, beak = run(q0, u0, dt, T, model=WoodpeckerNL())
summarize(beak, f"nonlinear kinematics, Leine IC, dt={dt}")
