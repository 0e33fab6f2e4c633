"""CalculiX decks for one bladder in 3-D: a rigid plane whose normal is tilted from the
bladder's axis (never used by the planner).

The shell is the axisymmetric model's (hpfem.py: same material, follower pressure, support
and one-step path), meshed in 3-D: the upper hemisphere's half y >= 0 (a symmetry plane,
u_y = 0 on y = 0) as a cubed sphere (the top face and the upper halves of the four side
faces, no pole singularity), C3D20R through the wall, the top face graded toward the pole.
The plane's normal n = (sin tilt, 0, cos tilt) lies in the symmetry plane; it is a layer of
C3D8 elements every node of which is prescribed (a rigid body whose reaction is the force),
moved along -n to the distance rho = ro (1 - delta/ro) from the centre.

Supports (at the equator, z = 0):
  centre  u_z = 0, and the equator ring's mean u_x = 0 (*EQUATION): the bladder's centre
          held, as in the axisymmetric model; the ring carries the force's component along
          the plane (a tilted plane pushes the shell sideways);
  panel   u = 0: the rim bonded to a flat panel through the centre.

Units: SI. The model is half the bladder: the force and moment are twice the printed ones.
"""
import math

import hpfem


def _grid(n, c):
    """2n + 1 node parameters on [-1, 1] (cell ends and midpoints) mapped to angles in
    [-pi/4, pi/4], graded toward 0: spacing c times uniform there, 3 - 2c at the ends."""
    out = []
    for k in range(2 * n + 1):
        s = -1.0 + k / n
        out.append(0.25 * math.pi * s * (c + (1 - c) * s * s))
    return out


def _tan(a):
    """tan, exact at 0 and +-pi/4 so that nodes shared by two faces coincide bit for bit."""
    if a == 0.0:
        return 0.0
    if abs(abs(a) - 0.25 * math.pi) < 1e-15:
        return math.copysign(1.0, a)
    return math.tan(a)


def _turn(p1, p2, p4, up):
    """((p2 - p1) x (p4 - p1)) . up: positive when p1, p2, p4 turn counterclockwise seen
    from the side `up` points to (a hex's first face, seen from its opposite face)."""
    u = [p2[q] - p1[q] for q in range(3)]
    v = [p4[q] - p1[q] for q in range(3)]
    return ((u[1] * v[2] - u[2] * v[1]) * up[0] + (u[2] * v[0] - u[0] * v[2]) * up[1] +
            (u[0] * v[1] - u[1] * v[0]) * up[2])


