"""Shared finite-element machinery for the LEFM references (scikit-fem).

Used by ``fem_sent.py`` (SENT, problems A and B), ``fem_inclined.py`` (inclined
centre crack, problem C) and ``verify_lefm.py`` (exact-solution checks).

Contents
--------
* Constitutive helpers: plane stress / plane strain Lame constants, E', kappa.
* Mesher (scikit-fem has no crack mesher):
    1. a structured base triangulation of a rectangle whose grid lines are
       chosen so that every crack segment is a chain of element edges
       (``structured_tri``);
    2. repeated conforming red-green-blue refinement (``MeshTri1.refined`` with
       marked elements, longest-edge rule) until every element satisfies a
       size field h(x) = min(h_max, alpha * distance to the nearest singular
       point), i.e. geometric grading toward crack tips and grip corners
       (``refine_to_size``);
    3. the crack is opened by duplicating every node that lies on a crack
       segment (crack tips excepted): elements on the "-" side of the crack
       get the copy, so the two crack faces are coincident but unconnected
       node rows (``split_crack``).
* P2 solve (``ElementVector(ElementTriP2())``) with both grips clamped:
  bottom u = 0, top u = (dx, dy) on every P2 node of the edge; ``condense`` +
  ``solve``; reaction forces from the residual K u on the top-edge DOFs.
* Domain (equivalent-domain) J-integral and interaction integral with the
  Williams auxiliary fields, evaluated at the quadrature points of the P2 mesh
  with a plateau weight function q (P2 interpolant of a smooth radial step).
* Williams near-tip fields, displacement-correlation K estimate, MTS kink
  angle.

Sign conventions: at every crack tip the local frame is e1 = unit vector in
the direction of crack extension (from the crack into the ligament) and
e2 = e1 rotated by +90 degrees.  theta is measured from e1, counter-clockwise
positive, theta = +-pi are the two crack faces (Williams convention):
K_II > 0 when [u.e1](+e2 face) - [u.e1](-e2 face) > 0
behind the tip, K_I > 0 when the faces open.
"""
import numpy as np

from skfem import (Basis, BilinearForm, ElementTriP2, ElementVector,
                   asm, condense, solve)
from skfem.helpers import ddot, div, sym_grad


# --------------------------------------------------------------------------
# material
# --------------------------------------------------------------------------
def lame(E, nu, plane):
    """(lambda_eff, mu) of the 2D law sigma = lambda tr(eps) I + 2 mu eps."""
    mu = E / (2.0 * (1.0 + nu))
    if plane == "stress":
        lam = E * nu / (1.0 - nu ** 2)
    elif plane == "strain":
        lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    else:
        raise ValueError(plane)
    return lam, mu


def e_prime(E, nu, plane):
    return E if plane == "stress" else E / (1.0 - nu ** 2)


def kappa(nu, plane):
    return (3.0 - nu) / (1.0 + nu) if plane == "stress" else 3.0 - 4.0 * nu


# --------------------------------------------------------------------------
# mesh
# --------------------------------------------------------------------------
def structured_tri(xs, ys, diag):
    """Triangulate the tensor grid xs x ys.

    diag(xc, yc) -> bool array: True = split the cell along the "/" diagonal
    (lower-left to upper-right), False = along the "\\" diagonal.
    """
    xs = np.asarray(xs, float)
    ys = np.asarray(ys, float)
    nx, ny = len(xs), len(ys)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    p = np.vstack([X.ravel(), Y.ravel()])
    idx = lambda i, j: i * ny + j
    I, J = np.meshgrid(np.arange(nx - 1), np.arange(ny - 1), indexing="ij")
    I, J = I.ravel(), J.ravel()
    v00, v10, v11, v01 = idx(I, J), idx(I + 1, J), idx(I + 1, J + 1), idx(I, J + 1)
    xc = 0.5 * (xs[I] + xs[I + 1])
    yc = 0.5 * (ys[J] + ys[J + 1])
    slash = np.asarray(diag(xc, yc), bool)
    t1 = np.where(slash, [v00, v10, v11], [v00, v10, v01])
    t2 = np.where(slash, [v00, v11, v01], [v10, v11, v01])
    return p, np.hstack([t1, t2])


def uniform_lines(x0, x1, hmax, nmin=1):
    """Uniform grid lines from x0 to x1 with spacing <= hmax (at least nmin cells)."""
    n = max(nmin, int(np.ceil((x1 - x0) / hmax - 1e-9)))
    return np.linspace(x0, x1, n + 1)


