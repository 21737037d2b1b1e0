"""Pendulum pinned to the world hitting a joint stop (Newton restitution on the joint limit).

theta from the downward vertical, counter-clockwise positive. I_O theta'' = -m g d sin theta.
Stop: theta >= theta_s (g = theta - theta_s, W = +1), or theta <= theta_s.
"""
import math
import numpy as np
from nsmech import Contact, moreau_step

g = 9.81


def agm_K(k):
    """Complete elliptic integral of the first kind K(k) (modulus k) by the AGM."""
    a, b = 1.0, math.sqrt(1 - k * k)
    for _ in range(60):
        a, b = (a + b) / 2, math.sqrt(a * b)
    return math.pi / (2 * a)


def case(name, I_O, m, d, theta0, theta_s, eps):
    Omega2 = m * g * d / I_O  # small-oscillation omega^2
    w_minus = math.sqrt(2 * Omega2 * (math.cos(theta_s) - math.cos(theta0)))
    w_plus = eps * w_minus
    c1 = math.cos(theta_s) - eps ** 2 * (math.cos(theta_s) - math.cos(theta0))
    theta1 = math.acos(c1)
    # time from release at theta0 to the bottom (theta_s = 0): quarter period
    t_hit = agm_K(math.sin(theta0 / 2)) / math.sqrt(Omega2)
    t_return = 2 * agm_K(math.sin(theta1 / 2)) / math.sqrt(Omega2)  # out to theta1 and back
    E0 = m * g * d * (1 - math.cos(theta0))
    E1 = m * g * d * (1 - math.cos(theta1))
    print(f"{name}: I_O={I_O:.6g} Omega={math.sqrt(Omega2):.6f} rad/s  w-={w_minus:.6f} w+={w_plus:.6f} "
          f"theta1={math.degrees(theta1):.4f} deg ({theta1:.6f} rad)  t_hit={t_hit:.6f} s  "
          f"t_between={t_return:.6f} s  E loss frac={(E0 - E1) / E0:.6f}")
    return dict(w_minus=w_minus, w_plus=w_plus, theta1=theta1, t_hit=t_hit, t_return=t_return)


class Pendulum:
    def __init__(self, I_O, m, d, theta_s, eps):
        self.I_O, self.m, self.d, self.theta_s, self.eps = I_O, m, d, theta_s, eps

    def M(self, q):
        return np.array([[self.I_O]])

    def h(self, q, u, t):
        return np.array([-self.m * g * self.d * math.sin(q[0])])

    def contacts(self, q):
        # stop on the negative side: theta >= theta_s, released from theta0 > 0 swinging through
        return [Contact(q[0] - self.theta_s, [1.0], epsN=self.eps)]


def simulate(I_O, m, d, theta0, theta_s, eps, dt, T):
    mdl = Pendulum(I_O, m, d, theta_s, eps)
    q, u, t = np.array([theta0]), np.array([0.0]), 0.0
    impacts, peaks = [], []
    prev = 0.0
    while t < T:
        uA = u[0]
        t, q, u, closed, LN, LT = moreau_step(mdl, t, q, u, dt)
        if closed and LN[0] > 1e-12 and uA < 0:
            impacts.append((t, uA, u[0]))
        if prev > 0 and u[0] <= 0:
            peaks.append((t, q[0]))
        prev = u[0]
    return impacts, peaks


if __name__ == "__main__":
    L, m, eps = 1.0, 1.0, 0.5
    th0 = math.pi / 2
    rod = case("uniform rod, stop at bottom", m * L * L / 3, m, L / 2, th0, 0.0, eps)
    pm = case("point mass, stop at bottom", m * L * L, m, L, th0, 0.0, eps)
    rod2 = case("uniform rod, stop at -30 deg", m * L * L / 3, m, L / 2, th0, -math.pi / 6, eps)
    for dt in (1e-3, 1e-4):
        imp, pk = simulate(m * L * L / 3, m, L / 2, th0, 0.0, eps, dt, 1.5)
        print(f"rod dt={dt}: impacts (t, w^A, w^E) {[(round(a,5), round(b,5), round(c,5)) for a,b,c in imp[:2]]}, peaks {[(round(a,5), round(math.degrees(b),4)) for a,b in pk[:2]]}")
        imp, pk = simulate(m * L * L, m, L, th0, 0.0, eps, dt, 1.5)
        print(f"point dt={dt}: impacts {[(round(a,5), round(b,5), round(c,5)) for a,b,c in imp[:2]]}, peaks {[(round(a,5), round(math.degrees(b),4)) for a,b in pk[:2]]}")
    # n-th rebound amplitude with the stop at the bottom: 1 - cos theta_n = eps^(2n) (1 - cos theta_0)
    for n in range(1, 5):
        print(n, math.degrees(math.acos(1 - eps ** (2 * n) * (1 - math.cos(th0)))))
