"""Glocker (1995) sec. 5.3.4 'Stoss ohne Kollision' set-up as coded in cardillo's
examples/Painleve.py: m = 1, half-length s = 1, J = m s^2/3, g = 10, mu = 5/3, eps = 0,
phi0 = 31 deg, lower end on the floor, sliding at 30 m/s with the lower end leading.
Mirrored into painleve.py's convention (contact end at C - s(cos, sin), sliding towards -x)."""
import math
import numpy as np
import painleve
from painleve import Rod, mu_crit
from nsmech import moreau_step

painleve.g = 10.0
import nsmech


def run(dt, T=1.5):
    rod = Rod(1.0, 1.0, 5 / 3)
    th0 = math.radians(31)
    q = np.array([0.0, math.sin(th0), th0]); u = np.array([-30.0, 0.0, 0.0]); t = 0.0
    out = []
    while t < T:
        uA = u.copy()
        t, q, u, closed, LN, LT = moreau_step(rod, t, q, u, dt)
        gT = u[0] + math.sin(q[2]) * u[2]
        out.append((t, q[2], u[0], gT, LN[0] if LN else 0.0, len(closed)))
    return np.array(out)


for dt in (5e-4, 1e-4, 2e-5):
    o = run(dt)
    t, th, xd, gT, LN, nc = o.T
    # the impact without collision: largest normal percussion per step, sliding stops
    i = int(np.argmax(LN))
    j = np.argmax(np.abs(gT) < 1e-9)
    print(f"dt={dt}: max Lambda_N {LN[i]:.5f} N s at t={t[i]:.5f} s, theta={math.degrees(th[i]):.3f} deg "
          f"(mu_c={mu_crit(th[i]):.4f}), slip before {gT[i-1]:.4f} after {gT[i]:.2e} m/s; "
          f"first stick at t={t[j]:.5f}")
print("mu_c(31 deg) =", mu_crit(math.radians(31)), "; theta where mu_c = 5/3:",
      [round(math.degrees(x), 4) for x in np.linspace(0.01, 1.56, 200000) if abs(mu_crit(x) - 5 / 3) < 2e-5][:3])

print("--- slip history around the crossing of 45 deg")
for dt in (5e-4, 1e-4, 2e-5):
    o = run(dt, 0.9)
    t, th, xd, gT, LN, nc = o.T
    k = int(np.argmax(th > math.radians(45)))
    stop = k + int(np.argmax(np.abs(gT[k:]) < 1e-6))
    print(f"dt={dt}: theta crosses 45 deg at t={t[k]:.5f}; slip {gT[k-1]:.4f} m/s; slip first zero at "
          f"t={t[stop]:.5f} (theta {math.degrees(th[stop]):.3f} deg); sum Lambda_N over [{t[k-1]:.4f},{t[stop]:.4f}] = "
          f"{LN[k-1:stop+1].sum():.4f} N s; steps: {stop-k+1}")