def graded_lines(x0, x1, h_start, h_max, growth=1.3):
    """Grid lines from x0 to x1: spacing h_start at x0, growing geometrically
    by at most `growth` per cell up to h_max (spacings rescaled to fit)."""
    Lx = abs(x1 - x0)
    hs = []
    h = h_start
    while sum(hs) < Lx:
        hs.append(min(h, h_max))
        h *= growth
    hs = np.array(hs)
    if len(hs) > 1 and sum(hs[:-1]) > 0 and (Lx - sum(hs[:-1])) < 0.5 * hs[-1]:
        hs = hs[:-1]
    hs *= Lx / hs.sum()
    xs = x0 + np.sign(x1 - x0) * np.concatenate([[0.0], np.cumsum(hs)])
    xs[-1] = x1
    return xs


def refine_to_size(mesh, size_fn, max_iter=80):
    """Conforming RGB refinement until longest edge <= size_fn at the element."""
    for _ in range(max_iter):
        p, t = mesh.p, mesh.t
        e01 = np.linalg.norm(p[:, t[0]] - p[:, t[1]], axis=0)
        e12 = np.linalg.norm(p[:, t[1]] - p[:, t[2]], axis=0)
        e02 = np.linalg.norm(p[:, t[0]] - p[:, t[2]], axis=0)
        h = np.maximum(np.maximum(e01, e12), e02)
        sv = size_fn(p)
        target = np.minimum(sv[t].min(axis=0), size_fn(p[:, t].mean(axis=1)))
        marked = np.nonzero(h > target * (1.0 + 1e-9))[0]
        if len(marked) == 0:
            return mesh
        mesh = mesh.refined(marked)
    raise RuntimeError("refinement did not terminate")


def point_size_field(points, alpha, floor, hmax):
    """h(x) = min(hmax, min_k alpha_k * max(|x - P_k|, floor_k))."""
    points = [np.asarray(P, float) for P in points]
    alpha = np.broadcast_to(np.asarray(alpha, float), (len(points),))
    floor = np.broadcast_to(np.asarray(floor, float), (len(points),))

    def f(x):
        h = np.full(x.shape[1], float(hmax))
        for P, a, fl in zip(points, alpha, floor):
            d = np.hypot(x[0] - P[0], x[1] - P[1])
            h = np.minimum(h, a * np.maximum(d, fl))
        return h
    return f


def split_crack(p, t, segments, tips, tol=1e-10):
    """Open cracks: duplicate nodes on the crack segments (tips excepted).

    segments: list of (A, B) end points; every crack segment must be a chain
    of mesh edges.  For each segment the elements on the right-hand side of
    A->B (negative cross product) get the duplicated node.  Returns
    (p_new, t_new, faces) where faces is a list per segment of
    (plus_nodes, minus_nodes) arrays, ordered by distance from A.
    """
    p = p.copy()
    t = t.copy()
    tips = [np.asarray(T, float) for T in tips]
    faces = []
    for A, B in segments:
        A = np.asarray(A, float)
        B = np.asarray(B, float)
        Lseg = np.linalg.norm(B - A)
        d = (B - A) / Lseg
        rel = p - A[:, None]
        s = d[0] * rel[0] + d[1] * rel[1]
        n = d[0] * rel[1] - d[1] * rel[0]
        on = (np.abs(n) < tol * Lseg) & (s > -tol * Lseg) & (s < Lseg * (1 + tol))
        for T in tips:
            on &= np.hypot(p[0] - T[0], p[1] - T[1]) > tol * Lseg
        nodes = np.nonzero(on)[0]
        nodes = nodes[np.argsort(s[nodes])]
        newid = np.full(p.shape[1], -1)
        newid[nodes] = p.shape[1] + np.arange(len(nodes))
        p = np.hstack([p, p[:, nodes]])
        cen = p[:, t].mean(axis=1)
        side = d[0] * (cen[1] - A[1]) - d[1] * (cen[0] - A[0])
        touches = (newid[t] >= 0)
        minus = side < 0
        if np.any(np.abs(side[touches.any(axis=0)]) < 1e-3 * tol * Lseg):
            raise RuntimeError("element centroid on crack line")
        for k in range(3):
            sel = touches[k] & minus
            t[k, sel] = newid[t[k, sel]]
        faces.append((nodes, newid[nodes]))
    return p, t, faces


