"""Small, independent re-implementation of the docs/physics.md section 4 step (Moreau midpoint,
one frictional LCP per step), used to compute reference numbers for docs/classics.md.

Not hopsim code: written from docs/physics.md alone (numpy only).
"""
import itertools
import numpy as np


# ----------------------------------------------------------------------------- LCP
def lcp_enumerate(A, b, tol=1e-10):
    """All solutions of w = A z + b, z, w >= 0, z'w = 0, by enumerating the 2^n
    complementary index sets (a set S: z_S free, w_S = 0; z_rest = 0).
    Returns a list of (S, z, w); duplicates (degenerate) are merged."""
    A = np.asarray(A, float)
    b = np.asarray(b, float)
    n = len(b)
    sols = []
    scale = max(1.0, np.abs(b).max(), np.abs(A).max())
    for k in range(n + 1):
        for S in itertools.combinations(range(n), k):
            S = list(S)
            z = np.zeros(n)
            if S:
                ASS = A[np.ix_(S, S)]
                if abs(np.linalg.det(ASS)) < 1e-14 * scale ** len(S):
                    continue
                z[S] = np.linalg.solve(ASS, -b[S])
            w = A @ z + b
            if z.min() >= -tol * scale and w.min() >= -tol * scale:
                if not any(np.allclose(z, s[1], atol=1e-9 * scale) for s in sols):
                    sols.append((tuple(S), z, w))
    return sols


def lemke(A, b, maxpiv=None, tol=1e-12):
    """Lemke's method with covering vector e = 1 and lexicographic ratio test
    (Murty ch. 2). Returns (status, z, pivots); status 'solved' or 'ray'."""
    A = np.asarray(A, float)
    b = np.asarray(b, float)
    n = len(b)
    if b.min() >= 0:
        return "solved", np.zeros(n), 0
    maxpiv = maxpiv or 50 * n + 100
    # tableau columns: w (0..n-1), z (n..2n-1), z0 (2n), rhs (2n+1)
    T = np.zeros((n, 2 * n + 2))
    T[:, :n] = np.eye(n)
    T[:, n:2 * n] = -A
    T[:, 2 * n] = -1.0
    T[:, -1] = b
    basis = list(range(n))

    def pivot(r, c):
        T[r] /= T[r, c]
        for i in range(n):
            if i != r and T[i, c] != 0.0:
                T[i] -= T[i, c] * T[r]
        leaving = basis[r]
        basis[r] = c
        return leaving

    r = int(np.argmin(b))
    leaving = pivot(r, 2 * n)
    piv = 1
    while piv < maxpiv:
        entering = leaving + n if leaving < n else leaving - n
        col = T[:, entering]
        cand = [i for i in range(n) if col[i] > tol * max(1.0, np.abs(col).max())]
        if not cand:
            return "ray", None, piv
        # lexicographic minimum of [rhs, B^-1] / col
        def key(i):
            return tuple([T[i, -1] / col[i]] + list(T[i, :n] / col[i]))
        # z0 leaves on a tie in the first component
        ratios = [T[i, -1] / col[i] for i in cand]
        m = min(ratios)
        z0rows = [i for i in cand if basis[i] == 2 * n and T[i, -1] / col[i] <= m + 1e-12 * max(1, abs(m))]
        if z0rows:
            r = z0rows[0]
        else:
            r = min(cand, key=key)
        leaving = pivot(r, entering)
        piv += 1
        if leaving == 2 * n:
            z = np.zeros(n)
            for i, v in enumerate(basis):
                if n <= v < 2 * n:
                    z[v - n] = T[i, -1]
            return "solved", z, piv
    return "pivot_limit", None, piv


# ------------------------------------------------------------------- contact LCP of section 4
def contact_lcp(G_NN, G_NT, G_TN, G_TT, mu, bN, bT):
    """A, b of docs/physics.md section 4 for k contacts, all with friction rows."""
    k = len(bN)
    Mu = np.diag(mu)
    I = np.eye(k)
    Z = np.zeros((k, k))
    A = np.block([
        [G_NN - G_NT @ Mu, G_NT, Z],
        [G_TN - G_TT @ Mu, G_TT, I],
        [2 * Mu, -I, Z],
    ])
    b = np.concatenate([bN, bT, np.zeros(k)])
    return A, b


