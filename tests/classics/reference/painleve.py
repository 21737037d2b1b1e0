"""Painleve's rod: uniform rod, length 2l, mass m, I = m l^2/3, lower end A on a rough floor.

q = (x, y, theta): centre of mass and the rod's angle to the floor (A = C - l (cos, sin)).
g_N = y - l sin theta,  W_N = (0, 1, -l cos theta),  W_T = (1, 0, l sin theta)  (t = +x).
"""
import math
import numpy as np
from nsmech import lcp_enumerate, lemke, contact_lcp, Contact, moreau_step

g = 9.81


def mu_crit(theta):
    return (1 + 3 * math.cos(theta) ** 2) / (3 * math.sin(theta) * math.cos(theta))


class Rod:
    def __init__(self, m, l, mu, eps=0.0):
        self.m, self.l, self.mu, self.eps = m, l, mu, eps

    def M(self, q):
        return np.diag([self.m, self.m, self.m * self.l ** 2 / 3])

    def h(self, q, u, t):
        return np.array([0.0, -self.m * g, 0.0])

    def contacts(self, q):
        x, y, th = q
        l = self.l
        return [Contact(y - l * math.sin(th), [0, 1, -l * math.cos(th)], [1, 0, l * math.sin(th)],
                        mu=self.mu, epsN=self.eps)]


def one_step_lcp(m, l, theta, mu, vs, vn, dt, eps=0.0):
    """LCP of one step from a state with A on the floor, A's velocity (vs, vn)."""
    rod = Rod(m, l, mu, eps)
    # u such that A moves with (vs, vn) and theta' = 0
    u = np.array([vs, vn, 0.0])
    q = np.array([0.0, l * math.sin(theta), theta])
    qM = q + dt / 2 * u
    c = rod.contacts(qM)[0]
    Minv = np.linalg.inv(rod.M(qM))
    ut = u + Minv @ rod.h(qM, u, 0) * dt
    wN, wT = c.wN, c.wT
    G = lambda a, b: a @ Minv @ b
    A, b = contact_lcp(np.array([[G(wN, wN)]]), np.array([[G(wN, wT)]]), np.array([[G(wT, wN)]]),
                       np.array([[G(wT, wT)]]), [mu], [wN @ ut + eps * (wN @ u)], [wT @ ut])
    return A, b, c.g, (wN, wT, Minv, ut, u)


def show(label, m, l, theta, mu, vs, vn, dt):
    A, b, gM, (wN, wT, Minv, ut, u) = one_step_lcp(m, l, theta, mu, vs, vn, dt)
    print(f"--- {label}: theta={math.degrees(theta):.1f} deg mu={mu} mu_c={mu_crit(theta):.6f} "
          f"v_T={vs} v_N={vn} dt={dt} g_N(q^M)={gM:.3e}")
    np.set_printoptions(precision=9, suppress=True)
    print("A =\n", A, "\nb =", b)
    sols = lcp_enumerate(A, b)
    for S, z, w in sols:
        LN, LR = z[0], z[1]
        LT = LR - mu * LN
        uE = ut + Minv @ (wN * LN + wT * LT)
        KE0 = 0.5 * u @ np.linalg.inv(Minv) @ u
        KE1 = 0.5 * uE @ np.linalg.inv(Minv) @ uE
        print(f"  solution, basis z_{list(S)}: z = {z}, w = {w}; Lambda_N={LN:.9f} Lambda_T={LT:.9f} "
              f"u^E={uE} gamma_N^E={wN @ uE:.3e} gamma_T^E={wT @ uE:.3e} KE {KE0:.6f}->{KE1:.6f}")
    st, z, piv = lemke(A, b)
    print(f"  {len(sols)} solution(s); Lemke (e = 1, lexicographic): {st}, z = {z}, pivots {piv}")
    # copositivity probe: min of z'Az over the simplex (random + vertices/edges)
    rng = np.random.default_rng(1)
    Z = rng.dirichlet(np.ones(3), 200000)
    vals = np.einsum("ij,jk,ik->i", Z, A, Z)
    print(f"  min z'Az on the simplex (sampled) = {vals.min():.6f} at z = {Z[np.argmin(vals)]}")
    return A, b


if __name__ == "__main__":
    m, l = 1.0, 0.5
    theta = math.pi / 3
    print("mu_c(60 deg) =", mu_crit(theta), " min over theta: 4/3 at tan theta = 2, theta =",
          math.degrees(math.atan(2)), mu_crit(math.atan(2)))
    s, c = math.sin(theta), math.cos(theta)
    print("acceleration-level normal coefficient for sliding in -x: (1 + 3c^2 - 3 mu s c)/m =",
          (1 + 3 * c * c - 3 * 2 * s * c) / m)
    A, b = show("paradox, pressed by gravity (b_N < 0)", m, l, theta, 2.0, -1.0, 0.0, 1e-3)
    np.savetxt("painleve_A.txt", A)
    with open("painleve_step.dat", "w") as f:
        f.write("3\n0\n3 3\n3 3\n")
        for row in A:
            f.write(" ".join(repr(float(x)) for x in row) + "\n")
        f.write(" ".join(repr(float(x)) for x in b) + "\n")
        f.write("Painleve rod, one Moreau step: m=1 l=0.5 theta=60deg mu=2 v_T=-1 v_N=0 dt=1e-3 eps=0\n")
    show("paradox, rod rising (b_N > 0)", m, l, theta, 2.0, -1.0, 0.05, 1e-3)
    show("paradox, other sliding direction", m, l, theta, 2.0, +1.0, 0.0, 1e-3)
    show("consistent friction mu = 1 < mu_c", m, l, theta, 1.0, -1.0, 0.0, 1e-3)
    # Delta t -> 0: the percussion does not vanish (impact without collision)
    for dt in (1e-2, 1e-3, 1e-4, 1e-5):
        A, b, gM, _ = one_step_lcp(m, l, theta, 2.0, -1.0, 0.0, dt)
        sols = lcp_enumerate(A, b)
        print(f"dt={dt}: Lambda_N = {[round(s_[1][0], 9) for s_ in sols]}")
    print("closed form dt->0: Lambda_N = 3 m s c v/4 =", 3 * s * c / 4, " Lambda_T = m (1+3c^2) v/4 =",
          (1 + 3 * c * c) / 4, " KE after / before = 3 s^2/4 =", 3 * s * s / 4)
    # a short run: the sliding stops in the first step; what next
    rod = Rod(m, l, 2.0)
    q = np.array([0.0, l * math.sin(theta) - 1e-12, theta]); u = np.array([-1.0, 0.0, 0.0]); t = 0.0
    for k in range(5):
        t, q, u, closed, LN, LT = moreau_step(rod, t, q, u, 1e-3)
        gT = (u[0] + l * math.sin(q[2]) * u[2]) if True else 0
        print(f"step {k+1}: closed {len(closed)} LN={LN} LT={LT} u={u} gamma_T={gT:.3e}")
