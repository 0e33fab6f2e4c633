"""CalculiX decks for one bladder: generator, runner and reader (never used by the planner).

A bladder is a thick spherical shell of nearly incompressible Mooney-Rivlin rubber, modelled
axisymmetric in the (r, z) plane over a quarter meridian (equator z = 0 to pole r = 0) with
8-node reduced-integration axisymmetric quads (CAX8R: CalculiX expands them to C3D20R, its
recommended element for nearly incompressible rubber), graded toward the pole where contact
begins. Step 1 inflates the cavity by a follower pressure on the inner surface (*DLOAD with
NLGEOM); step 2 holds that pressure (the regulator does) and pushes a rigid frictionless
indenter (a plane, or a sphere of the head's radius of curvature) down the axis by a
prescribed displacement; the force is the indenter's reaction.

Supports (at the equator, z = 0):
  centre  u_z = 0 only: the shell between two plates pressed equally, i.e. the bladder's
          centre held, which is what the kinematic and load levels assume;
  panel   u_r = u_z = 0: a hemisphere whose rim is bonded to a flat panel through its centre.

Units: SI (m, Pa, N). CalculiX's axisymmetric reactions belong to a 2-degree segment, so the
whole-circle force is 180 times the printed one.
"""
import math
import os
import re
import subprocess
import tempfile

SEGMENT = 180.0  # whole circle / CalculiX's 2-degree axisymmetric segment


def id_lines(ids):
    """A CalculiX set's members, 12 to a line (the deck format's limit is 16)."""
    return [",".join(map(str, ids[i:i + 12])) for i in range(0, len(ids), 12)]


def rubber_section(C10, C01, D1):
    """The shell's nearly incompressible Mooney-Rivlin material on the element set SHELL."""
    return ["*MATERIAL,NAME=RUBBER", "*HYPERELASTIC,MOONEY-RIVLIN",
            "%.10e,%.10e,%.10e" % (C10, C01, D1),
            "*SOLID SECTION,ELSET=SHELL,MATERIAL=RUBBER"]


def steel_section(elset):
    """A rigid-enough steel body (an indenter or a plate) on the element set elset."""
    return ["*MATERIAL,NAME=STEEL", "*ELASTIC", "2e11,0.3",
            "*SOLID SECTION,ELSET=%s,MATERIAL=STEEL" % elset]


def f_(lam):
    return -1.0 / lam - 0.25 / lam ** 4


def g_(lam):
    return lam - 0.5 / lam ** 2


def ik(Ri, Ro, ri, C1, C2):
    """Closed-form IK (the project's iab model, used here only to place the indenter)."""
    ro = (Ro ** 3 + ri ** 3 - Ri ** 3) ** (1.0 / 3.0)
    li, lo = ri / Ri, ro / Ro
    return 2 * C1 * (f_(li) - f_(lo)) + 2 * C2 * (g_(li) - g_(lo)), ro


def fk(Ri, Ro, P, C1, C2):
    """Inner radius at pressure P by bisection on the stable branch (placement only)."""
    a, b = Ri * 0.5, Ri
    while ik(Ri, Ro, b, C1, C2)[0] < P:
        a, b = b, b * 1.05
        if b > 3 * Ri:
            raise ValueError("pressure beyond the limit point")
    if P >= 0:
        a = max(a, Ri)
    for _ in range(200):
        m = 0.5 * (a + b)
        if ik(Ri, Ro, m, C1, C2)[0] < P:
            a = m
        else:
            b = m
    ri = 0.5 * (a + b)
    return ri, ik(Ri, Ro, ri, C1, C2)[1]


