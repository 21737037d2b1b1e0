"""Sliding phase of Glocker's example as an ODE (contact maintained, slip towards -x):
lambda_N = m (g - s sin(th) th'^2) / (1 + 3 cos^2 th - 3 mu sin th cos th),
th'' = 3 lambda_N (mu sin th - cos th) / (m s),  x'' = mu lambda_N / m.
RK4 with a small fixed step until th = 45 deg (the coefficient's zero for mu = 5/3)."""
import math
m, s, g, mu = 1.0, 1.0, 10.0, 5 / 3


def f(st):
    x, xd, th, thd = st
    den = 1 + 3 * math.cos(th) ** 2 - 3 * mu * math.sin(th) * math.cos(th)
    lam = m * (g - s * math.sin(th) * thd ** 2) / den
    return (xd, mu * lam / m, thd, 3 * lam * (mu * math.sin(th) - math.cos(th)) / (m * s)), lam


def rk4(st, h):
    k1, _ = f(st)
    k2, _ = f([a + h / 2 * b for a, b in zip(st, k1)])
    k3, _ = f([a + h / 2 * b for a, b in zip(st, k2)])
    k4, _ = f([a + h * b for a, b in zip(st, k3)])
    return [a + h / 6 * (b + 2 * c + 2 * d + e) for a, b, c, d, e in zip(st, k1, k2, k3, k4)]


for h in (1e-5, 2e-6):
    st = [0.0, -30.0, math.radians(31), 0.0]
    t = 0.0
    imp = 0.0
    marks = [40, 44, 44.9, 44.99]
    while st[2] < math.radians(44.999):
        _, lam = f(st)
        new = rk4(st, h)
        imp += lam * h
        t += h
        if marks and new[2] >= math.radians(marks[0]):
            slip = new[1] + s * math.sin(new[2]) * new[3]
            print(f"h={h}: theta={marks[0]} deg at t={t:.6f}, slip={slip:.5f} m/s, th'={new[3]:.5f}, lambda_N={f(new)[1]:.3f} N")
            marks.pop(0)
        st = new
        if t > 3:
            break
    slip = st[1] + s * math.sin(st[2]) * st[3]
    print(f"h={h}: theta=44.999 deg at t={t:.6f} s, slip {slip:.5f} m/s, th'={st[3]:.5f} rad/s, "
          f"normal impulse so far {imp:.5f} N s, lambda_N now {f(st)[1]:.1f} N")

print("--- reference samples (h = 1e-6)")
st = [0.0, -30.0, math.radians(31), 0.0]; t = 0.0; h = 1e-6
targets = [0.2, 0.4, 0.6, 0.7, 0.8]
while targets:
    st = rk4(st, h); t += h
    if t >= targets[0] - 1e-12:
        slip = st[1] + s * math.sin(st[2]) * st[3]
        print(f"t={t:.3f}: x={st[0]:.6f} m (CoM; contact-end slip {slip:.6f} m/s), theta={math.degrees(st[2]):.5f} deg, "
              f"th'={st[3]:.6f} rad/s, lambda_N={f(st)[1]:.5f} N")
        targets.pop(0)