def mesh_quality(mesh):
    """Minimum interior angle [deg], and (h_min, h_max) of longest edges."""
    p, t = mesh.p, mesh.t
    ang = []
    for i in range(3):
        a = p[:, t[(i + 1) % 3]] - p[:, t[i]]
        b = p[:, t[(i + 2) % 3]] - p[:, t[i]]
        c = np.sum(a * b, axis=0) / (np.linalg.norm(a, axis=0) * np.linalg.norm(b, axis=0))
        ang.append(np.degrees(np.arccos(np.clip(c, -1, 1))))
    h = np.max([np.linalg.norm(p[:, t[i]] - p[:, t[(i + 1) % 3]], axis=0) for i in range(3)], axis=0)
    return float(np.min(ang)), float(h.min()), float(h.max())


# --------------------------------------------------------------------------
# P2 elasticity
# --------------------------------------------------------------------------
@BilinearForm
def _a_div(u, v, w):
    return div(u) * div(v)


@BilinearForm
def _a_sym(u, v, w):
    return ddot(sym_grad(u), sym_grad(v))


class Model:
    """P2 vector basis with separately assembled div-div and eps:eps matrices.

    K = lambda * K_div + 2 mu * K_sym for any (plane) material on the mesh.
    """

    def __init__(self, mesh):
        self.mesh = mesh
        self.elem = ElementVector(ElementTriP2())
        self.basis = Basis(mesh, self.elem, intorder=2)   # exact for P2 on straight cells
        self.K_div = asm(_a_div, self.basis)
        self.K_sym = asm(_a_sym, self.basis)

    @property
    def ndofs(self):
        return int(self.basis.N)

    def K(self, lam, mu):
        return (lam * self.K_div + 2.0 * mu * self.K_sym).tocsr()

    def edge_dofs(self, pred):
        """(x-dofs, y-dofs) of all P2 nodes on boundary facets with pred(midpoint)."""
        m = self.mesh
        f = m.boundary_facets()
        mid = m.p[:, m.facets[:, f]].mean(axis=1)
        f = f[pred(mid)]
        dofs = self.basis.get_dofs(facets=f)
        return dofs.all("u^1"), dofs.all("u^2")

    def solve_dirichlet(self, K, fixed, values):
        """Solve K u = 0 with u[fixed] = values (no loads); returns u."""
        x = np.zeros(K.shape[0])
        x[fixed] = values
        # SuperLU with the default COLAMD ordering (skfem's default solver);
        # MMD orderings were 10-30x slower on these graded meshes.
        return solve(*condense(K, x=x, D=fixed))


def solve_grips(model, E, nu, plane, W, L, dx, dy, K=None):
    """Clamped grips: u = 0 on y = -L/2 and u = (dx, dy) on y = +L/2.

    Returns dict with u, reaction forces on the top grip (Px, Py) from the
    residual K u, and the strain energy.
    """
    lam, mu = lame(E, nu, plane)
    if K is None:
        K = model.K(lam, mu)
    tol = 1e-9 * L
    bx, by = model.edge_dofs(lambda x: np.abs(x[1] + L / 2) < tol)
    tx, ty = model.edge_dofs(lambda x: np.abs(x[1] - L / 2) < tol)
    fixed = np.concatenate([bx, by, tx, ty])
    vals = np.concatenate([0 * bx, 0 * by, dx + 0 * tx, dy + 0 * ty])
    u = model.solve_dirichlet(K, fixed, vals)
    r = K @ u
    return dict(u=u, Px=float(r[tx].sum()), Py=float(r[ty].sum()),
                energy=float(0.5 * u @ r), lam=lam, mu=mu, K=K)


# --------------------------------------------------------------------------
# Williams near-tip fields (local crack frame)
# --------------------------------------------------------------------------
def _williams_f(th, mode, kap):
    """Angular functions: u_i = K/(2 mu) sqrt(r/(2 pi)) f_i(theta)."""
    c, s = np.cos(th / 2), np.sin(th / 2)
    if mode == 1:
        return c * (kap - 1 + 2 * s ** 2), s * (kap + 1 - 2 * c ** 2)
    return s * (kap + 1 + 2 * c ** 2), -c * (kap - 1 - 2 * s ** 2)


def williams_disp_grad(x1, x2, mode, mu, kap, K=1.0):
    """Local displacement (u1, u2) and gradient G[i][j] = du_i/dx_j."""
    r = np.hypot(x1, x2)
    th = np.arctan2(x2, x1)
    h = 1e-30
    f = _williams_f(th, mode, kap)
    fp = [fi.imag / h for fi in _williams_f(th + 1j * h, mode, kap)]   # complex step
    A = K / (2 * mu * np.sqrt(2 * np.pi))
    ct, st = np.cos(th), np.sin(th)
    u = [A * np.sqrt(r) * fi for fi in f]
    G = []
    for fi, fpi in zip(f, fp):
        dur = A * fi / (2 * np.sqrt(r))
        dut = A * np.sqrt(r) * fpi
        G.append([ct * dur - st / r * dut, st * dur + ct / r * dut])
    return u, G


