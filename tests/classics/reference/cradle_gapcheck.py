"""How the index set reacts to 'touching' balls whose gap is computed with round-off."""
import numpy as np
from cradle import Cradle, stepper_run
from nsmech import moreau_step

# positions as in stepper_run: the computed gaps between resting balls
R = 0.05
for n in (3, 5):
    q = np.array([0.0] + [0.0123 + 2 * R + i * (2 * R + 0.0) for i in range(n - 1)])
    print(n, "computed gaps of 'touching' balls:", [q[i + 1] - q[i] - 2 * R for i in range(1, n - 1)])
for n in (3, 5):
    for eps in (1.0, 0.9, 0.5, 0.0):
        for gap in (-1e-12,):
            u, imp = stepper_run(n, eps, gap)
            print(f"n={n} eps={eps} gap={gap:g}: u_end = {np.round(u, 12)} impact steps {imp}")
# exactly representable layout: R = 1/16, positions multiples of 1/8 -> gaps exactly 0
class C2(Cradle):
    pass
for n in (3, 5):
    for eps in (1.0, 0.5):
        mdl = Cradle(n, eps, R=0.0625)
        q = np.array([-0.0625] + [0.125 * (i + 1) for i in range(n - 1)])  # ball 1 0.0625 m off
        u = np.zeros(n); u[0] = 1.0
        t = 0.0; imp = []
        for k in range(200):
            t, q, u, closed, LN, LT = moreau_step(mdl, t, q, u, 1e-3)
            if any(l > 0 for l in LN): imp.append((k + 1, len(closed)))
        print(f"exact layout n={n} eps={eps}: u = {np.round(u, 12)} impacts {imp}")
