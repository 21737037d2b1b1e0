"""Slider-crank with a translational clearance joint, Flores, Leine & Glocker (2010).
Parameters as in Siconos examples/mechanics/SliderCrank/SCConst.h ("according to Table 1")
and cardillo's SliderCrankFlores (eqs. (90)-(96) of the paper's book-chapter version).
q = (theta1, theta2, theta3) absolute angles of crank, rod, slider; slider CoM at the rod end.
Simulated with the docs/physics.md section-4 step (nsmech.py)."""
import math
import sys
import numpy as np
from nsmech import Contact, moreau_step

l1, l2, a, b, c = 0.1530, 0.3060, 0.05, 0.025, 0.001
d = 2 * (b + c)
m1, m2, m3 = 0.038, 0.038, 0.076
J1, J2, J3 = 7.4e-5, 5.9e-4, 2.7e-6
grav = 9.81
eN, mu = 0.4, 0.01
CORNERS = [(-a, +b, +1), (+a, +b, +1), (-a, -b, -1), (+a, -b, -1)]  # (x, y) in slider frame, wall side


class SliderCrank:
    def __init__(self, eN=eN, mu=mu):
        self.eN, self.mu = eN, mu

    def M(self, q):
        t1, t2, t3 = q
        M12 = (m2 / 2 + m3) * l1 * l2 * math.cos(t2 - t1)
        return np.array([[J1 + (m1 / 4 + m2 + m3) * l1 ** 2, M12, 0],
                         [M12, J2 + (m2 / 4 + m3) * l2 ** 2, 0],
                         [0, 0, J3]])

    def h(self, q, u, t):
        t1, t2, t3 = q
        w1, w2, w3 = u
        f = (m2 / 2 + m3) * l1 * l2 * math.sin(t2 - t1)
        return np.array([f * w2 ** 2 - (m1 / 2 + m2 + m3) * grav * l1 * math.cos(t1),
                         -f * w1 ** 2 - (m2 / 2 + m3) * grav * l2 * math.cos(t2), 0.0])

    def contacts(self, q):
        t1, t2, t3 = q
        c3, s3 = math.cos(t3), math.sin(t3)
        out = []
        for i, (xc, yc, side) in enumerate(CORNERS):
            # corner position and its Jacobian
            y = l1 * math.sin(t1) + l2 * math.sin(t2) + xc * s3 + yc * c3
            Jy = np.array([l1 * math.cos(t1), l2 * math.cos(t2), xc * c3 - yc * s3])
            Jx = np.array([-l1 * math.sin(t1), -l2 * math.sin(t2), -xc * s3 - yc * c3])
            gN = d / 2 - side * y
            out.append(Contact(gN, -side * Jy, Jx, self.mu, self.eN, 0.0, f"corner{i+1}"))
        return out


def energy(q, u):
    t1, t2, t3 = q
    T = 0.5 * u @ SliderCrank().M(q) @ u
    V = grav * ((m1 / 2 + m2 + m3) * l1 * math.sin(t1) + (m2 / 2 + m3) * l2 * math.sin(t2))
    return T + V


def run(dt, T, eN_=eN, mu_=mu, u0=(150.0, -75.0, 0.0)):
    mdl = SliderCrank(eN_, mu_)
    q, u, t = np.zeros(3), np.array(u0, float), 0.0
    E0 = energy(q, u)
    rows = []
    impacts = {k: [] for k in range(4)}
    closed_prev = set()
    while t < T - 1e-12:
        uA = u.copy()
        t, q, u, closed, LN, LT = moreau_step(mdl, t, q, u, dt)
        now = set()
        for cc, ln in zip(closed, LN):
            k = int(cc.name[-1]) - 1
            now.add(k)
            gA = cc.wN @ uA
            if k not in closed_prev and gA < -1e-6:
                impacts[k].append((t, q[0] / (2 * math.pi), gA, ln))
        closed_prev = now
        rows.append((t, *q, *u, energy(q, u)))
    return np.array(rows), impacts, E0


def ideal(T=0.2, n=200001):
    """Ideal prismatic joint (no clearance): energy conservation gives omega1(theta1)."""
    mdl = SliderCrank()
    E0 = energy(np.zeros(3), np.array([150.0, -75.0, 0.0]))
    th = np.linspace(0, 2 * math.pi, n)
    w = np.empty(n); xs = np.empty(n); vs = np.empty(n)
    for i, t1 in enumerate(th):
        t2 = -math.asin(l1 * math.sin(t1) / l2)
        dt2 = -l1 * math.cos(t1) / (l2 * math.cos(t2))
        Mq = mdl.M([t1, t2, 0.0])
        Meff = np.array([1, dt2, 0]) @ Mq @ np.array([1, dt2, 0])
        V = grav * ((m1 / 2 + m2 + m3) * l1 * math.sin(t1) + (m2 / 2 + m3) * l2 * math.sin(t2))
        w[i] = math.sqrt(2 * (E0 - V) / Meff)
        xs[i] = l1 * math.cos(t1) + l2 * math.cos(t2)
        vs[i] = -(l1 * math.sin(t1) + l2 * math.sin(t2) * dt2) * w[i]
    t_rev = np.trapezoid(1 / w, th)
    return E0, t_rev, w.min(), w.max(), th[np.argmin(w)], th[np.argmax(w)], vs.min(), vs.max()


if __name__ == "__main__":
    E0, trev, wmin, wmax, thmin, thmax, vmin, vmax = ideal()
    print(f"ideal joint: E0={E0:.6f} J, first-revolution time {trev:.6f} s, omega1 in [{wmin:.4f}, {wmax:.4f}] "
          f"(min at {math.degrees(thmin):.1f} deg, max at {math.degrees(thmax):.1f} deg), slider speed in [{vmin:.4f}, {vmax:.4f}] m/s")
    T = float(sys.argv[1]) if len(sys.argv) > 1 else 0.2
    for dt in ([float(x) for x in sys.argv[2:]] or [1e-4, 1e-5]):
        import os
        w3_0 = float(os.environ.get("W3", "0"))
        rows, imp, E0 = run(dt, T, u0=(150.0, -75.0, w3_0))
        t, th1, th2, th3, w1, w2, w3, E = rows.T
        print(f"dt={dt}: at t={t[-1]:.4f}: revolutions {th1[-1]/(2*math.pi):.5f}, omega1 {w1[-1]:.4f}, energy {E[-1]:.6f} J (E0 {E0:.6f})")
        for tt in (0.05, 0.1, 0.15, 0.2):
            i = int(round(tt / dt)) - 1
            if i < len(t):
                print(f"   t={t[i]:.3f}: rev {th1[i]/(2*math.pi):.5f} omega1 {w1[i]:.4f} theta3 {th3[i]:.5f} E {E[i]:.6f}")
        for k in range(4):
            print(f"   corner {k+1}: {len(imp[k])} impacts; first at rev {[round(x[1], 4) for x in imp[k][:6]]}")
        np.save(f"slider_crank_dt{dt:g}_w3{w3_0:g}.npy", rows)
