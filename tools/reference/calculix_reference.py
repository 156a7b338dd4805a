#!/usr/bin/env python3
"""Independent references for the accuracy suite (docs/verification.md problems 3, 5, 6), solved by
CalculiX (Debian's calculix-ccx) with quadratic elements, from the problem parameters the engine
uses (`xcut bench --suite accuracy` passes them as JSON).

  calculix_reference.py PROBLEM PARAMS.json LEVELS OUT.json [--ccx ccx] [--work DIR]

PROBLEM 3: the cantilever under its own weight on 20-node hexahedra (C3D20), clamped at x = 0; the
  value is the mean downward deflection of the nodes at x = L [m].
PROBLEM 5: the block with a partial planar cut on C3D20, nodes duplicated across the cut part of
  the plane x = cut_x (a conforming crack), the grid graded toward the front if "front_grading" != 1; both end faces held and pulled by +-pull; the values
  are the displacements at the suite's sample points [m], interpolated with the elements' own
  quadratic shape functions.
PROBLEM 14: Cook's membrane (Cook 1974): the tapered panel with corners (0, 0), (48, 44), (48, 60),
  (0, 44) x scale, clamped on its left edge, a shear load on its right edge (consistent nodal loads),
  in plane strain on 8-node quadrilaterals with reduced integration (CPE8R, which does not lock as
  nu nears 0.5); the value is the vertical displacement of the top right corner [m].
PROBLEM 6: the edge-cracked plate in plane stress on 8-node quadrilaterals (CPS8) graded toward the
  crack tip (planes_toward), nodes duplicated along the crack; sigma on the top and bottom edges as consistent nodal loads; the value is the
  crack mouth opening [m]. The section is PLANE_STRESS_SECTION x W thick whatever the plate's own
  thickness (CalculiX solves a 2D element as a layer of 3D ones: see PLANE_STRESS_SECTION), or
  "section_fraction" x W if the parameters give it (tests).

LEVELS are the cells across the problem's reference length (L for 3 and 5, W for 6), comma
separated, coarse to fine. OUT.json gets every level's values, run time and DOFs, and the
reference's own error estimate (estimate() below: Richardson's extrapolation of the finest levels
with the observed order, and its distance to the extrapolation one level coarser). SI units throughout. Exit 2 with a message on bad input, 1 if CalculiX fails.
"""
import json
import math
import os
import subprocess
import sys
import tempfile
import time

# ----------------------------------------------------------------------------- structured quadratic grids


