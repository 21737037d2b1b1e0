"""Woodpecker toy, Glocker's linearised 3-DOF model (Glocker 1995 thesis sec. 5.3.5; Pfeiffer &
Glocker 1996), parameters as in Siconos' examples/mechanics/Woodpecker/WoodPeckerConsts.h and
Leine's sys_woodpecker.m. q = (y, phi_M, phi_S): sleeve height, sleeve angle, bird angle.
Simulated with the docs/physics.md section-4 step (independent implementation, nsmech.py)."""
import sys
import numpy as np
from nsmech import Contact, moreau_step

r_O, r_M, h_M, l_M, l_G, h_S, l_S = 0.0025, 0.0031, 0.0058, 0.010, 0.015, 0.02, 0.0201
m_M, m_S, J_M, J_S = 0.0003, 0.0045, 5.0e-9, 7.0e-7
c_phi, g = 0.0056, 9.81
eps1, eps23, mu = 0.5, 0.0, 0.3


class Woodpecker:
    Mc = np.array([[m_S + m_M, m_S * l_M, m_S * l_G],
                   [m_S * l_M, J_M + m_S * l_M ** 2, m_S * l_M * l_G],
                   [m_S * l_G, m_S * l_M * l_G, J_S + m_S * l_G ** 2]])

    def M(self, q):
        return self.Mc

    def h(self, q, u, t):
        y, pM, pS = q
        return np.array([-(m_S + m_M) * g, -c_phi * (pM - pS) - m_S * g * l_M,
                         -c_phi * (pS - pM) - m_S * g * l_G])

    def contacts(self, q):
        y, pM, pS = q
        return [Contact(l_M + l_G - l_S - r_O - h_S * pS, [0, 0, -h_S], [1, l_M, l_G - l_S], mu, eps1, 0.0, "beak"),
                Contact(r_M - r_O + h_M * pM, [0, h_M, 0], [1, r_M, 0], mu, eps23, 0.0, "sleeve2"),
                Contact(r_M - r_O - h_M * pM, [0, -h_M, 0], [1, r_M, 0], mu, eps23, 0.0, "sleeve3")]


def run(q0, u0, dt, T, model=None):
    mdl = model or Woodpecker()
    q, u, t = np.array(q0, float), np.array(u0, float), 0.0
    beak = []   # (t, q, u^A, u^E) of steps where the beak impact starts (beak closed, gamma^A < 0)
    traj = []
    was_closed = False
    while t < T - 1e-12:
        uA = u.copy()
        t, q, u, closed, LN, LT = moreau_step(mdl, t, q, u, dt)
        bclosed = any(c.name == "beak" for c in closed)
        if bclosed and not was_closed:
            beak.append((t, q.copy(), uA, u.copy()))
        was_closed = bclosed
        traj.append((t, *q, *u))
    return np.array(traj), beak


def summarize(beak, label):
    ts = np.array([b[0] for b in beak])
    ys = np.array([b[1][0] for b in beak])
    print(f"{label}: beak impacts at {np.round(ts, 5)}")
    if len(ts) > 2:
        P = np.diff(ts)
        dy = np.diff(ys)
        print(f"   periods {np.round(P, 5)}")
        print(f"   descent per period {np.round(dy, 6)}  speed {np.round(dy / P, 5)}")
        for b in beak[-2:]:
            print(f"   at beak impact t={b[0]:.5f}: q={np.round(b[1], 6)} u^A={np.round(b[2], 4)} u^E={np.round(b[3], 4)}")


if __name__ == "__main__":
    T = float(sys.argv[1]) if len(sys.argv) > 1 else 1.0
    siconos0 = ([0, -0.1036, -0.2788], [-0.3411, 4.8572e-15, -7.4583])
    leine0 = ([0, -0.000107, 0.00312], [-0.3505, 31.81, 14.44])
    for dt in (2e-5, 1e-5):
        traj, beak = run(*siconos0, dt, T)
        summarize(beak, f"Siconos IC, dt={dt}")
        np.save(f"woodpecker_traj_{dt:g}.npy", traj)
    traj, beak = run(*leine0, 1.5e-4, T)
    summarize(beak, "Leine IC, dt=1.5e-4")
    traj, beak = run(*leine0, 2e-5, T)
    summarize(beak, "Leine IC, dt=2e-5")
