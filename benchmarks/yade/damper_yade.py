# Yade script of pdamper's benchmark damper: `yade -n -x damper_yade.py PARAMS.json`
# (written and run by yade_damper.py beside this file, which reads the JSON it writes).
# Not importable outside Yade: it uses the globals Yade gives a script (O, FrictMat, ...).
# ruff: noqa: F821
#
# mode "damper": 32 steel spheres in the PVC box 40 x 40 x 120 mm (six infinite walls,
#   moved as one rigid box), Hertz-Mindlin with Tsuji's viscous damping from the COR
#   (Ip2_FrictMat_FrictMat_MindlinPhys en/es, Law2_ScGeom_MindlinPhys_Mindlin), gravity;
#   settling, then the box moved as x_c = X sin(2 pi f t); writes the particles' mean
#   vertical force on the container over each window of `nout` steps.
# mode "impact": one normal impact (sphere on the floor, or two spheres head-on), no
#   gravity; writes the rebound COR.
import json
import math
import sys

from yade import pack, utils

P = json.load(open(sys.argv[1]))
ids = {}


def materials():
    steel = O.materials.append(FrictMat(young=P["E_p"], poisson=P["nu_p"], density=P["rho_p"],
                                        frictionAngle=math.atan(P["mu"]), label="steel"))
    wall = O.materials.append(FrictMat(young=P["E_w"], poisson=P["nu_w"], density=P["rho_w"],
                                       frictionAngle=math.atan(P["mu"]), label="wall"))
    cor = MatchMaker(matches=((steel, steel, P["epp"]), (steel, wall, P["epw"]),
                              (wall, wall, P["epw"])))
    return steel, wall, cor


def engines(cor, extra=(), gravity=(0.0, 0.0, 0.0)):
    O.engines = [
        ForceResetter(),
        InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()]),
        InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom()],
                        [Ip2_FrictMat_FrictMat_MindlinPhys(en=cor, es=cor)],
                        [Law2_ScGeom_MindlinPhys_Mindlin()]),
        *extra,
        # no local (numerical) damping: all dissipation is the contact law's
        NewtonIntegrator(damping=0.0, gravity=gravity),
    ]


def impact():
    steel, wall, cor = materials()
    r, v = P["radius"], P["velocity"]
    engines(cor)
    O.dt = P["dt"]
    if P["pair"] == "wall":
        O.bodies.append(utils.wall(0.0, axis=2, sense=1, material=wall))
        a = O.bodies.append(utils.sphere((0, 0, r + 1e-7), r, material=steel))
        O.bodies[a].state.vel = (0, 0, -v)
        b = None
    else:
        a = O.bodies.append(utils.sphere((0, 0, 0), r, material=steel))
        b = O.bodies.append(utils.sphere((0, 0, 2 * r + 1e-7), r, material=steel))
        O.bodies[a].state.vel = (0, 0, 0.5 * v)
        O.bodies[b].state.vel = (0, 0, -0.5 * v)
    touched = False
    for _ in range(10 ** 6):
        O.step()
        if len([i for i in O.interactions if i.isReal]):
            touched = True
        elif touched:
            break
    va = O.bodies[a].state.vel[2]
    e = (O.bodies[b].state.vel[2] - va) / v if b is not None else va / v
    json.dump({"cor": e, "steps": O.iter}, open(P["out"], "w"))


def damper():
    steel, wall, cor = materials()
    lx, ly, lz = P["box"]
    r = P["radius"]
    walls = [O.bodies.append(utils.wall(pos, axis=ax, sense=s, material=wall))
             for pos, ax, s in ((0.0, 0, 1), (lx, 0, -1), (0.0, 1, 1), (ly, 1, -1),
                                (0.0, 2, 1), (lz, 2, -1))]
    if P["positions"] is not None:
        spheres = [O.bodies.append(utils.sphere(tuple(p), r, material=steel))
                   for p in P["positions"]]
    else:  # a random cloud, no overlaps, seeded
        sp = pack.SpherePack()
        n = sp.makeCloud((0, 0, 0), (lx, ly, lz), rMean=r, rRelFuzz=0.0, num=P["count"],
                         seed=P["seed"])
        if n != P["count"]:
            raise RuntimeError(f"makeCloud placed {n} of {P['count']} spheres")
        spheres = [O.bodies.append(utils.sphere(c, r, material=steel)) for c, _ in sp]
    dt, nout = P["dt"], P["nout"]
    w = 2.0 * math.pi * P["freq"]
    # the box's velocity, set before each step's position update (t0: the excitation's start)
    shake = HarmonicMotionEngine(A=(0, 0, 0), f=(0, 0, 0), fi=(0, 0, 0), ids=walls, dead=True)
    win = {"acc": 0.0, "n": 0, "rows": [], "p": []}
    mass = sum(O.bodies[i].state.mass for i in spheres)

    def record():  # "forces": after each step's forces, the particles' force on the walls
        win["acc"] += sum(O.forces.f(i)[2] for i in walls)
        win["n"] += 1
        if win["n"] == nout:
            win["rows"].append((O.iter - start + 1, win["acc"] / nout))
            win["acc"], win["n"] = 0.0, 0

    def momentum():  # "momentum": every nout steps, after the velocity update
        win["p"].append((O.iter - start, sum(O.bodies[i].state.mass * O.bodies[i].state.vel[2]
                                             for i in spheres)))

    # PyRunner commands run in the script's globals
    globals()["record"], globals()["momentum"] = record, momentum
    if P["force"] == "forces":
        rec = PyRunner(command="record()", iterPeriod=1, dead=True)
        extra = (rec, shake)
    else:
        # The walls' force summed over a window is minus the spheres' momentum change less
        # gravity's impulse (the contacts between spheres cancel): the same sum as "forces"
        # (the force of each step enters the velocity update once), at the cost of one
        # Python call per window instead of per step.
        rec = PyRunner(command="momentum()", iterPeriod=nout, initRun=True, dead=True)
        extra = (shake,)
    engines(cor, extra=extra, gravity=(0.0, 0.0, -P["g"]))
    if P["force"] != "forces":
        O.engines = O.engines + [rec]
    O.dt = dt
    O.run(P["nsettle"], True)
    start = O.iter
    t0 = O.time  # HarmonicMotionEngine: v = -A w sin(w t + fi); with the velocity of the
    # step's midpoint, x_c = A sin(w (t - t0)) at the step ends (leapfrog)
    shake.A = (0, 0, P["amp"])
    shake.f = (0, 0, P["freq"])
    shake.fi = (0, 0, -0.5 * math.pi - w * (t0 - 0.5 * dt))
    shake.dead = rec.dead = False
    # "momentum" records after the step: one more step gives the last window's end
    O.run(P["nrun"] + (P["force"] != "forces"), True)
    if P["force"] != "forces":
        it = [k for k, _ in win["p"]]
        if it[0] != 0 or any(b - a != nout for a, b in zip(it, it[1:], strict=False)):
            raise RuntimeError(f"momentum records not every {nout} steps: {it[:4]}")
        win["rows"] = [(k, -(pb - pa) / (nout * dt) - mass * P["g"])
                       for (_, pa), (k, pb) in zip(win["p"], win["p"][1:], strict=False)]
    json.dump({"windows": win["rows"], "nsettle": start, "dt": dt,
               "box_z_end": O.bodies[walls[4]].state.pos[2],
               "box_z_expected": P["amp"] * math.sin(w * (O.time - t0))},
              open(P["out"], "w"))


if P["mode"] == "impact":
    impact()
else:
    damper()
O.exitNoBacktrace()