class Case:
    """One run. indenter: None (free inflation), 'plane' or a sphere radius in m."""

    def __init__(self, Ri=0.027, Ro=0.030, C1=1.1e4, C2=2.2e4, P=5e3, nr=4, nt=40,
                 grade=3.0, bulk_ratio=1e4, indenter=None, support="centre",
                 delta=0.0, penalty=100.0, inc=0.05, contact="NODE TO SURFACE",
                 controls=None, gap=1.0, stretch=None):
        self.__dict__.update(locals())
        del self.__dict__["self"]

    def mesh(self):
        """Nodes {id: (r, z)}, elements [(id, 8 node ids)], inner and outer faces."""
        nr, nt = self.nr, self.nt
        ni, nj = 2 * nr + 1, 2 * nt + 1
        num = {}
        for j in range(nj):
            for i in range(ni):
                if not (i % 2 and j % 2):  # 8-node quads have no centre node
                    num[i, j] = len(num) + 1
        nid = lambda i, j: num[i, j]
        nodes = {}
        for j in range(nj):
            s = j / (nj - 1)
            # graded: fine near the pole (s = 1); grade = ratio of equator to pole size
            t = s if self.grade == 1 else math.log1p((self.grade - 1) * s) / math.log(self.grade)
            al = 0.5 * math.pi * t
            for i in range(ni):
                if i % 2 and j % 2:
                    continue  # 8-node quads have no centre node
                R = self.Ri + (self.Ro - self.Ri) * i / (ni - 1)
                r, z = R * math.cos(al), R * math.sin(al)
                if j == nj - 1:
                    r = 0.0
                nodes[nid(i, j)] = (r, z)
        els = []
        for b in range(nt):
            for a in range(nr):
                i, j = 2 * a, 2 * b
                els.append((1 + a + nr * b,
                            (nid(i, j), nid(i + 2, j), nid(i + 2, j + 2), nid(i, j + 2),
                             nid(i + 1, j), nid(i + 2, j + 1), nid(i + 1, j + 2), nid(i, j + 1))))
        inner_el = [1 + nr * b for b in range(nt)]
        outer_el = [nr + nr * b for b in range(nt)]
        self.inner_nodes = [nid(0, j) for j in range(nj)]
        self.outer_nodes = [nid(ni - 1, j) for j in range(nj)]
        self.equator = [nid(i, 0) for i in range(ni)]
        self.axis = [nid(i, nj - 1) for i in range(ni)]
        self._nodes = nodes
        return nodes, els, inner_el, outer_el

    def free_radius(self):
        return fk(self.Ri, self.Ro, self.P, self.C1, self.C2)

    def deck(self):
        nodes, els, inner_el, outer_el = self.mesh()
        C10, C01 = self.C1 / 2, self.C2 / 2
        mu = self.C1 + self.C2           # initial shear modulus 2(C10 + C01)
        D1 = 2.0 / (self.bulk_ratio * mu)  # bulk modulus K = 2/D1 = bulk_ratio * mu
        L = ["*HEADING", "headplan bladder: " + self.describe(), "*NODE"]
        L += ["%d,%.12e,%.12e" % (k, r, z) for k, (r, z) in sorted(nodes.items())]
        L.append("*ELEMENT,TYPE=CAX8R,ELSET=SHELL")
        L += ["%d,%s" % (e, ",".join(map(str, c))) for e, c in els]
        sets = {"INNER": self.inner_nodes, "OUTER": self.outer_nodes,
                "EQUATOR": self.equator, "AXIS": self.axis}
        ind = None
        if self.indenter is not None:
            ind = self.indenter_mesh(max(nodes) + 1, len(els) + 1)
            L.append("*NODE")
            L += ["%d,%.12e,%.12e" % (k, r, z) for k, (r, z) in ind["nodes"]]
            L.append("*ELEMENT,TYPE=CAX8R,ELSET=INDENTER")
            L += ["%d,%s" % (e, ",".join(map(str, c))) for e, c in ind["els"]]
            sets["IND"] = [k for k, _ in ind["nodes"]]
        for name, ids in sets.items():
            L.append("*NSET,NSET=%s" % name)
            L += id_lines(ids)
        L.append("*ELSET,ELSET=INNEREL")
        L += id_lines(inner_el)
        L += rubber_section(C10, C01, D1)
        if ind:
            # every indenter node is prescribed: a rigid body whose reaction is the force
            L += steel_section("INDENTER") + ["*SURFACE,NAME=SOUT,TYPE=ELEMENT"]
            L += ["%d,S2" % e for e in outer_el]
            L.append("*SURFACE,NAME=SIND,TYPE=ELEMENT")
            L += ["%d,S1" % e for e in ind["face"]]
            # penalty: contact pressure per overclosure, `penalty` times the wall's
            # membrane stiffness scale (C1 + C2)/t
            k = self.penalty * mu / (self.Ro - self.Ri)
            L += ["*SURFACE INTERACTION,NAME=SI", "*SURFACE BEHAVIOR,PRESSURE-OVERCLOSURE=LINEAR",
                  "%.6e" % k,
                  "*CONTACT PAIR,INTERACTION=SI,TYPE=%s" % self.contact, "SOUT,SIND"]
        # One step: the pressure ramps to P while the indenter moves to its final contact
        # distance, both linear in the step's time; the bladder meets the indenter late in
        # the step. The rubber is elastic and the contact frictionless, so the end state
        # does not depend on that path. (A second step that starts from the inflated state
        # does not converge in CalculiX 2.20, with or without contact: its Newton iteration
        # drifts away from the equilibrium it starts at. One run per indentation, then.)
        L += ["*BOUNDARY", "AXIS,1,1", "EQUATOR,2,2"]
        if self.support == "panel":
            L.append("EQUATOR,1,1")
        if ind:
            L.append("IND,1,1")
        L += ["*STEP,NLGEOM,INC=2000", "*STATIC", "%g,1.0,1e-7,%g" % (self.inc, self.inc * 2)]
        if self.stretch is None:
            L += ["*DLOAD", "INNEREL,P4,%.10e" % self.P]
        else:
            # displacement control: the inner surface is moved to the sphere of radius
            # stretch*Ri (free inflation's exact inner displacement) and the pressure is read
            # from its reactions (cavity_pressure); no follower load, no limit to pass
            L.append("*BOUNDARY")
            for k in self.inner_nodes:
                L += ["%d,%d,%d,%.12e" % (k, d + 1, d + 1, (self.stretch - 1) * nodes[k][d])
                      for d in (0, 1)]
        if self.controls:
            L += ["*CONTROLS,PARAMETERS=TIME INCREMENTATION", self.controls]
        if ind:
            L += ["*BOUNDARY", "IND,2,2,%.12e" % (self.rho() - self.z_start),
                  "*NODE PRINT,NSET=IND,TOTALS=ONLY", "RF"]
        L += ["*NODE PRINT,NSET=INNER", "U" if self.stretch is None else "U,RF",
              "*NODE PRINT,NSET=OUTER", "U",
              "*NODE PRINT,NSET=EQUATOR,TOTALS=ONLY", "RF", "*END STEP"]
        return "\n".join(L) + "\n"

    def rho(self):
        """Contact distance (the indenter's nearest point to the held centre) at delta/ro."""
        return self.free_radius()[1] * (1 - self.delta)

    def indenter_mesh(self, n0, e0):
        ro = self.free_radius()[1]
        # start above the free top (the clamped rim lets the pole rise further than ro - Ro)
        self.z_start = ro + self.gap * (0.3 * (self.Ro - self.Ri) + 0.02 * ro)
        w, h, n = 1.4 * ro, 0.2 * ro, 24
        Rh = None if self.indenter == "plane" else float(self.indenter)
        nodes, els, face = [], [], []

        def zb(r):
            return self.z_start if Rh is None else self.z_start + Rh - math.sqrt(Rh * Rh - r * r)
        ids = {}
        for i in range(2 * n + 1):
            r = w * i / (2 * n)
            for j in range(3):
                if i % 2 and j == 1:
                    continue
                k = n0 + len(nodes)
                ids[i, j] = k
                nodes.append((k, (r, zb(r) + h * j / 2)))
        for a in range(n):
            i = 2 * a
            # counter-clockwise in (r, z): bottom face (S1) is nodes 1-2
            c = (ids[i, 0], ids[i + 2, 0], ids[i + 2, 2], ids[i, 2],
                 ids[i + 1, 0], ids[i + 2, 1], ids[i + 1, 2], ids[i, 1])
            els.append((e0 + a, c))
            face.append(e0 + a)
        return {"nodes": nodes, "els": els, "face": face}

    def describe(self):
        return ("Ri=%g Ro=%g C1=%g C2=%g P=%g nr=%d nt=%d grade=%g K/mu=%g indenter=%s "
                "support=%s penalty=%g" % (self.Ri, self.Ro, self.C1, self.C2, self.P, self.nr,
                                           self.nt, self.grade, self.bulk_ratio, self.indenter,
                                           self.support, self.penalty))