class Case3D:
    """One 3-D run. n: cells across the cubed sphere's top face (even), nv: cells up a side
    face, nr: cells through the wall, grade: the top face's pole spacing over uniform."""

    def __init__(self, Ri=0.027, Ro=0.030, C1=1.1e4, C2=2.2e4, P=5e3, n=16, nv=4, nr=2,
                 grade=0.5, bulk_ratio=1e4, tilt=0.0, delta=0.1, penalty=100.0, inc=0.02,
                 gap=1.0, support="centre", contact="NODE TO SURFACE",
                 controls="4,8,9,16,10,4,,3", small_sliding=False, plate_cells=1):
        self.__dict__.update(locals())
        del self.__dict__["self"]

    def free_radius(self):
        return hpfem.fk(self.Ri, self.Ro, self.P, self.C1, self.C2)

    def rho(self):
        return self.free_radius()[1] * (1 - self.delta)

    def delta_at(self, t):
        """delta/ro of the state at the step's time t: the plane at z_start + t (rho -
        z_start) from the centre, the bladder's free radius at the pressure t P."""
        ro = self.free_radius()[1]
        z_start = ro + self.gap * (0.3 * (self.Ro - self.Ri) + 0.02 * ro)
        z = z_start + t * (ro * (1 - self.delta) - z_start)
        return 1.0 - z / hpfem.fk(self.Ri, self.Ro, t * self.P, self.C1, self.C2)[1]

    def normal(self):
        t = math.radians(self.tilt)
        return (math.sin(t), 0.0, math.cos(t))

    def mesh(self):
        """Nodes {id: (x, y, z)}, C3D20R elements [(id, 20 node ids)], inner and outer
        element lists (face S1 inner, S2 outer)."""
        T = [_tan(a) for a in _grid(self.n, self.grade)]
        V = [_tan(0.25 * math.pi * k / (2 * self.nv)) for k in range(2 * self.nv + 1)]
        h = self.n  # index of the middle of T (angle 0)
        # each face: direction of node (i, j), the ranges of i and j (node indices)
        faces = [(lambda i, j: (T[i], T[j], 1.0), range(0, 2 * self.n + 1), range(h, 2 * self.n + 1)),
                 (lambda i, j: (1.0, T[i], V[j]), range(h, 2 * self.n + 1), range(0, 2 * self.nv + 1)),
                 (lambda i, j: (-1.0, T[i], V[j]), range(h, 2 * self.n + 1), range(0, 2 * self.nv + 1)),
                 (lambda i, j: (T[i], 1.0, V[j]), range(0, 2 * self.n + 1), range(0, 2 * self.nv + 1))]
        nk = 2 * self.nr + 1
        key2id, nodes = {}, {}

        def node(d, k):
            R = self.Ri + (self.Ro - self.Ri) * k / (nk - 1)
            m = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
            x = tuple(R * c / m for c in d)
            key = tuple(round(c * 1e9) for c in x)
            if key not in key2id:
                key2id[key] = len(key2id) + 1
                nodes[key2id[key]] = x
            return key2id[key]
        els, inner, outer = [], [], []
        corner = [(0, 0), (2, 0), (2, 2), (0, 2)]
        mid = [(1, 0), (2, 1), (1, 2), (0, 1)]
        for f, irange, jrange in faces:
            i0, j0 = irange[0], jrange[0]
            ni, nj = (len(irange) - 1) // 2, (len(jrange) - 1) // 2
            for a in range(ni):
                for b in range(nj):
                    for c in range(self.nr):
                        def nd(di, dj, dk):
                            return node(f(i0 + 2 * a + di, j0 + 2 * b + dj), 2 * c + dk)
                        cn, md = corner, mid
                        # right-handed: (x2 - x1) x (x4 - x1) along the outward radius
                        p1, p2, p4 = (nodes[nd(*corner[0], 0)], nodes[nd(*corner[1], 0)],
                                      nodes[nd(*corner[3], 0)])
                        if _turn(p1, p2, p4, p1) < 0:
                            cn = [corner[0], corner[3], corner[2], corner[1]]
                            md = [mid[3], mid[2], mid[1], mid[0]]
                        ids = ([nd(i, j, 0) for i, j in cn] + [nd(i, j, 2) for i, j in cn] +
                               [nd(i, j, 0) for i, j in md] + [nd(i, j, 2) for i, j in md] +
                               [nd(i, j, 1) for i, j in cn])
                        e = len(els) + 1
                        els.append((e, ids))
                        if c == 0:
                            inner.append(e)
                        if c == self.nr - 1:
                            outer.append(e)
        self._nodes = nodes
        return nodes, els, inner, outer

    def plate(self, n0, e0):
        """The rigid plane: a layer of C3D8 over the patch's side of the symmetry plane,
        its face S1 toward the shell, at distance z_start from the centre along n."""
        ro = self.free_radius()[1]
        self.z_start = ro + self.gap * (0.3 * (self.Ro - self.Ri) + 0.02 * ro)  # delta_at's
        nx, ny = self.normal(), (0.0, 1.0, 0.0)
        e1 = (nx[2], 0.0, -nx[0])  # in the plane, along the tilt
        # one element: a flat master face has nothing to resolve, and a slave node sliding
        # across the edge between two faces changes its pairing (Newton then converged only
        # linearly at tilt 20 with 12 x 6 faces)
        m, th = self.plate_cells, 0.1 * ro
        us = [-0.9 * ro + 1.8 * ro * i / m for i in range(m + 1)]
        mv = max(1, m // 2)
        vs = [-0.1 * ro + 1.0 * ro * j / mv for j in range(mv + 1)]
        ids, nodes = {}, []
        for i, u in enumerate(us):
            for j, v in enumerate(vs):
                for k in range(2):
                    p = tuple((self.z_start + th * k) * nx[q] + u * e1[q] + v * ny[q]
                              for q in range(3))
                    ids[i, j, k] = n0 + len(nodes)
                    nodes.append((ids[i, j, k], p))
        els = []
        for i in range(m):
            for j in range(mv):
                c = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]
                p = [nodes[ids[a, b, 0] - n0][1] for a, b in c]
                if _turn(p[0], p[1], p[3], nx) < 0:  # right-handed, S1 (k = 0) toward the shell
                    c = [c[0], c[3], c[2], c[1]]
                els.append((e0 + len(els), [ids[a, b, 0] for a, b in c] +
                            [ids[a, b, 1] for a, b in c]))
        return nodes, els

    def deck(self):
        """delta None: free inflation (no plate), the inner surface's pole and equator
        nodes printed (inflation_radii)."""
        nodes, els, inner, outer = self.mesh()
        C10, C01 = self.C1 / 2, self.C2 / 2
        mu = self.C1 + self.C2
        D1 = 2.0 / (self.bulk_ratio * mu)
        L = ["*HEADING", "headplan bladder 3-D: " + self.describe(), "*NODE"]
        L += ["%d,%.12e,%.12e,%.12e" % ((k,) + x) for k, x in sorted(nodes.items())]
        L.append("*ELEMENT,TYPE=C3D20R,ELSET=SHELL")
        for e, c in els:
            L += ["%d,%s," % (e, ",".join(map(str, c[:15]))), ",".join(map(str, c[15:]))]
        pn, pe = self.plate(max(nodes) + 1, len(els) + 1) if self.delta is not None else ([], [])
        if pn:
            L.append("*NODE")
            L += ["%d,%.12e,%.12e,%.12e" % ((k,) + x) for k, x in pn]
            L.append("*ELEMENT,TYPE=C3D8,ELSET=PLATE")
            L += ["%d,%s" % (e, ",".join(map(str, c))) for e, c in pe]
        sym = [k for k, x in nodes.items() if abs(x[1]) < 1e-12]
        equ = [k for k, x in nodes.items() if abs(x[2]) < 1e-12]
        self.plate_nodes = dict(pn)
        self.poles = [k for k, x in nodes.items() if abs(x[0]) < 1e-12 and abs(x[1]) < 1e-12
                      and abs(x[2] - self.Ri) < 1e-12]
        self.poles += [k for k, x in nodes.items() if abs(x[1]) < 1e-12 and abs(x[2]) < 1e-12
                       and abs(x[0] - self.Ri) < 1e-12]
        sets = [("SYM", sym), ("EQUATOR", equ), ("POLES", self.poles)]
        if pn:
            sets.append(("IND", [k for k, _ in pn]))
        for name, ids in sets:
            L.append("*NSET,NSET=%s" % name)
            L += hpfem.id_lines(ids)
        L += hpfem.rubber_section(C10, C01, D1)
        if pn:
            L += hpfem.steel_section("PLATE") + ["*SURFACE,NAME=SOUT,TYPE=ELEMENT"]
            # the slave surface: the outer faces within 55 degrees of the plane's normal
            # (the patch reaches 40 at tilt 20, delta/ro 0.18). small_sliding freezes the
            # pairing at the step's start: in CalculiX 2.20 that diverged at first touch
            nx = self.normal()
            for e in outer:
                c = [sum(nodes[q][d] for q in els[e - 1][1][4:8]) for d in range(3)]
                if sum(c[d] * nx[d] for d in range(3)) > math.cos(math.radians(55)) * math.sqrt(
                        sum(v * v for v in c)):
                    L.append("%d,S2" % e)
            L.append("*SURFACE,NAME=SIND,TYPE=ELEMENT")
            L += ["%d,S1" % e for e, _ in pe]
            k = self.penalty * mu / (self.Ro - self.Ri)
            L += ["*SURFACE INTERACTION,NAME=SI",
                  "*SURFACE BEHAVIOR,PRESSURE-OVERCLOSURE=LINEAR", "%.6e" % k,
                  "*CONTACT PAIR,INTERACTION=SI,TYPE=%s%s" % (
                      self.contact, ",SMALL SLIDING" if self.small_sliding else ""),
                  "SOUT,SIND"]
        L += ["*BOUNDARY", "SYM,2,2", "EQUATOR,3,3"]
        if self.support == "panel":
            L.append("EQUATOR,1,2")
        else:
            # the ring's mean u_x = 0 (the first term's dof becomes the dependent one)
            L += ["*EQUATION", str(len(equ))]
            t = ["%d,1,1." % q for q in equ]
            L += [",".join(t[i:i + 4]) for i in range(0, len(t), 4)]
            L.append("*BOUNDARY")
        if pn:
            L += ["IND,2,2"]
        L += ["*STEP,NLGEOM,INC=2000", "*STATIC", "%g,1.0,1e-7,%g" % (self.inc, self.inc * 2),
              "*DLOAD"]
        L += ["%d,P1,%.10e" % (e, self.P) for e in inner]
        if self.controls:
            # a tilted run's Newton converges only linearly past about 0.9 of the step
            # (40 iterations and 10 cutbacks did not get it to the end): give up after 3
            # cutbacks (I_A 5 -> 3) and keep the states reached (result's t)
            L += ["*CONTROLS,PARAMETERS=TIME INCREMENTATION", self.controls]
        if pn:
            s = self.rho() - self.z_start  # along n, negative: toward the centre
            nx = self.normal()
            L += ["*BOUNDARY", "IND,1,1,%.12e" % (s * nx[0]), "IND,3,3,%.12e" % (s * nx[2]),
                  "*NODE PRINT,NSET=IND", "RF"]
        L += ["*NODE PRINT,NSET=POLES", "U", "*END STEP"]
        return "\n".join(L) + "\n"

    def describe(self):
        return ("Ri=%g Ro=%g C1=%g C2=%g P=%g n=%d nv=%d nr=%d grade=%g K/mu=%g tilt=%g "
                "delta=%s support=%s penalty=%g" % (
                    self.Ri, self.Ro, self.C1, self.C2, self.P, self.n, self.nv, self.nr,
                    self.grade, self.bulk_ratio, self.tilt, self.delta, self.support,
                    self.penalty))