def williams_stress(x1, x2, mode, K=1.0):
    """Closed-form Williams stresses (s11, s22, s12) in the local frame."""
    r = np.hypot(x1, x2)
    th = np.arctan2(x2, x1)
    c, s = np.cos(th / 2), np.sin(th / 2)
    c3, s3 = np.cos(1.5 * th), np.sin(1.5 * th)
    A = K / np.sqrt(2 * np.pi * r)
    if mode == 1:
        return A * c * (1 - s * s3), A * c * (1 + s * s3), A * s * c * c3
    return -A * s * (2 + c * c3), A * s * c * c3, A * c * (1 - s * s3)


def williams_global_disp(xg, tip, e1, KI, KII, mu, kap):
    """Williams displacement (global components) at global points xg (2, n)."""
    e1 = np.asarray(e1, float) / np.linalg.norm(e1)
    e2 = np.array([-e1[1], e1[0]])
    d = xg - np.asarray(tip, float)[:, None]
    x1 = e1 @ d
    x2 = e2 @ d
    u1 = np.zeros_like(x1)
    u2 = np.zeros_like(x1)
    for mode, K in ((1, KI), (2, KII)):
        (a, b), _ = williams_disp_grad(x1, x2, mode, mu, kap, K)
        u1 += a
        u2 += b
    return e1[0] * u1 + e2[0] * u2, e1[1] * u1 + e2[1] * u2


# --------------------------------------------------------------------------
# J-integral and interaction integral
# --------------------------------------------------------------------------
def smooth_step_q(r, r1, r2):
    """q = 1 for r <= r1, 0 for r >= r2, C2 quintic in between."""
    s = np.clip((r - r1) / (r2 - r1), 0.0, 1.0)
    return 1.0 - s ** 3 * (10 - 15 * s + 6 * s ** 2)


def tip_integrals(model, u, tip, e1, lam, mu, plane, nu, E, r1, r2, intorder=6):
    """Domain J and interaction integrals at one tip.

    q = P2 interpolant of smooth_step_q(|x - tip|, r1, r2).  Returns dict with
    J (domain J-integral), KI, KII (interaction integral), J_from_K.
    """
    mesh = model.mesh
    tip = np.asarray(tip, float)
    e1 = np.asarray(e1, float) / np.linalg.norm(e1)
    e2 = np.array([-e1[1], e1[0]])
    # elements that can carry grad q: any vertex closer than r2 + h_e
    p, t = mesh.p, mesh.t
    dv = np.hypot(p[0] - tip[0], p[1] - tip[1])[t]
    h = np.max([np.linalg.norm(p[:, t[i]] - p[:, t[(i + 1) % 3]], axis=0) for i in range(3)], axis=0)
    elems = np.nonzero((dv.min(axis=0) < r2 + h) & (dv.max(axis=0) > r1 - h))[0]
    vb = Basis(mesh, model.elem, intorder=intorder, elements=elems)
    sb = vb.with_element(ElementTriP2())
    qdofs = smooth_step_q(np.hypot(sb.doflocs[0] - tip[0], sb.doflocs[1] - tip[1]), r1, r2)
    gq = sb.interpolate(qdofs).grad                       # (2, ne, nq)
    gu = vb.interpolate(u).grad                            # (2, 2, ne, nq) du_i/dx_j
    X = vb.global_coordinates().value                     # (2, ne, nq)
    dx = vb.dx                                            # (ne, nq)
    eps = 0.5 * (gu + np.swapaxes(gu, 0, 1))
    tr = eps[0, 0] + eps[1, 1]
    sig = 2 * mu * eps
    sig[0, 0] += lam * tr
    sig[1, 1] += lam * tr
    wdens = 0.5 * np.einsum("ijen,ijen->en", sig, eps)
    sgq = np.einsum("ijen,jen->ien", sig, gq)             # sigma . grad q
    du1 = gu[:, 0] * e1[0] + gu[:, 1] * e1[1]             # du_i/dx1 (global comps)
    e1gq = e1[0] * gq[0] + e1[1] * gq[1]
    J = float(np.sum(dx * (np.einsum("ien,ien->en", sgq, du1) - wdens * e1gq)))

    # auxiliary fields
    d0, d1 = X[0] - tip[0], X[1] - tip[1]
    x1 = e1[0] * d0 + e1[1] * d1
    x2 = e2[0] * d0 + e2[1] * d1
    R = np.array([[e1[0], e2[0]], [e1[1], e2[1]]])        # columns e1, e2
    kap = kappa(nu, plane)
    out = {}
    for mode in (1, 2):
        _, Gl = williams_disp_grad(x1, x2, mode, mu, kap)
        Gl = np.array([[Gl[0][0], Gl[0][1]], [Gl[1][0], Gl[1][1]]])
        Gg = np.einsum("ia,aben,jb->ijen", R, Gl, R)       # global gradient
        ea = 0.5 * (Gg + np.swapaxes(Gg, 0, 1))
        tra = ea[0, 0] + ea[1, 1]
        sa = 2 * mu * ea
        sa[0, 0] += lam * tra
        sa[1, 1] += lam * tra
        dua1 = Gg[:, 0] * e1[0] + Gg[:, 1] * e1[1]
        sagq = np.einsum("ijen,jen->ien", sa, gq)
        wint = np.einsum("ijen,ijen->en", sig, ea)
        I = np.sum(dx * (np.einsum("ien,ien->en", sgq, dua1)
                         + np.einsum("ien,ien->en", sagq, du1)
                         - wint * e1gq))
        out[mode] = float(I)
    Ep = e_prime(E, nu, plane)
    KI = 0.5 * Ep * out[1]
    KII = 0.5 * Ep * out[2]
    return dict(J=J, KI=KI, KII=KII, J_from_K=(KI ** 2 + KII ** 2) / Ep,
                r1=r1, r2=r2, n_elems=int(len(elems)))