_BLOCK = re.compile(r"^\s*(displacements|forces|total force)\s*\(.*?\)\s*for set (\S+) and time\s+(\S+)")


def read_dat(path):
    """{(kind, set): [(time, {node: (x, y, z)} or [fx, fy, fz])]} from a CalculiX .dat file
    (the axisymmetric decks use the first two components, r and z)."""
    out = {}
    cur = None
    step_base, last_t = 0.0, -1.0
    with open(path) as fh:
        for line in fh:
            m = _BLOCK.match(line)
            if m:
                kind, name, t = m.group(1), m.group(2), float(m.group(3))
                cur = {} if kind != "total force" else []
                out.setdefault((kind, name), []).append((t, cur))
                continue
            if line.strip().startswith("STEP"):
                continue
            p = line.split()
            if cur is None or not p:
                continue
            try:
                vals = [float(x) for x in p]
            except ValueError:
                cur = None
                continue
            if isinstance(cur, list):
                cur.extend(vals)
            elif len(vals) >= 3:
                cur[int(vals[0])] = tuple(vals[1:])
    return out


# The niceness ccx runs at: 19 for the long table runs (fem/make_tables.py), which yield to
# everything else; fem/check_case.py, a test, sets 0 (at 19, beside .ci/run's busy loops,
# its three small cases got almost no CPU: 900 s and a timeout, against 10 s unloaded).
NICE = 19


