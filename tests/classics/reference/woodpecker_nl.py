"""Woodpecker with exact planar kinematics (what a body/joint/shape scene would compute),
to size the difference from Glocker's linearised model. Same parameters.
Sleeve centre (0, y) on the pole axis (no horizontal freedom), rotation phi_M; spring pivot at
sleeve-fixed (l_M, 0); bird CoM at bird-fixed (l_G, 0) from the pivot; beak at bird-fixed
(-l_S, h_S) from the bird CoM; sleeve corners at sleeve-fixed (r_M, -h_M), (r_M, +h_M);
pole surface x = r_O (contacts are vertices against that line, normal +x, tangent +y)."""
import numpy as np
from nsmech import Contact
from woodpecker import (r_O, r_M, h_M, l_M, l_G, h_S, l_S, m_M, m_S, J_M, J_S, c_phi, g, eps1,
                        eps23, mu, run, summarize)


def R(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s], [s, c]])


def points(q):
    y, pM, pS = q
    O = np.array([0.0, y])
    P = O + R(pM) @ [l_M, 0]
    S = P + R(pS) @ [l_G, 0]
    B = S + R(pS) @ [-l_S, h_S]
    C2 = O + R(pM) @ [r_M, -h_M]
    C3 = O + R(pM) @ [r_M, h_M]
    return O, S, B, C2, C3


def jac(f, q, e=1e-7):
    cols = []
    for i in range(3):
        dq = np.zeros(3); dq[i] = e
        cols.append((f(q + dq) - f(q - dq)) / (2 * e))
    return np.column_stack(cols)


class WoodpeckerNL:
    def M(self, q):
        JO = jac(lambda x: points(x)[0], q)
        JS = jac(lambda x: points(x)[1], q)
        return m_M * JO.T @ JO + m_S * JS.T @ JS + np.diag([0, J_M, J_S])

    def h(self, q, u, t):
        y, pM, pS = q
        JS = jac(lambda x: points(x)[1], q)
        # bias acceleration of the bird CoM: d/dt(J_S) u = second directional derivative
        e = 1e-5
        acc = (points(q + e * u)[1] - 2 * points(q)[1] + points(q - e * u)[1]) / e ** 2
        JO = jac(lambda x: points(x)[0], q)
        f_grav = -(m_M * JO.T @ [0, g] + m_S * JS.T @ [0, g])
        f_spring = np.array([0, -c_phi * (pM - pS), -c_phi * (pS - pM)])
        return f_grav + f_spring - m_S * JS.T @ acc

    def contacts(self, q):
        O, S, B, C2, C3 = points(q)
        out = []
        for idx, name, eps in ((2, "beak", eps1), (3, "sleeve2", eps23), (4, "sleeve3", eps23)):
            Jp = jac(lambda x: points(x)[idx], q)
            p = points(q)[idx]
            out.append(Contact(p[0] - r_O, Jp[0], Jp[1], mu, eps, 0.0, name))
        return out


if __name__ == "__main__":
    import sys
    T = float(sys.argv[1]) if len(sys.argv) > 1 else 1.0
    q0 = np.array([0, -0.000107, 0.00312]); u0 = np.array([-0.3505, 31.81, 14.44])
    mdl = WoodpeckerNL()
    print("M(0) =\n", mdl.M(np.zeros(3)))
    print("gaps at q=0:", [c.g for c in mdl.contacts(np.zeros(3))])
    traj, beak = run(q0, u0, 2e-5, T, model=mdl)
    summarize(beak, "nonlinear kinematics, Leine IC, dt=2e-5")
    # The settled cycle: from the first beak impact after the 0.4 s transient to the last.
    settled = [b for b in beak if b[0] > 0.4]
    if len(settled) > 1:
        (t0, q0s), (t1, q1s), n = settled[0][:2], settled[-1][:2], len(settled) - 1
        t = traj[:, 0]
        w = traj[(t >= t0 - 1e-9) & (t <= t1 + 1e-9)]
        print(f"   {n} cycles from t = {t0:.5f} to {t1:.5f} s: period {(t1 - t0) / n:.9f} s, "
              f"descent {(q0s[0] - q1s[0]) / n:.9f} m per cycle")
        print(f"   phi_M in [{w[:, 2].min():.7f}, {w[:, 2].max():.7f}], "
              f"phi_S in [{w[:, 3].min():.7f}, {w[:, 3].max():.7f}] rad, "
              f"stuck (ydot = 0) {np.mean(np.abs(w[:, 4]) < 1e-12):.4f} of the time")
