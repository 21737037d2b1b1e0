"""Point-foot hopper with a prismatic spring leg: closed forms and a docs/physics.md-section-4 check.

q = (y_b, s): body height, leg length (foot height y_f = y_b - s).
T = 1/2 m y_b'^2 + 1/2 m_f (y_b' - s')^2;  V = m g y_b + m_f g (y_b - s) + 1/2 k (L0 - s)^2.
Joint limit s <= L0 (hard stop, restitution eps_stop), foot-ground contact y_f >= 0 (eps = 0).
"""
import math
import numpy as np
from nsmech import Contact, moreau_step

g = 9.81


def closed_form(m, k, L0, h0):
    """Lossless spring-mass hopper (massless foot). h0 = apex clearance of the foot."""
    v = math.sqrt(2 * g * h0)           # touchdown (and lift-off) speed
    w = math.sqrt(k / m)
    x0 = m * g / k                      # static compression
    A = math.sqrt(x0 ** 2 + (v / w) ** 2)  # oscillation amplitude about equilibrium
    t_stance = (math.pi + 2 * math.atan(g / (w * v))) / w
    t_flight = 2 * v / g
    return dict(v_td=v, omega=w, half_period=math.pi / w, t_stance=t_stance, t_flight=t_flight,
                period=t_stance + t_flight, max_compression=x0 + A, y_body_min=L0 - x0 - A,
                apex_body=L0 + h0, peak_force=k * (x0 + A))


def losses(m, mf, h0):
    v = math.sqrt(2 * g * h0)
    E_td = 0.5 * mf * v ** 2                      # foot stops (eps = 0)
    v_lo = m * v / (m + mf)                       # plastic stop engages at lift-off
    E_lo = 0.5 * m * v ** 2 * mf / (m + mf)
    ratio = (m / (m + mf)) ** 2                   # apex-height ratio per hop
    return dict(E_touchdown=E_td, E_liftoff=E_lo, v_after_stop=v_lo, apex_ratio=ratio,
                E_before=(m + mf) * g * h0)


class Hopper:
    def __init__(self, m, mf, k, L0, eps_stop=0.0):
        self.m, self.mf, self.k, self.L0, self.eps_stop = m, mf, k, L0, eps_stop

    def M(self, q):
        m, mf = self.m, self.mf
        return np.array([[m + mf, -mf], [-mf, mf]])

    def h(self, q, u, t):
        yb, s = q
        return np.array([-(self.m + self.mf) * g, self.mf * g + self.k * (self.L0 - s)])

    def contacts(self, q):
        yb, s = q
        return [Contact(yb - s, [1.0, -1.0], epsN=0.0, name="foot"),
                Contact(self.L0 - s, [0.0, -1.0], epsN=self.eps_stop, name="stop")]


def simulate(m, mf, k, L0, h0, dt, hops=3):
    mdl = Hopper(m, mf, k, L0)
    q = np.array([L0 + h0, L0])
    u = np.zeros(2)
    t = 0.0
    on = False
    events = []   # (kind, time)
    apex = []
    prev_vy = 0.0
    Es = []
    while len([e for e in events if e[0] == "takeoff"]) < hops and t < 10:
        t, q, u, closed, LN, LT = moreau_step(mdl, t, q, u, dt)
        foot_closed = any(c.name == "foot" and l > 0 for c, l in zip(closed, LN)) or (q[0] - q[1] <= 0)
        if foot_closed and not on:
            events.append(("touchdown", t)); on = True
        if on and q[0] - q[1] > 0 and u[0] - u[1] > 0:
            events.append(("takeoff", t)); on = False
        if prev_vy > 0 and u[0] <= 0 and not on:
            apex.append((t, q[0]))
        prev_vy = u[0]
    return events, apex


if __name__ == "__main__":
    m, k, L0, h0 = 1.0, 1000.0, 0.5, 0.1
    cf = closed_form(m, k, L0, h0)
    for key, val in cf.items():
        print(f"{key:16s} {val:.6f}")
    for mf in (0.01, 0.05):
        print("m_f =", mf, {k_: round(v, 6) for k_, v in losses(m, mf, h0).items()})
    for mf in (1e-4, 0.01):
        for dt in (1e-4, 1e-5):
            ev, ap = simulate(m, mf, k, L0, h0, dt)
            td = [t for e, t in ev if e == "touchdown"]
            to = [t for e, t in ev if e == "takeoff"]
            st = [b - a for a, b in zip(td, to)]
            fl = [td[i + 1] - to[i] for i in range(len(to) - 1) if i + 1 < len(td)]
            print(f"sim m_f={mf} dt={dt}: stance {np.round(st, 5)} flight {np.round(fl, 5)} apex body y {[round(a[1], 6) for a in ap]}")