def inflation_radii(case, res):
    """The inner radius at the pole and at the equator after a free inflation (delta None)."""
    t, U = res[("displacements", "POLES")][-1]
    if abs(t - 1.0) > 1e-9:
        raise RuntimeError("3-D inflation stopped at t = %g" % t)
    pole, eq = case.poles[0], case.poles[-1]
    return case.Ri + U[pole][2], case.Ri + U[eq][0]


def forces(case, res):
    """[(t, F)] at every printed increment: F the force on the plane (whole bladder, twice
    the half model's), t the step's time (pressure t P, plane at z_start + t (rho -
    z_start) along n)."""
    out = []
    for t, RF in res.get(("forces", "IND"), []):
        out.append((t, [-2.0 * sum(f[q] for f in RF.values()) for q in range(3)], RF))
    return out


def result(case, res):
    """The force on the plane and its line of action at the last converged increment.

    force      |F| of the whole bladder [N]
    angle_deg  the angle between F and the plane's normal
    offset     the centre of pressure's distance from the foot of the normal through the
               bladder's centre, along the plane in the tilt's direction [m]
    t          the step's time reached (1: the run's end state; less: the run stopped,
               "error" says why, and the force is that of the state at t)
    series     [(t, |F|)] at every increment, to compare runs at the same t
    """
    fs = forces(case, res)
    if not fs:
        raise RuntimeError("3-D contact run printed no force: " + res.get("failed", ""))
    t, F, RF = fs[-1]
    nx = case.normal()
    s = t * (case.rho() - case.z_start)
    My = 0.0
    for k, f in RF.items():  # moment about the centre of the force on the plane (half)
        x = [case.plate_nodes[k][q] + s * nx[q] for q in range(3)]
        My += x[2] * (-f[0]) - x[0] * (-f[2])
    mag = math.sqrt(sum(c * c for c in F))
    cosang = sum(F[q] * nx[q] for q in range(3)) / mag
    out = {"force": mag, "angle_deg": math.degrees(math.acos(min(1.0, cosang))),
           "offset": -2.0 * My / mag, "t": t,
           "series": [(ti, math.sqrt(sum(c * c for c in Fi))) for ti, Fi, _ in fs]}
    if abs(t - 1.0) > 1e-9:
        out["error"] = "stopped at t = %.4f: %s" % (t, res.get("failed", "")[-60:])
    return out
