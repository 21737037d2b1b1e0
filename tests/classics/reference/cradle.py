"""Newton's cradle: Moreau's simultaneous impact law vs sequential binary collisions.

n equal balls (mass m, radius R) in a row along x, touching; ball 1 arrives with speed v.
Contacts i = 1..n-1 between balls i and i+1: g_i = x_{i+1} - x_i - 2R,
W_N column i = e_{i+1} - e_i, G = W^T M^-1 W = tridiag(-1, 2, -1) / m.
"""
from fractions import Fraction as F
import numpy as np
from nsmech import lcp_enumerate, lemke, Contact, moreau_step


def simultaneous_exact(n, eps):
    """All contacts active: G P = -(1+eps) gamma^- with gamma^- = (-v, 0, ..., 0), v = 1.
    Exact rational arithmetic; returns post velocities (units of v) and percussions/m."""
    k = n - 1
    G = [[F(0)] * k for _ in range(k)]
    for i in range(k):
        G[i][i] = F(2)
        if i > 0:
            G[i][i - 1] = F(-1)
        if i < k - 1:
            G[i][i + 1] = F(-1)
    rhs = [F(0)] * k
    rhs[0] = (1 + eps)  # -(1+eps)*gamma1^- with gamma1^- = -1
    # Gaussian elimination (exact)
    Gm = [row[:] + [rhs[i]] for i, row in enumerate(G)]
    for c in range(k):
        p = Gm[c][c]
        Gm[c] = [x / p for x in Gm[c]]
        for r in range(k):
            if r != c and Gm[r][c] != 0:
                f = Gm[r][c]
                Gm[r] = [a - f * b for a, b in zip(Gm[r], Gm[c])]
    P = [Gm[i][-1] for i in range(k)]
    u = [F(1)] + [F(0)] * (n - 1)
    for i in range(k):  # contact i pushes ball i back, ball i+1 forward
        u[i] -= P[i]
        u[i + 1] += P[i]
    return u, P


def lcp_check(n, eps):
    """Numerical LCP of the impact (velocity level, no gravity): w = G P + (1+eps) gamma^-,
    all solutions by enumeration, and Lemke's."""
    k = n - 1
    G = 2 * np.eye(k) - np.eye(k, k, 1) - np.eye(k, k, -1)
    gm = np.zeros(k)
    gm[0] = -1.0
    b = (1 + eps) * gm  # xi = gamma^+ + eps gamma^- = gamma^- + G P + eps gamma^-
    sols = lcp_enumerate(G, b)
    st, z, piv = lemke(G, b)
    return sols, (st, z, piv)


def sequential(n, eps, gaps=None, max_events=200000):
    """Event-driven binary collisions (Newton law, equal masses) with initial gaps between
    resting balls (default: equal tiny gaps). Returns final velocities and collision count."""
    x = np.zeros(n)
    gaps = np.full(n - 1, 1e-6) if gaps is None else np.asarray(gaps, float)
    x[1:] = np.cumsum(gaps)  # 2R omitted: only gaps matter
    x[0] = -1e-6  # ball 1 a little way off ball 2... (gap 1-2 = gaps[0] + 1e-6)
    u = np.zeros(n)
    u[0] = 1.0
    count = 0
    t = 0.0
    while count < max_events:
        g = np.diff(x)
        rel = np.diff(u)  # rate of change of gap
        # touching and approaching pairs collide now; otherwise next gap closure
        times = np.where(rel < -1e-15, np.maximum(g, 0) / np.maximum(-rel, 1e-300), np.inf)
        i = int(np.argmin(times))
        if not np.isfinite(times[i]):
            break
        dt = times[i]
        x += u * dt
        t += dt
        x[i + 1] = x[i] + max(x[i + 1] - x[i], 0.0)
        # binary collision between i and i+1 (equal masses)
        ui, uj = u[i], u[i + 1]
        vc = 0.5 * (ui + uj)
        u[i] = vc - eps * 0.5 * (ui - uj)
        u[i + 1] = vc + eps * 0.5 * (ui - uj)
        count += 1
        if count > 10 and np.all(np.diff(u) >= -1e-13):
            break
    return u, count


class Cradle:
    def __init__(self, n, eps, R=0.05, m=0.1):
        self.n, self.eps, self.R, self.m = n, eps, R, m

    def M(self, q):
        return self.m * np.eye(self.n)

    def h(self, q, u, t):
        return np.zeros(self.n)

    def contacts(self, q):
        cs = []
        for i in range(self.n - 1):
            w = np.zeros(self.n)
            w[i], w[i + 1] = -1.0, 1.0
            cs.append(Contact(q[i + 1] - q[i] - 2 * self.R, w, epsN=self.eps))
        return cs


def stepper_run(n, eps, gap, dt=1e-3, v=1.0, T=0.2, first_gap=0.0123):
    """Balls 2..n spaced by 2R + gap; ball 1 starts first_gap away with speed v."""
    mdl = Cradle(n, eps)
    R = mdl.R
    q = np.array([0.0] + [first_gap + 2 * R + i * (2 * R + gap) for i in range(n - 1)])
    u = np.zeros(n)
    u[0] = v
    t = 0.0
    impact_steps = []
    while t < T - 1e-12:
        t, q, u, closed, LN, LT = moreau_step(mdl, t, q, u, dt)
        if any(l > 0 for l in LN):
            impact_steps.append((round(t / dt), len(closed)))
    return u, impact_steps


def fmt(u):
    return "(" + ", ".join(str(x) for x in u) + ")"


if __name__ == "__main__":
    print("== Moreau simultaneous impact, exact (v = 1, m = 1) ==")
    for n in (3, 5):
        for eps in (F(1), F(9, 10), F(1, 2), F(0)):
            u, P = simultaneous_exact(n, eps)
            p = sum(u)
            ke = sum(x * x for x in u)  # (2 T / m v^2)
            print(f"n={n} eps={eps}: u+ = {fmt(u)}  P/(m v) = {fmt(P)}  momentum = {p}  KE+/KE- = {ke} = {float(ke):.6f}")
            sols, lem = lcp_check(n, float(eps))
            print(f"      LCP enumeration: {len(sols)} solution(s), active sets {[s[0] for s in sols]}, "
                  f"z = {np.round(sols[0][1], 12)}; Lemke: {lem[0]}, z = {np.round(lem[1], 12)}, pivots {lem[2]}")
    print()
    print("== sequential binary collisions (equal tiny gaps) ==")
    for n in (3, 5):
        for eps in (1.0, 0.9, 0.5, 0.0):
            u, c = sequential(n, eps)
            print(f"n={n} eps={eps}: u_final = {np.round(u, 6)}  collisions = {c}  momentum = {u.sum():.6f}  KE ratio = {np.sum(u*u):.6f}")
    print()
    print("== midpoint time-stepper (docs/physics.md section 4), dt = 1e-3, v = 1 ==")
    for n in (3, 5):
        for eps in (1.0, 0.9, 0.5, 0.0):
            for gap in (0.0, 1e-4, 2e-3):
                u, imp = stepper_run(n, eps, gap)
                print(f"n={n} eps={eps} gap={gap:g}: u_end = {np.round(u, 9)}  impact steps (step, #closed) = {imp[:8]}{'...' if len(imp) > 8 else ''}")