class Grid:
    """Serendipity nodes of a tensor grid of cells: corner and edge-midpoint nodes, no face or cell
    centres. Coordinates are given per axis as the sorted corner planes."""

    def __init__(self, planes):
        self.planes = planes  # per axis: corner coordinates
        self.dim = len(planes)
        self.ids = {}
        self.coords = []

    def pos(self, ijk):  # ijk in half-cell units
        return tuple(self.planes[a][ijk[a] // 2] if ijk[a] % 2 == 0 else
                     0.5 * (self.planes[a][ijk[a] // 2] + self.planes[a][ijk[a] // 2 + 1]) for a in range(self.dim))

    def node(self, ijk, copy=False):
        key = (tuple(ijk), copy)
        if key not in self.ids:
            self.coords.append(self.pos(ijk))
            self.ids[key] = len(self.coords)  # 1-based, as CalculiX numbers
        return self.ids[key]


def planes_through(length, cells, fixed):
    """`cells` equal cells over [0, length] moved so each of `fixed` is a plane: the cells on each
    side of a fixed plane are spaced evenly."""
    marks = sorted(set([0.0, length] + list(fixed)))
    out = [0.0]
    for a, b in zip(marks, marks[1:]):
        k = max(1, round(cells * (b - a) / length))
        out += [a + (b - a) * (i + 1) / k for i in range(k - 1)] + [b]  # the mark itself, exactly
    return out


# CalculiX node orders: C3D20 corners 1-8 (bottom z- face counter-clockwise, then top), edges 9-12
# bottom, 13-16 top, 17-20 vertical; CPS8 corners 1-4 counter-clockwise, edges 5-8.
HEX_CORNERS = [(0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0), (0, 0, 2), (2, 0, 2), (2, 2, 2), (0, 2, 2)]
HEX_EDGES = [(1, 0, 0), (2, 1, 0), (1, 2, 0), (0, 1, 0), (1, 0, 2), (2, 1, 2), (1, 2, 2), (0, 1, 2),
             (0, 0, 1), (2, 0, 1), (2, 2, 1), (0, 2, 1)]
QUAD_LOCAL = [(0, 0), (2, 0), (2, 2), (0, 2), (1, 0), (2, 1), (1, 2), (0, 1)]


def hex20_shape(xi, eta, zeta):
    """C3D20 shape functions at natural coordinates in [-1, 1]^3, in CalculiX's node order."""
    n = []
    for (i, j, k) in HEX_CORNERS:
        a, b, c = i - 1, j - 1, k - 1
        n.append(0.125 * (1 + a * xi) * (1 + b * eta) * (1 + c * zeta) * (a * xi + b * eta + c * zeta - 2))
    for (i, j, k) in HEX_EDGES:
        a, b, c = i - 1, j - 1, k - 1
        if a == 0:
            n.append(0.25 * (1 - xi * xi) * (1 + b * eta) * (1 + c * zeta))
        elif b == 0:
            n.append(0.25 * (1 - eta * eta) * (1 + a * xi) * (1 + c * zeta))
        else:
            n.append(0.25 * (1 - zeta * zeta) * (1 + a * xi) * (1 + b * eta))
    return n


# ----------------------------------------------------------------------------- CalculiX


def run_ccx(ccx, work, name, deck):
    path = os.path.join(work, name + ".inp")
    with open(path, "w") as f:
        f.write(deck)
    t0 = time.time()
    env = dict(os.environ, OMP_NUM_THREADS=os.environ.get("OMP_NUM_THREADS", "2"))
    r = subprocess.run([ccx, "-i", name], cwd=work, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=env,
                       text=True)
    seconds = time.time() - t0
    dat = os.path.join(work, name + ".dat")
    if r.returncode != 0 or "ERROR" in r.stdout or not os.path.exists(dat):
        sys.stderr.write(r.stdout[-3000:])
        sys.exit(f"error: CalculiX failed on {path} (exit {r.returncode})")
    disp = {}
    with open(dat) as f:
        for line in f:
            parts = line.split()
            if len(parts) == 4 and parts[0].isdigit():
                disp[int(parts[0])] = tuple(float(v) for v in parts[1:])
    return disp, seconds


# CalculiX reads each field of a card into 20 characters: numbers go as 13 significant digits
# (:.12e, at most 19 characters).


def nodes_block(grid):
    return "*NODE, NSET=NALL\n" + "".join(
        f"{i + 1}, " + ", ".join(f"{c:.12e}" for c in xyz) + ("\n" if len(xyz) == 3 else ", 0\n")
        for i, xyz in enumerate(grid.coords))


def elements_block(kind, elements):
    lines = [f"*ELEMENT, TYPE={kind}, ELSET=EALL\n"]
    for e, nodes in enumerate(elements, 1):
        ids = [str(e)] + [str(n) for n in nodes]
        # at most 16 entries on a line: continue on the next
        lines.append(", ".join(ids[:16]) + (",\n" + ", ".join(ids[16:]) if len(ids) > 16 else "") + "\n")
    return "".join(lines)


def material(p, thickness=None):
    section = f"*SOLID SECTION, ELSET=EALL, MATERIAL=M\n{thickness:.12e}\n" if thickness else \
        "*SOLID SECTION, ELSET=EALL, MATERIAL=M\n"
    return (f"*MATERIAL, NAME=M\n*ELASTIC\n{p['young']:.12e}, {p['poisson']:.12e}\n"
            f"*DENSITY\n{p.get('density', 1000.0):.12e}\n" + section)


def hex_mesh(planes, copy_of):
    """C3D20 elements on the grid; copy_of(cell, ijk) says whether that element uses the node's copy."""
    g = Grid(planes)
    elements = []
    nx, ny, nz = (len(p) - 1 for p in planes)
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                base = (2 * i, 2 * j, 2 * k)
                ids = []
                for loc in HEX_CORNERS + HEX_EDGES:
                    ijk = tuple(base[a] + loc[a] for a in range(3))
                    ids.append(g.node(ijk, copy_of((i, j, k), ijk)))
                elements.append(ids)
    return g, elements


# ----------------------------------------------------------------------------- problems


def cantilever(p, n, ccx, work):
    L, b, h = p["length"], p["width"], p["height"]
    planes = [planes_through(L, 20 * n, []), planes_through(b, n, []), planes_through(h, n, [])]
    g, elements = hex_mesh(planes, lambda cell, ijk: False)
    clamped = [i for (ijk, c), i in g.ids.items() if ijk[0] == 0]
    tip = [i for (ijk, c), i in g.ids.items() if ijk[0] == 2 * (len(planes[0]) - 1)]
    deck = (nodes_block(g) + elements_block("C3D20", elements) + material(p) +
            "*NSET, NSET=TIP\n" + "".join(f"{i},\n" for i in tip) +
            "*BOUNDARY\n" + "".join(f"{i}, 1, 3\n" for i in clamped) +
            "*STEP\n*STATIC\n*DLOAD\nEALL, GRAV, " + f"{p['gravity']:.12e}, 0, 0, -1\n" +
            "*NODE PRINT, NSET=TIP\nU\n*END STEP\n")
    disp, seconds = run_ccx(ccx, work, f"p3_{n}", deck)
    value = -sum(disp[i][2] for i in tip) / len(tip)
    return {"n": n, "values": [value], "dofs": 3 * len(g.coords), "seconds": seconds}


# With "front_grading" g != 1 the block's x and z planes crowd toward the crack front (the line
# x = cut_x, z = H - d) as (i / k)^g, as the plate's toward its tip (its cells are long along the
# front: y stays uniform). g = 2 took the reference's own error estimate from 0.32 % (uniform) to
# 0.12 % at levels 8-64 (observed order 1.15 -> 1.61) at nu 0.3; at nu 0.49 it is worse than uniform
# (1.6 % against 1.4 % at levels 8-32: thin fully integrated C3D20 cells lock), so the locking suite
# keeps the uniform grid.


def cut_block(p, n, ccx, work):
    L, B, H = p["size"]
    cut_x, depth, pull = p["cut_x"], p["depth"], p["pull"]
    front = H - depth
    grading = p.get("front_grading", 1.0)
    if grading == 1.0:
        planes = [planes_through(L, n, [cut_x]), planes_through(B, max(1, round(n * B / L)), []),
                  planes_through(H, max(2, round(n * H / L)), [front])]
    else:
        planes = [planes_toward(L, n, cut_x, grading), planes_through(B, max(1, round(n * B / L)), []),
                  planes_toward(H, max(2, round(n * H / L)), front, grading)]
    ic = planes[0].index(cut_x)  # the cut plane's index among the x planes
    kf = planes[2].index(front)

    def copy_of(cell, ijk):  # cells beyond the plane take the copies of its cut part's nodes
        return cell[0] >= ic and ijk[0] == 2 * ic and ijk[2] > 2 * kf

    g, elements = hex_mesh(planes, copy_of)
    nxh = 2 * (len(planes[0]) - 1)
    left = [i for (ijk, c), i in g.ids.items() if ijk[0] == 0]
    right = [i for (ijk, c), i in g.ids.items() if ijk[0] == nxh]
    samples = p["samples"]
    deck = (nodes_block(g) + elements_block("C3D20", elements) + material(p) +
            "*BOUNDARY\n" + "".join(f"{i}, 1, 1, {-pull:.12e}\n{i}, 2, 3\n" for i in left) +
            "".join(f"{i}, 1, 1, {pull:.12e}\n{i}, 2, 3\n" for i in right) +
            "*STEP\n*STATIC\n*NODE PRINT, NSET=NALL\nU\n*END STEP\n")
    disp, seconds = run_ccx(ccx, work, f"p5_{n}", deck)
    values = []
    for (x, y, z) in samples:
        cell, local = [], []
        for a, c in enumerate((x, y, z)):
            pl = planes[a]
            k = max(0, min(len(pl) - 2, next((m for m in range(len(pl) - 1) if c < pl[m + 1]), len(pl) - 2)))
            cell.append(k)
            local.append(2 * (c - pl[k]) / (pl[k + 1] - pl[k]) - 1)
        base = [2 * c for c in cell]
        shape = hex20_shape(*local)
        u = [0.0, 0.0, 0.0]
        for s, loc in zip(shape, HEX_CORNERS + HEX_EDGES):
            ijk = tuple(base[a] + loc[a] for a in range(3))
            d = disp[g.ids[(ijk, copy_of(tuple(cell), ijk))]]
            for a in range(3):
                u[a] += s * d[a]
        values += u
    return {"n": n, "values": values, "dofs": 3 * len(g.coords), "seconds": seconds}


# The plate's planes crowd toward the crack tip: the planes of a uniform grid moved to
# mark +- d max((i / k)^TIP_GRADING, SMALLEST_CELL i / k). A uniform grid resolves the tip's sqrt(r)
# field at order 1 only, and extrapolating order-1 levels left an error estimate (0.05 %) that
# rested on that order alone; graded grids converge at the order 3-3.5 observed (levels 10-80,
# a / W 0.2 and 0.5) to the same value within 0.006 % (docs/BENCHMARKS.md, accuracy suite). The
# cells next to the tip stay at least SMALLEST_CELL of a uniform cell: at 6e-5 of it (grading 4 at
# level 80, grading 3 at level 160) CalculiX found the long thin cells' Jacobian nonpositive.
TIP_GRADING = 3.0
SMALLEST_CELL = 1e-3


def planes_toward(length, cells, mark, grading=TIP_GRADING):
    """`cells` cells over [0, length], `mark` a plane, each side's planes crowded toward it."""
    out = {0.0, length, mark}
    for lo, hi in ((0.0, mark), (mark, length)):
        k = max(1, round(cells * (hi - lo) / length))
        for i in range(1, k):
            t = max((i / k) ** grading, SMALLEST_CELL * i / k)
            out.add(mark - t * (mark - lo) if hi == mark else mark + t * (hi - mark))
    return sorted(out)


# CalculiX expands each 2D element into a layer of 3D elements as thick as its section, so CPS8 is
# plane stress only as that thickness goes to zero against the field's gradients: near the crack tip
# the layer's faces hold each other and the plate is stiffer. The plate's CMOD at a / W = 0.5
# (levels 10-80, graded), the section t against the limit as t -> 0 (3.95237e-7 m): t = W / 40 (the
# plate's own 1 mm) -0.176 %, W / 400 -0.017 %, W / 4000 -0.0015 %, W / 13000 -0.0005 %; thinner
# still (W / 4e5) the flat elements lose the convergence (order 2.5, then 1, irregular). A
# plane-stress CMOD does not depend on the thickness (the loads scale with it), so the deck's
# section is this fraction of W. The suite's engine runs, which are plane stress, converge to the
# thin limit: the snapping cutter's levels 160-640 at order 1.006 to 0.013 % from it.
PLANE_STRESS_SECTION = 1e-4


def edge_crack(p, n, ccx, work):
    W, H, a = p["width"], p["height"], p["crack"]
    planes = [planes_toward(W, n, a), planes_toward(H, 3 * n if 3 * n % 2 == 0 else 3 * n + 1, H / 2)]
    ia, jc = planes[0].index(a), planes[1].index(H / 2)
    g = Grid(planes)
    elements = []
    for i in range(len(planes[0]) - 1):
        for j in range(len(planes[1]) - 1):
            ids = []
            for loc in QUAD_LOCAL:
                ij = (2 * i + loc[0], 2 * j + loc[1])
                ids.append(g.node(ij, copy=(j >= jc and ij[1] == 2 * jc and ij[0] < 2 * ia)))
            elements.append(ids)
    top, bottom = 2 * (len(planes[1]) - 1), 0
    loads = {}
    t, sigma = p.get("section_fraction", PLANE_STRESS_SECTION) * W, p["stress"]
    for j, sign in ((top, 1.0), (bottom, -1.0)):  # consistent loads of a quadratic edge: 1/6, 2/3, 1/6
        for i in range(len(planes[0]) - 1):
            le = planes[0][i + 1] - planes[0][i]
            for off, w in ((0, 1 / 6), (1, 2 / 3), (2, 1 / 6)):
                node = g.ids[((2 * i + off, j), False)]
                loads[node] = loads.get(node, 0.0) + sign * sigma * t * le * w
    nxh = 2 * (len(planes[0]) - 1)
    hold, corner = g.ids[((nxh, 2 * jc), False)], g.ids[((nxh, 0), False)]
    mouth_low, mouth_up = g.ids[((0, 2 * jc), False)], g.ids[((0, 2 * jc), True)]
    deck = (nodes_block(g) + elements_block("CPS8", elements) + material(p, t) +
            f"*BOUNDARY\n{hold}, 1, 2\n{corner}, 1, 1\n" +
            "*NSET, NSET=MOUTH\n" + f"{mouth_low},\n{mouth_up},\n" +
            "*STEP\n*STATIC\n*CLOAD\n" + "".join(f"{node}, 2, {f:.12e}\n" for node, f in sorted(loads.items())) +
            "*NODE PRINT, NSET=MOUTH\nU\n*END STEP\n")
    disp, seconds = run_ccx(ccx, work, f"p6_{n}", deck)
    return {"n": n, "values": [disp[mouth_up][1] - disp[mouth_low][1]], "dofs": 2 * len(g.coords), "seconds": seconds}


def cook_point(p, xi, eta):
    """Cook's membrane's map from the unit square: straight lines in xi and eta stay straight."""
    s = p["scale"]
    return (48.0 * s * xi, s * (44.0 * xi + eta * (44.0 - 28.0 * xi)))


def cook_membrane(p, n, ccx, work):
    unit = planes_through(1.0, n, [])
    g = Grid([unit, unit])
    elements = []
    for i in range(n):
        for j in range(n):
            elements.append([g.node((2 * i + loc[0], 2 * j + loc[1])) for loc in QUAD_LOCAL])
    g.coords = [cook_point(p, xi, eta) for (xi, eta) in g.coords]
    loads, right = {}, 2 * n
    edge = p["load"] / n  # the right edge's cells are equally long: each carries F / n
    for j in range(n):  # consistent loads of a quadratic edge: 1/6, 2/3, 1/6
        for off, w in ((0, 1 / 6), (1, 2 / 3), (2, 1 / 6)):
            node = g.ids[((right, 2 * j + off), False)]
            loads[node] = loads.get(node, 0.0) + edge * w
    clamped = [i for (ij, c), i in g.ids.items() if ij[0] == 0]
    corner = g.ids[((right, 2 * n), False)]
    deck = (nodes_block(g) + elements_block("CPE8R", elements) + material(p, p["thickness"]) +
            "*BOUNDARY\n" + "".join(f"{i}, 1, 2\n" for i in clamped) +
            f"*NSET, NSET=CORNER\n{corner},\n" +
            "*STEP\n*STATIC\n*CLOAD\n" + "".join(f"{node}, 2, {f:.12e}\n" for node, f in sorted(loads.items())) +
            "*NODE PRINT, NSET=CORNER\nU\n*END STEP\n")
    disp, seconds = run_ccx(ccx, work, f"p14_{n}", deck)
    return {"n": n, "values": [disp[corner][1]], "dofs": 2 * len(g.coords), "seconds": seconds}


PROBLEMS = {3: cantilever, 5: cut_block, 6: edge_crack, 14: cook_membrane}


def norm(v):
    return math.sqrt(sum(x * x for x in v))


def richardson(fine, coarse, ratio, p):
    return [f + (f - c) / (ratio ** p - 1) for f, c in zip(fine, coarse)]


def observed_order(v, n, k):
    """The order observed over levels k-2, k-1, k (clamped to [0.5, 4]; 1 if not converging)."""
    d_fine = norm([x - y for x, y in zip(v[k], v[k - 1])])
    d_coarse = norm([x - y for x, y in zip(v[k - 1], v[k - 2])])
    if not (d_fine > 0 and d_coarse > d_fine):
        return 1.0
    return max(0.5, min(4.0, math.log(d_coarse / d_fine) / math.log(n[k - 1] / n[k - 2])))


def estimate(levels):
    """The reference values, their relative error estimate and the observed order of convergence:
    Richardson's extrapolation of the two finest levels with the order observed over the last three
    (a crack tip's singular field converges at about p = 1 on uniform meshes). Its error is estimated
    by the distance to the same extrapolation one level coarser (with the order observed there), or,
    with three levels only, by the size of the extrapolation's correction; with two, the finest
    level is the reference and their distance over 2^1 - 1 its error."""
    v = [lv["values"] for lv in levels]
    n = [lv["n"] for lv in levels]
    scale = max(norm(v[-1]), 1e-300)
    if len(levels) < 3:
        return v[-1], norm([x - y for x, y in zip(v[-1], v[-2])]) / (n[-1] / n[-2] - 1) / scale, 1.0
    k = len(levels) - 1
    p = observed_order(v, n, k)
    value = richardson(v[k], v[k - 1], n[k] / n[k - 1], p)
    if len(levels) == 3:
        return value, norm([x - y for x, y in zip(value, v[k])]) / scale, p
    previous = richardson(v[k - 1], v[k - 2], n[k - 1] / n[k - 2], observed_order(v, n, k - 1))
    return value, norm([x - y for x, y in zip(value, previous)]) / scale, p


def main(argv):
    if len(argv) < 5:
        sys.exit(__doc__)
    problem = int(argv[1])
    if problem not in PROBLEMS:
        print(f"error: problem {problem}: CalculiX references exist for 3, 5, 6 and 14", file=sys.stderr)
        sys.exit(2)
    with open(argv[2]) as f:
        params = json.load(f)
    levels = [int(v) for v in argv[3].split(",")]
    if len(levels) < 2 or levels != sorted(levels) or levels[0] < 1:
        print(f"error: levels {argv[3]}: two or more, increasing", file=sys.stderr)
        sys.exit(2)
    ccx = argv[argv.index("--ccx") + 1] if "--ccx" in argv else "ccx"
    with tempfile.TemporaryDirectory() as tmp:
        work = argv[argv.index("--work") + 1] if "--work" in argv else tmp
        results = []
        for n in levels:
            results.append(PROBLEMS[problem](params, n, ccx, work))
            print(f"problem {problem} level {n}: {results[-1]['dofs']} DOFs, {results[-1]['seconds']:.1f} s",
                  file=sys.stderr)
    values, err, order = estimate(results)
    solver = {6: "CPS8", 14: "CPE8R"}.get(problem, "C3D20")
    out = {"problem": problem, "solver": "CalculiX " + solver, "levels": results,
           "values": values, "error_estimate": err, "observed_order": order}
    with open(argv[4], "w") as f:
        json.dump(out, f, indent=1)
    print(f"problem {problem}: reference from levels {argv[3]} (Richardson, order {order:.2f} observed); its relative "
          f"error estimate {100 * err:.3g} %", file=sys.stderr)


if __name__ == "__main__":
    main(sys.argv)