def run(case, workdir=None, keep=False, partial=False):
    """Write the deck, run ccx (nice'd, one thread) and return the parsed .dat. A run that
    fails raises, unless partial: then what it printed up to its last converged increment
    is returned with the key "failed" (the engine's error lines)."""
    d = workdir or tempfile.mkdtemp(prefix="hpfem_")
    os.makedirs(d, exist_ok=True)
    deck = case.deck()
    with open(os.path.join(d, "b.inp"), "w") as fh:
        fh.write(deck)
    env = dict(os.environ, OMP_NUM_THREADS="1", CCX_NPROC_EQUATION_SOLVER="1")
    r = subprocess.run(["nice", "-n", str(NICE), "ccx", "-i", "b"], cwd=d, env=env, capture_output=True,
                       text=True, timeout=1800)
    ok = r.returncode == 0 and "Job finished" in r.stdout and "*ERROR" not in r.stdout
    res = read_dat(os.path.join(d, "b.dat")) if os.path.exists(os.path.join(d, "b.dat")) else {}
    if not keep and workdir is None:
        for f in os.listdir(d):
            os.remove(os.path.join(d, f))
        os.rmdir(d)
    if not ok:
        tail = "\n".join(l for l in r.stdout.splitlines() if "ERROR" in l)[:600]
        if partial:
            res["failed"] = tail
            return res
        raise RuntimeError("ccx failed (%s): %s" % (case.describe(), tail))
    return res


def cavity_pressure(case, res):
    """The pressure a displacement-controlled inflation (case.stretch) holds, from the inner
    surface's axial reactions: for consistent nodal loads of a uniform pressure p,
    sum(z_i f_z,i) = p * integral(z n_z dA) = p V exactly (z is in the elements'
    interpolation; the equator plane, z = 0, and the segment's sides, n_z = 0, add
    nothing), V the deformed half cavity, here the hemisphere of radius stretch*Ri the nodes
    lie on (the quadratic faces' departure from it is below 1e-7 on the coarsest mesh). The
    equator's own support reaction acts at z = 0 and drops out. The radial reactions are
    not used: CalculiX's expansion of the axisymmetric segment leaves them short by a few
    per cent of the pressure's. Whole circle: 180 segments."""
    t, U = res[("displacements", "INNER")][-1]
    if abs(t - 1.0) > 1e-9:
        raise RuntimeError("inflation stopped at t = %g" % t)
    _, RF = res[("forces", "INNER")][-1]
    m = sum((case._nodes[k][1] + U[k][1]) * RF[k][1] for k in case.inner_nodes)
    return SEGMENT * m / ((2.0 / 3.0) * math.pi * (case.stretch * case.Ri) ** 3)


def ccx_version():
    r = subprocess.run(["ccx", "-v"], capture_output=True, text=True)
    m = re.search(r"Version\s+(\S+)", r.stdout + r.stderr)
    return m.group(1) if m else "unknown"


def polyline(case, disp, ids):
    """Deformed (r, z) of the listed nodes in order."""
    nodes = case._nodes
    return [(nodes[k][0] + disp[k][0], nodes[k][1] + disp[k][1]) for k in ids]


def cavity_volume(pts):
    """Volume of revolution under a meridian polyline from equator to pole (half cavity),
    by the exact volume of each segment's frustum (piecewise linear through every node,
    midside nodes included)."""
    v = 0.0
    for (r1, z1), (r2, z2) in zip(pts, pts[1:]):
        v += math.pi * (z2 - z1) * (r1 * r1 + r1 * r2 + r2 * r2) / 3.0
    return v


def indenter_gap(case, r, z, rho):
    """Distance of the point (r, z) from the indenter whose nearest point to the centre is at
    height rho on the axis (a plane, or a sphere of radius case.indenter)."""
    if case.indenter == "plane":
        return rho - z
    Rh = float(case.indenter)
    return math.hypot(r, rho + Rh - z) - Rh