def displacement_correlation(mesh, u, basis, faces_plus, faces_minus, tip, e1,
                             E, nu, plane, rmax):
    """K_I, K_II from the crack-face displacement jump (vertex nodes only).

    faces_plus / faces_minus: matching vertex rows on the +e2 / -e2 face of the
    tip frame (the caller orders them).  K(r) = E'/8 sqrt(2 pi / r) [u] (jump:
    +e2 face minus -e2 face, local components); fitted linearly in r on
    0 < r <= rmax and extrapolated to r = 0.
    """
    tip = np.asarray(tip, float)
    e1 = np.asarray(e1, float) / np.linalg.norm(e1)
    e2 = np.array([-e1[1], e1[0]])
    nd = basis.nodal_dofs
    P = mesh.p
    r = np.hypot(P[0, faces_plus] - tip[0], P[1, faces_plus] - tip[1])
    ux = u[nd[0]]
    uy = u[nd[1]]
    jx = ux[faces_plus] - ux[faces_minus]
    jy = uy[faces_plus] - uy[faces_minus]
    j1 = e1[0] * jx + e1[1] * jy
    j2 = e2[0] * jx + e2[1] * jy
    sel = (r > 0) & (r <= rmax)
    Ep = e_prime(E, nu, plane)
    KI_r = Ep / 8 * np.sqrt(2 * np.pi / r[sel]) * j2[sel]
    KII_r = Ep / 8 * np.sqrt(2 * np.pi / r[sel]) * j1[sel]
    A = np.vstack([np.ones(sel.sum()), r[sel]]).T
    cI = np.linalg.lstsq(A, KI_r, rcond=None)[0]
    cII = np.linalg.lstsq(A, KII_r, rcond=None)[0]
    return dict(KI=float(cI[0]), KII=float(cII[0]), n_points=int(sel.sum()), rmax=rmax)


# --------------------------------------------------------------------------
# MTS criterion
# --------------------------------------------------------------------------
def mts_angle(KI, KII):
    """Kink angle [rad] of the maximum tangential stress criterion.

    theta_c = 2 arctan[(K_I - sqrt(K_I^2 + 8 K_II^2)) / (4 K_II)], measured
    from the crack's own extension direction e1, counter-clockwise positive.
    """
    if KII == 0.0:
        return 0.0
    return float(2.0 * np.arctan((KI - np.sqrt(KI ** 2 + 8.0 * KII ** 2)) / (4.0 * KII)))


def hoop_stress(theta, KI, KII):
    """sigma_theta_theta * sqrt(2 pi r) of the Williams field."""
    c = np.cos(theta / 2)
    return c * (KI * c ** 2 - 1.5 * KII * np.sin(theta))