class Contact:
    """One closed-or-open unilateral constraint evaluated at q^M."""

    def __init__(self, g, wN, wT=None, mu=0.0, epsN=0.0, epsT=0.0, name=""):
        self.g, self.wN, self.wT = g, np.asarray(wN, float), None if wT is None else np.asarray(wT, float)
        self.mu, self.epsN, self.epsT, self.name = mu, epsN, epsT, name


def solve_impact(Minv, u_tilde, uA, contacts, method="lemke"):
    """Solve the section-4 LCP for the given closed contacts.
    Returns (u^E, Lambda_N, Lambda_T, info). Contacts without wT or with mu == 0 get
    normal rows only."""
    fr = [c for c in contacts if c.wT is not None and c.mu > 0]
    nf = [c for c in contacts if not (c.wT is not None and c.mu > 0)]
    order = fr + nf
    k, kf = len(order), len(fr)
    WN = np.column_stack([c.wN for c in order])
    WT = np.column_stack([c.wT for c in fr]) if kf else np.zeros((len(uA), 0))
    G_NN = WN.T @ Minv @ WN
    G_NT = WN.T @ Minv @ WT
    G_TT = WT.T @ Minv @ WT
    bN = WN.T @ u_tilde + np.array([c.epsN for c in order]) * (WN.T @ uA)
    bT = WT.T @ u_tilde + np.array([c.epsT for c in fr]) * (WT.T @ uA) if kf else np.zeros(0)
    mu = np.array([c.mu for c in fr])
    # z = (Lambda_N (k), Lambda_R (kf), xi_L (kf))
    Mu = np.zeros((kf, k))
    Mu[np.arange(kf), np.arange(kf)] = mu
    A = np.block([
        [G_NN - G_NT @ Mu, G_NT, np.zeros((k, kf))],
        [G_NT.T - G_TT @ Mu, G_TT, np.eye(kf)],
        [2 * Mu, -np.eye(kf), np.zeros((kf, kf))],
    ])
    b = np.concatenate([bN, bT, np.zeros(kf)])
    if method == "lemke":
        status, z, piv = lemke(A, b)
        if status != "solved":
            sols = lcp_enumerate(A, b)
            if not sols:
                raise RuntimeError("LCP has no solution")
            z = sols[0][1]
            status = "enumeration"
    else:
        sols = lcp_enumerate(A, b)
        z = sols[0][1]
        status = "enumeration"
    LN = z[:k]
    LR = z[k:k + kf]
    LT = LR - mu * LN[:kf]
    uE = u_tilde + Minv @ (WN @ LN + WT @ LT)
    # map back to the caller's order
    LN_out = {id(c): LN[i] for i, c in enumerate(order)}
    LT_out = {id(c): (LT[i] if i < kf else 0.0) for i, c in enumerate(order)}
    return uE, [LN_out[id(c)] for c in contacts], [LT_out[id(c)] for c in contacts], status


def moreau_step(model, t, q, u, dt):
    """One docs/physics.md section-4 step. model provides M(q), h(q,u,t), contacts(q) -> list of
    Contact (all candidates; the ones with g <= 0 are used)."""
    tM = t + dt / 2
    qM = q + dt / 2 * u
    M = model.M(qM)
    Minv = np.linalg.inv(M)
    h = model.h(qM, u, tM)
    u_tilde = u + Minv @ h * dt
    closed = [c for c in model.contacts(qM) if c.g <= 0]
    if closed:
        uE, LN, LT, status = solve_impact(Minv, u_tilde, u, closed)
    else:
        uE, LN, LT, status = u_tilde, [], [], "free"
    qE = qM + dt / 2 * uE
    return t + dt, qE, uE, closed, LN, LT