SHAPE_ANGLES = (0, 30, 45, 60)  # elevations above the equator where the profile is sampled


def surface_shape(pts, ro, rho, gap=None, tol=None):
    """The free outer surface's departure from the shape the levels assume: the sphere of
    radius ro about the held centre, cut by the indenter (the cap law's shape).

    pts  the deformed outer meridian, equator to pole, (r, z) about the held centre
    gap  gap(r, z): distance from the indenter, positive outside (default: a plane at
         height rho)
    tol  a point nearer than this is in contact (default 1e-9 ro)
    bulge(point) = (|x| - R_cut)/ro, R_cut the cut sphere's radius along the point's ray
    from the centre (ro below the cap's edge, the indenter's distance along the ray above).
    Returns bulge_max and bulge_min over the free surface with their elevations
    bulge_max_deg and bulge_min_deg above the equator, bulge_A at elevation A degrees for A
    in SHAPE_ANGLES (interpolated linearly between nodes; NaN inside the patch) and
    edge_deg, the elevation of the patch's edge (the first point in contact from the
    equator)."""
    gap = gap or (lambda r, z: rho - z)
    tol = 1e-9 * ro if tol is None else tol

    def cut(c, s):  # the cut sphere's radius along the ray (c, s), by bisection
        if gap(ro * c, ro * s) >= 0:
            return ro
        lo, hi = 0.0, ro  # gap > 0 at the centre, < 0 at ro
        for _ in range(100):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if gap(mid * c, mid * s) > 0 else (lo, mid)
        return 0.5 * (lo + hi)
    free = []
    for r, z in pts:
        if gap(r, z) < tol:
            break
        R = math.hypot(r, z)
        free.append((math.degrees(math.atan2(z, r)), (R - cut(r / R, z / R)) / ro))
    edge = (math.degrees(math.atan2(pts[len(free)][1], pts[len(free)][0]))
            if len(free) < len(pts) else 90.0)
    k = max(range(len(free)), key=lambda i: free[i][1])
    m = min(range(len(free)), key=lambda i: free[i][1])
    out = {"bulge_max": free[k][1], "bulge_max_deg": free[k][0], "bulge_min": free[m][1],
           "bulge_min_deg": free[m][0], "edge_deg": edge}
    for a in SHAPE_ANGLES:
        out["bulge_%d" % a] = float("nan")
        for (a1, b1), (a2, b2) in zip(free, free[1:]):
            if a1 <= a <= a2 and a2 > a1:
                out["bulge_%d" % a] = b1 + (b2 - b1) * (a - a1) / (a2 - a1)
                break
        if a == free[0][0]:
            out["bulge_%d" % a] = free[0][1]
    return out


def contact_result(case, res):
    """Force, contact patch radius, cavity volume change and the free surface's shape at the
    end of a contact run.

    force  whole-circle reaction on the indenter [N] (CalculiX prints a 2-degree segment's)
    patch  deformed radius of the outermost outer-surface node within the contact tolerance
           of the indenter (twice the penalty overclosure at the pressure, plus 1e-6 ro)
    dvol   cavity volume over the free-inflated sphere's (4/3 pi ri^3) minus 1
    and surface_shape's keys for the outer meridian with the same tolerance
    """
    t, f = res[("total force", "IND")][-1]
    if abs(t - 1.0) > 1e-9:
        raise RuntimeError("contact run stopped at t = %g" % t)
    F = -f[1] * SEGMENT
    ri, ro = case.free_radius()
    _, Uo = res[("displacements", "OUTER")][-1]
    _, Ui = res[("displacements", "INNER")][-1]
    rho = case.rho()
    kpen = case.penalty * (case.C1 + case.C2) / (case.Ro - case.Ri)
    tol = 2.0 * case.P / kpen + 1e-6 * ro
    outer = polyline(case, Uo, case.outer_nodes)
    gap = lambda r, z: indenter_gap(case, r, z, rho)
    a = max([r for r, z in outer if gap(r, z) < tol] + [0.0])
    V = 2.0 * cavity_volume(polyline(case, Ui, case.inner_nodes))
    out = {"force": F, "patch": a, "dvol": V / (4.0 / 3.0 * math.pi * ri ** 3) - 1.0,
           "outer": outer}
    out.update(surface_shape(outer, ro, rho, gap, tol))
    return out
