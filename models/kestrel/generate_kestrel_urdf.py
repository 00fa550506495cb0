#!/usr/bin/env python3
"""Generates models/kestrel/kestrel.urdf and its meshes in models/kestrel/meshes/.

Kestrel is a humanoid designed by the Plantar project (not a real robot) whose kinematics
differ from the HRP-2-like model's on purpose, to show that Plantar runs any humanoid:

* leg chain from the pelvis: hip PITCH (y) -> hip ROLL (x) -> hip YAW (z) -> knee (y) ->
  ankle pitch (y) -> ankle roll (x); the hip axes do not meet (the roll axis is 0.025 m
  below the pitch axis), the knee is 0.02 m forward of the hip, the ankle 0.015 m behind
  the knee, the ankle roll axis 0.015 m below the ankle pitch axis: HRP-2's closed-form leg
  IK does not apply (a numerical IK is needed);
* 40 kg, heavier torso and lighter legs than HRP-2's proportions; smaller feet
  (0.20 x 0.11 m soles) whose centre is 0.02 m ahead of the ankle;
* no sole links: the scene places the sole frame on `r_foot` / `l_foot` (SOLE_IN_FOOT);
* visuals are triangle meshes (binary STL, ASCII STL, Wavefront OBJ), written by this
  script into meshes/, referenced relative to the URDF; collisions are boxes/cylinders
  (the shapes whose inertias the links carry).

Run:  /usr/bin/python3 models/kestrel/generate_kestrel_urdf.py
It writes kestrel.urdf and meshes/* next to itself (deterministic output) and prints to
stderr the total mass, the CoM heights and the sole placement quoted in
docs/kestrel_model.md. Standard library only.
"""
import math
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
MESH_DIR = "meshes"

# ------------------------------------------------------------------------------ geometry
# All lengths in m. Frames: x forward, y left, z up; every link frame is parallel to the
# pelvis frame at q = 0 (legs nearly straight, arms hanging).
HIP_Y = 0.07            # pelvis centre to each hip-pitch joint, lateral
HIP_Z = -0.06           # hip-pitch axis below the pelvis origin
HIP_PITCH_TO_ROLL = 0.025   # hip-roll axis below the hip-pitch axis (axes do not meet)
HIP_ROLL_TO_YAW = 0.03      # hip-yaw joint origin below the hip-roll axis
THIGH = 0.26            # hip-pitch axis to knee axis, vertical
KNEE_X = 0.02           # knee axis ahead of the hip-pitch joint
SHANK = 0.26            # knee axis to ankle-pitch axis, vertical
ANKLE_X = -0.015        # ankle-pitch axis behind the knee axis
ANKLE_PITCH_TO_ROLL = 0.015  # ankle-roll axis below the ankle-pitch axis
ANKLE_H = 0.07          # ankle-pitch axis above the sole's bottom face
SOLE_L, SOLE_W = 0.20, 0.11  # sole (foot) size
SOLE_DX = 0.02          # sole centre ahead of the ankle axes
FOOT_T = 0.035          # foot plate thickness
# Sole frame (centre of the sole's bottom face, axes parallel to the foot link) in the
# r_foot / l_foot frame (origin on the ankle-roll axis), rpy = 0. NOT in the URDF.
SOLE_IN_FOOT = (SOLE_DX, 0.0, -(ANKLE_H - ANKLE_PITCH_TO_ROLL))

TORSO_PITCH_Z = 0.08    # torso-pitch axis above the pelvis origin
TORSO_YAW_Z = 0.05      # torso-yaw joint above the torso-pitch axis (chest origin)
NECK_Z = 0.34           # neck-yaw joint above the chest origin
NECK_PITCH_Z = 0.05     # neck-pitch axis above the neck-yaw joint
SHOULDER = (0.0, 0.175, 0.26)  # shoulder-pitch joint in the chest frame (left; right mirrored)
SHOULDER_ROLL_Y = 0.03  # shoulder-roll axis outboard of the shoulder-pitch joint
SHOULDER_YAW_Z = 0.04   # shoulder-yaw joint below the shoulder-roll axis
UPPER_ARM = 0.16        # shoulder-yaw joint to elbow axis (0.20 m from the roll axis)
ELBOW_X = 0.01          # elbow axis ahead of the upper-arm axis
FOREARM = 0.17          # elbow axis to wrist-yaw joint

DEG = math.pi / 180.0


# ------------------------------------------------------------------------------ inertias
def box_inertia(m, a, b, c):
    """Diagonal inertia of a solid box a x b x c (along x, y, z) about its centre."""
    return [[m * (b * b + c * c) / 12.0, 0, 0], [0, m * (a * a + c * c) / 12.0, 0],
            [0, 0, m * (a * a + b * b) / 12.0]]


def cyl_inertia(m, r, h, axis="z"):
    """Solid cylinder of radius r, length h, axis along `axis`, about its centre."""
    perp = m * (3 * r * r + h * h) / 12.0
    along = m * r * r / 2.0
    d = {"x": (along, perp, perp), "y": (perp, along, perp), "z": (perp, perp, along)}[axis]
    return [[d[0], 0, 0], [0, d[1], 0], [0, 0, d[2]]]


def composite(parts):
    """Mass, CoM and inertia about the CoM of rigid parts (m, centre, inertia about centre)."""
    m = sum(p[0] for p in parts)
    c = [sum(p[0] * p[1][i] for p in parts) / m for i in range(3)]
    I = [[0.0] * 3 for _ in range(3)]
    for pm, pc, pI in parts:
        d = [pc[i] - c[i] for i in range(3)]
        dd = sum(x * x for x in d)
        for i in range(3):
            for j in range(3):
                I[i][j] += pI[i][j] + pm * ((dd if i == j else 0.0) - d[i] * d[j])
    return m, c, I


# --------------------------------------------------------------------------------- meshes
def box_mesh(a, b, c):
    """Closed box a x b x c centred at the origin: 8 vertices, 12 outward triangles."""
    v = [((i & 1) * a - a / 2, ((i >> 1) & 1) * b - b / 2, ((i >> 2) & 1) * c - c / 2) for i in range(8)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    f = []
    for q in quads:
        f += [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
    return v, f


def revolve_mesh(rings, n):
    """Closed solid of revolution about z. rings: (z, radius) from top to bottom; a ring of
    radius 0 is a pole. n sides (a multiple of 4: the extremes lie on the x and y axes)."""
    v, idx = [], []
    for z, r in rings:
        if r == 0.0:
            idx.append([len(v)] * n)
            v.append((0.0, 0.0, z))
        else:
            idx.append(list(range(len(v), len(v) + n)))
            v += [(r * math.cos(2 * math.pi * k / n), r * math.sin(2 * math.pi * k / n), z) for k in range(n)]
    f = []
    for a, b in zip(idx[:-1], idx[1:]):  # a above b; outward = counter-clockwise seen from outside
        for k in range(n):
            k1 = (k + 1) % n
            for t in ((a[k], b[k], b[k1]), (a[k], b[k1], a[k1])):
                if len(set(t)) == 3:
                    f.append(t)
    return v, f


def cylinder_mesh(r, h, n=16):
    return revolve_mesh([(h / 2, 0.0), (h / 2, r), (-h / 2, r), (-h / 2, 0.0)], n)


def capsule_mesh(r, length, n=12, rings=3):
    """Capsule of radius r and total length (tip to tip) `length`, axis z, centred."""
    h = length / 2 - r
    top = [(h + r * math.cos(0.5 * math.pi * k / rings), r * math.sin(0.5 * math.pi * k / rings)) for k in range(rings + 1)]
    bottom = [(-z, rr) for z, rr in reversed(top)]
    return revolve_mesh(top + bottom, n)


def normal(v, t):
    a, b, c = (v[i] for i in t)
    u = [b[i] - a[i] for i in range(3)]
    w = [c[i] - a[i] for i in range(3)]
    n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
    s = math.sqrt(sum(x * x for x in n)) or 1.0
    return [x / s for x in n]


def signed_volume(v, f):
    vol = 0.0
    for t in f:
        a, b, c = (v[i] for i in t)
        vol += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0
    return vol


def write_mesh(name, mesh, fmt, expected_volume):
    v, f = mesh
    vol = signed_volume(v, f)
    # Self-check: closed and outward (volume > 0), close to the solid's volume.
    assert vol > 0 and abs(vol / expected_volume - 1.0) < 0.2, (name, vol, expected_volume)
    path = os.path.join(HERE, MESH_DIR, name)
    solid = "kestrel_" + os.path.splitext(name)[0]
    if fmt == "stl-binary":
        header = ("%s: generated by models/kestrel/generate_kestrel_urdf.py, metres" % solid).encode()
        data = bytearray(header.ljust(80, b" ")[:80])
        data += struct.pack("<I", len(f))
        for t in f:
            data += struct.pack("<12fH", *normal(v, t), *v[t[0]], *v[t[1]], *v[t[2]], 0)
        with open(path, "wb") as out:
            out.write(bytes(data))
    elif fmt == "stl-ascii":
        lines = ["solid " + solid]
        for t in f:
            lines.append("  facet normal %.6g %.6g %.6g" % tuple(normal(v, t)))
            lines.append("    outer loop")
            lines += ["      vertex %.6g %.6g %.6g" % v[i] for i in t]
            lines.append("    endloop")
            lines.append("  endfacet")
        lines.append("endsolid " + solid)
        with open(path, "w") as out:
            out.write("\n".join(lines) + "\n")
    else:  # Wavefront OBJ, 1-based indices, counter-clockwise = outward
        lines = ["# %s: generated by models/kestrel/generate_kestrel_urdf.py, metres" % solid, "o " + solid]
        lines += ["v %.6g %.6g %.6g" % p for p in v]
        lines += ["f %d %d %d" % (t[0] + 1, t[1] + 1, t[2] + 1) for t in f]
        with open(path, "w") as out:
            out.write("\n".join(lines) + "\n")
    return os.path.getsize(path)


# name -> (mesh, format, volume of the ideal solid): the meshes, in their own frames
# (centred; cylinders and capsules along their z). "bracket.stl" is a unit cube that the
# URDF scales.
def capsule_volume(r, length):
    return math.pi * r * r * (length - 2 * r) + 4.0 / 3.0 * math.pi * r ** 3


MESHES = {
    "pelvis.stl": (box_mesh(0.16, 0.24, 0.12), "stl-binary", 0.16 * 0.24 * 0.12),
    "chest.stl": (box_mesh(0.18, 0.28, 0.30), "stl-binary", 0.18 * 0.28 * 0.30),
    "foot.stl": (box_mesh(SOLE_L, SOLE_W, FOOT_T), "stl-binary", SOLE_L * SOLE_W * FOOT_T),
    "motor.stl": (cylinder_mesh(0.04, 0.07), "stl-binary", math.pi * 0.04 ** 2 * 0.07),
    "bracket.stl": (box_mesh(1.0, 1.0, 1.0), "stl-ascii", 1.0),
    "battery.stl": (box_mesh(0.08, 0.20, 0.12), "stl-ascii", 0.08 * 0.20 * 0.12),
    "hand.stl": (box_mesh(0.04, 0.07, 0.10), "stl-ascii", 0.04 * 0.07 * 0.10),
    "thigh.obj": (capsule_mesh(0.045, 0.24), "obj", capsule_volume(0.045, 0.24)),
    "shank.obj": (capsule_mesh(0.038, 0.26), "obj", capsule_volume(0.038, 0.26)),
    "upper_arm.obj": (capsule_mesh(0.035, 0.18), "obj", capsule_volume(0.035, 0.18)),
    "forearm.obj": (capsule_mesh(0.03, 0.18), "obj", capsule_volume(0.03, 0.18)),
    "head.obj": (capsule_mesh(0.07, 0.16), "obj", capsule_volume(0.07, 0.16)),
    "waist.obj": (cylinder_mesh(0.05, 0.12), "obj", math.pi * 0.05 ** 2 * 0.12),
    "neck.obj": (cylinder_mesh(0.025, 0.05), "obj", math.pi * 0.025 ** 2 * 0.05),
}

# ----------------------------------------------------------------------------- the robot
LINKS = {}   # name -> dict(mass, com, inertia, comment, visuals, collisions)
JOINTS = []  # (name, parent, child, xyz, axis, lower, upper, effort, velocity, comment)
ROT_Y = (math.pi / 2, 0.0, 0.0)  # rpy that lays a z-axis cylinder along y


def link(name, mass, com, inertia, comment, visuals, collisions):
    """visuals: [(mesh file, scale or None, xyz, rpy)]; collisions: [(shape, size, xyz, rpy)]
    with shape "box" (size x y z) or "cylinder" (radius, length)."""
    LINKS[name] = dict(mass=mass, com=com, inertia=inertia, comment=comment, visuals=visuals,
                       collisions=collisions)


def joint(name, parent, child, xyz, axis, lim, effort, vel, comment):
    JOINTS.append((name, parent, child, xyz, axis, lim[0], lim[1], effort, vel, comment))


# Masses (kg). Total 40.0: pelvis 6.7, legs 4.75 each, waist + chest 16.6, neck + head 1.8,
# arms 2.7 each.
M = {"pelvis": 6.7, "hip": 0.35, "hip_bracket": 0.35, "thigh": 1.9, "shank": 1.2, "ankle": 0.25,
     "foot": 0.7, "waist": 0.6, "chest_shell": 12.0, "battery": 4.0, "neck": 0.3, "head": 1.5,
     "shoulder": 0.35, "shoulder_bracket": 0.3, "upper_arm": 1.0, "forearm": 0.7, "hand": 0.35}

link("pelvis", M["pelvis"], (0.0, 0.0, 0.0), box_inertia(M["pelvis"], 0.16, 0.24, 0.12),
     "pelvis: box 0.16 x 0.24 x 0.12 m centred on the origin",
     [("pelvis.stl", None, (0, 0, 0), (0, 0, 0))], [("box", (0.16, 0.24, 0.12), (0, 0, 0), (0, 0, 0))])

# Legs. Limits (rad) for the right leg; the left leg mirrors roll and yaw.
# Signs: hip pitch < 0 swings the thigh forward; knee > 0 bends it (shank backwards);
# ankle pitch < 0 lifts the toes (dorsiflexion), > 0 points them; right hip roll < 0 and
# right hip yaw < 0 turn the leg outwards.
LEG_LIM_R = {"hip_pitch": (-2.0, 0.5), "hip_roll": (-0.6, 0.35), "hip_yaw": (-0.7, 0.4),
             "knee": (0.0, 2.4), "ankle_pitch": (-0.9, 0.7), "ankle_roll": (-0.35, 0.45)}
LEG_EFFORT = {"hip_pitch": 120, "hip_roll": 100, "hip_yaw": 60, "knee": 150, "ankle_pitch": 100,
              "ankle_roll": 60}
LEG_VEL = {"hip_pitch": 7.0, "hip_roll": 6.0, "hip_yaw": 6.0, "knee": 8.0, "ankle_pitch": 7.0,
           "ankle_roll": 6.0}
MIRRORED = ("hip_roll", "hip_yaw", "ankle_roll", "shoulder_roll", "shoulder_yaw", "wrist_yaw")


def limits(table, key, s):
    lo, hi = table[key]
    return (-hi, -lo) if (s > 0 and key in MIRRORED) else (lo, hi)


BRACKET_HIP = (0.08, 0.06, 0.05)
BRACKET_ANKLE = (0.05, 0.06, 0.045)
THIGH_CAPSULE = (0.045, 0.24, (KNEE_X / 2, 0.0, -0.11))  # radius, length, centre in r_thigh
SHANK_CAPSULE = (0.038, 0.26, (ANKLE_X / 2, 0.0, -SHANK / 2))
FOOT_CENTRE = (SOLE_DX, 0.0, SOLE_IN_FOOT[2] + FOOT_T / 2)
for s, p in ((-1.0, "r_"), (1.0, "l_")):
    side = "right" if s < 0 else "left"
    link(p + "hip", M["hip"], (0, 0, 0), cyl_inertia(M["hip"], 0.04, 0.07, "y"),
         "%s hip-pitch motor: cylinder r 0.04 m, 0.07 m, along y" % side,
         [("motor.stl", None, (0, 0, 0), ROT_Y)], [("cylinder", (0.04, 0.07), (0, 0, 0), ROT_Y)])
    bc = (0.0, 0.0, -0.01)
    link(p + "hip_bracket", M["hip_bracket"], bc, box_inertia(M["hip_bracket"], *BRACKET_HIP),
         "%s hip roll-yaw bracket: box 0.08 x 0.06 x 0.05 m" % side,
         [("bracket.stl", BRACKET_HIP, bc, (0, 0, 0))], [("box", BRACKET_HIP, bc, (0, 0, 0))])
    r, L, c = THIGH_CAPSULE
    link(p + "thigh", M["thigh"], c, cyl_inertia(M["thigh"], r, L),
         "%s thigh: cylinder r %.3f m, %.2f m (drawn as a capsule)" % (side, r, L),
         [("thigh.obj", None, c, (0, 0, 0))], [("cylinder", (r, L), c, (0, 0, 0))])
    r, L, c = SHANK_CAPSULE
    link(p + "shank", M["shank"], c, cyl_inertia(M["shank"], r, L),
         "%s shank: cylinder r %.3f m, %.2f m (drawn as a capsule)" % (side, r, L),
         [("shank.obj", None, c, (0, 0, 0))], [("cylinder", (r, L), c, (0, 0, 0))])
    ac = (0.0, 0.0, -0.0125)  # from 0.01 m above the pitch axis down to the foot plate's top
    link(p + "ankle", M["ankle"], ac, box_inertia(M["ankle"], *BRACKET_ANKLE),
         "%s ankle pitch-roll bracket: box 0.05 x 0.06 x 0.045 m" % side,
         [("bracket.stl", BRACKET_ANKLE, ac, (0, 0, 0))], [("box", BRACKET_ANKLE, ac, (0, 0, 0))])
    link(p + "foot", M["foot"], FOOT_CENTRE, box_inertia(M["foot"], SOLE_L, SOLE_W, FOOT_T),
         "%s foot plate: box %.2f x %.2f x %.3f m, bottom face = the sole (0.02 m ahead of the ankle)" % (side, SOLE_L, SOLE_W, FOOT_T),
         [("foot.stl", None, FOOT_CENTRE, (0, 0, 0))], [("box", (SOLE_L, SOLE_W, FOOT_T), FOOT_CENTRE, (0, 0, 0))])
    lim = lambda k: limits(LEG_LIM_R, k, s)  # noqa: E731
    joint(p + "hip_pitch", "pelvis", p + "hip", (0.0, s * HIP_Y, HIP_Z), (0, 1, 0), lim("hip_pitch"),
          LEG_EFFORT["hip_pitch"], LEG_VEL["hip_pitch"], "hip pitch: %.3f m lateral, %.3f m below the pelvis origin" % (HIP_Y, -HIP_Z))
    joint(p + "hip_roll", p + "hip", p + "hip_bracket", (0.0, 0.0, -HIP_PITCH_TO_ROLL), (1, 0, 0), lim("hip_roll"),
          LEG_EFFORT["hip_roll"], LEG_VEL["hip_roll"], "hip roll: %.3f m below the hip-pitch axis (the axes do not meet)" % HIP_PITCH_TO_ROLL)
    joint(p + "hip_yaw", p + "hip_bracket", p + "thigh", (0.0, 0.0, -HIP_ROLL_TO_YAW), (0, 0, 1), lim("hip_yaw"),
          LEG_EFFORT["hip_yaw"], LEG_VEL["hip_yaw"], "hip yaw: %.3f m below the hip-roll axis" % HIP_ROLL_TO_YAW)
    joint(p + "knee", p + "thigh", p + "shank", (KNEE_X, 0.0, -(THIGH - HIP_PITCH_TO_ROLL - HIP_ROLL_TO_YAW)), (0, 1, 0),
          lim("knee"), LEG_EFFORT["knee"], LEG_VEL["knee"],
          "knee: %.3f m below and %.3f m ahead of the hip-pitch axis; bends forward only" % (THIGH, KNEE_X))
    joint(p + "ankle_pitch", p + "shank", p + "ankle", (ANKLE_X, 0.0, -SHANK), (0, 1, 0), lim("ankle_pitch"),
          LEG_EFFORT["ankle_pitch"], LEG_VEL["ankle_pitch"], "ankle pitch: %.3f m below and %.3f m behind the knee" % (SHANK, -ANKLE_X))
    joint(p + "ankle_roll", p + "ankle", p + "foot", (0.0, 0.0, -ANKLE_PITCH_TO_ROLL), (1, 0, 0), lim("ankle_roll"),
          LEG_EFFORT["ankle_roll"], LEG_VEL["ankle_roll"],
          "ankle roll: %.3f m below the ankle-pitch axis; sole centre at (%.3f, 0, %.3f) in the foot frame (placed by the scene)"
          % (ANKLE_PITCH_TO_ROLL, SOLE_IN_FOOT[0], SOLE_IN_FOOT[2]))

# Torso: pitch then yaw (HRP-2: yaw then pitch). The chest is a shell with a battery pack
# low at its back: the composite inertia has a product ixz.
link("waist", M["waist"], (0, 0, 0), cyl_inertia(M["waist"], 0.05, 0.12, "y"),
     "waist (torso-pitch motor): cylinder r 0.05 m, 0.12 m, along y",
     [("waist.obj", None, (0, 0, 0), ROT_Y)], [("cylinder", (0.05, 0.12), (0, 0, 0), ROT_Y)])
CHEST_SHELL = (0.01, 0.0, 0.17)   # centre of the 0.18 x 0.28 x 0.30 shell in the chest frame
BATTERY = (-0.085, 0.0, 0.09)     # centre of the 0.08 x 0.20 x 0.12 battery pack
m_chest, c_chest, I_chest = composite([
    (M["chest_shell"], CHEST_SHELL, box_inertia(M["chest_shell"], 0.18, 0.28, 0.30)),
    (M["battery"], BATTERY, box_inertia(M["battery"], 0.08, 0.20, 0.12))])
link("chest", m_chest, tuple(c_chest), I_chest,
     "chest: shell box 0.18 x 0.28 x 0.30 m (%.1f kg) + battery box 0.08 x 0.20 x 0.12 m (%.1f kg) at its back"
     % (M["chest_shell"], M["battery"]),
     [("chest.stl", None, CHEST_SHELL, (0, 0, 0)), ("battery.stl", None, BATTERY, (0, 0, 0))],
     [("box", (0.18, 0.28, 0.30), CHEST_SHELL, (0, 0, 0)), ("box", (0.08, 0.20, 0.12), BATTERY, (0, 0, 0))])
joint("torso_pitch", "pelvis", "waist", (0.0, 0.0, TORSO_PITCH_Z), (0, 1, 0), (-0.3, 0.8), 150, 5.0,
      "torso pitch: %.3f m above the pelvis origin; > 0 leans forward" % TORSO_PITCH_Z)
joint("torso_yaw", "waist", "chest", (0.0, 0.0, TORSO_YAW_Z), (0, 0, 1), (-1.0, 1.0), 80, 5.0,
      "torso yaw: %.3f m above the torso-pitch axis" % TORSO_YAW_Z)

NECK_C = (0.0, 0.0, 0.025)
HEAD_C = (0.01, 0.0, 0.08)
link("neck", M["neck"], NECK_C, cyl_inertia(M["neck"], 0.025, 0.05), "neck: cylinder r 0.025 m, 0.05 m",
     [("neck.obj", None, NECK_C, (0, 0, 0))], [("cylinder", (0.025, 0.05), NECK_C, (0, 0, 0))])
link("head", M["head"], HEAD_C, cyl_inertia(M["head"], 0.07, 0.16), "head: cylinder r 0.07 m, 0.16 m (drawn as a capsule)",
     [("head.obj", None, HEAD_C, (0, 0, 0))], [("cylinder", (0.07, 0.16), HEAD_C, (0, 0, 0))])
joint("neck_yaw", "chest", "neck", (0.0, 0.0, NECK_Z), (0, 0, 1), (-1.2, 1.2), 10, 6.0,
      "neck yaw: %.3f m above the chest origin" % NECK_Z)
joint("neck_pitch", "neck", "head", (0.0, 0.0, NECK_PITCH_Z), (0, 1, 0), (-0.5, 0.7), 10, 6.0,
      "neck pitch: %.3f m above the neck-yaw joint; > 0 looks down" % NECK_PITCH_Z)

# Arms: shoulder pitch (y), shoulder roll (x), shoulder yaw (z), elbow (y), wrist yaw (z).
ARM_LIM_R = {"shoulder_pitch": (-3.0, 1.0), "shoulder_roll": (-1.6, 0.15), "shoulder_yaw": (-1.5, 1.5),
             "elbow": (-2.3, 0.0), "wrist_yaw": (-1.6, 1.6)}
ARM_EFFORT = {"shoulder_pitch": 50, "shoulder_roll": 50, "shoulder_yaw": 25, "elbow": 40, "wrist_yaw": 10}
BRACKET_SHOULDER = (0.06, 0.05, 0.06)
UPPER_ARM_CAPSULE = (0.035, 0.18, (0.0, 0.0, -0.08))
FOREARM_CAPSULE = (0.03, 0.18, (0.0, 0.0, -0.085))
HAND_C = (0.0, 0.0, -0.05)
for s, p in ((-1.0, "r_"), (1.0, "l_")):
    side = "right" if s < 0 else "left"
    link(p + "shoulder", M["shoulder"], (0, 0, 0), cyl_inertia(M["shoulder"], 0.04, 0.07, "y"),
         "%s shoulder-pitch motor: cylinder r 0.04 m, 0.07 m, along y" % side,
         [("motor.stl", None, (0, 0, 0), ROT_Y)], [("cylinder", (0.04, 0.07), (0, 0, 0), ROT_Y)])
    bc = (0.0, 0.0, -0.02)
    link(p + "shoulder_bracket", M["shoulder_bracket"], bc, box_inertia(M["shoulder_bracket"], *BRACKET_SHOULDER),
         "%s shoulder roll-yaw bracket: box 0.06 x 0.05 x 0.06 m" % side,
         [("bracket.stl", BRACKET_SHOULDER, bc, (0, 0, 0))], [("box", BRACKET_SHOULDER, bc, (0, 0, 0))])
    r, L, c = UPPER_ARM_CAPSULE
    link(p + "upper_arm", M["upper_arm"], c, cyl_inertia(M["upper_arm"], r, L),
         "%s upper arm: cylinder r %.3f m, %.2f m (drawn as a capsule)" % (side, r, L),
         [("upper_arm.obj", None, c, (0, 0, 0))], [("cylinder", (r, L), c, (0, 0, 0))])
    r, L, c = FOREARM_CAPSULE
    link(p + "forearm", M["forearm"], c, cyl_inertia(M["forearm"], r, L),
         "%s forearm: cylinder r %.3f m, %.2f m (drawn as a capsule)" % (side, r, L),
         [("forearm.obj", None, c, (0, 0, 0))], [("cylinder", (r, L), c, (0, 0, 0))])
    link(p + "hand", M["hand"], HAND_C, box_inertia(M["hand"], 0.04, 0.07, 0.10), "%s hand: box 0.04 x 0.07 x 0.10 m" % side,
         [("hand.stl", None, HAND_C, (0, 0, 0))], [("box", (0.04, 0.07, 0.10), HAND_C, (0, 0, 0))])
    lim = lambda k: limits(ARM_LIM_R, k, s)  # noqa: E731
    joint(p + "shoulder_pitch", "chest", p + "shoulder", (SHOULDER[0], s * SHOULDER[1], SHOULDER[2]), (0, 1, 0),
          lim("shoulder_pitch"), ARM_EFFORT["shoulder_pitch"], 6.0, "shoulder pitch; < 0 raises the arm forward")
    joint(p + "shoulder_roll", p + "shoulder", p + "shoulder_bracket", (0.0, s * SHOULDER_ROLL_Y, 0.0), (1, 0, 0),
          lim("shoulder_roll"), ARM_EFFORT["shoulder_roll"], 6.0, "shoulder roll: %.3f m outboard of the pitch joint" % SHOULDER_ROLL_Y)
    joint(p + "shoulder_yaw", p + "shoulder_bracket", p + "upper_arm", (0.0, 0.0, -SHOULDER_YAW_Z), (0, 0, 1),
          lim("shoulder_yaw"), ARM_EFFORT["shoulder_yaw"], 6.0, "shoulder yaw: %.3f m below the roll axis" % SHOULDER_YAW_Z)
    joint(p + "elbow", p + "upper_arm", p + "forearm", (ELBOW_X, 0.0, -UPPER_ARM), (0, 1, 0), lim("elbow"),
          ARM_EFFORT["elbow"], 6.0, "elbow: %.3f m below the shoulder-yaw joint, %.3f m ahead; < 0 bends" % (UPPER_ARM, ELBOW_X))
    joint(p + "wrist_yaw", p + "forearm", p + "hand", (0.0, 0.0, -FOREARM), (0, 0, 1), lim("wrist_yaw"),
          ARM_EFFORT["wrist_yaw"], 6.0, "wrist yaw: %.3f m below the elbow" % FOREARM)


# ----------------------------------------------------------------------- checks (own FK)
def rot(axis, a):
    c, s = math.cos(a), math.sin(a)
    x, y, z = axis
    C = 1 - c
    return [[c + x * x * C, x * y * C - z * s, x * z * C + y * s],
            [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
            [z * x * C - y * s, z * y * C + x * s, c + z * z * C]]


def mm(A, B):
    return [[sum(A[i][k] * B[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def mv(A, v):
    return [sum(A[i][k] * v[k] for k in range(3)) for i in range(3)]


def poses(q):
    """World pose (R, p) of every link for joint angles q (by name), pelvis at the origin."""
    children = {}
    for j in JOINTS:
        children.setdefault(j[1], []).append(j)
    out = {}
    stack = [("pelvis", [[1, 0, 0], [0, 1, 0], [0, 0, 1]], [0.0, 0.0, 0.0])]
    while stack:
        name, R, p = stack.pop()
        out[name] = (R, p)
        for j in children.get(name, []):
            pj = [p[i] + mv(R, j[3])[i] for i in range(3)]
            stack.append((j[2], mm(R, rot(j[4], q.get(j[0], 0.0))), pj))
    return out


def stance(q):
    """Mass, CoM and right-sole centre (pelvis frame) and the sole's tilt for q."""
    P = poses(q)
    mt, mc = 0.0, [0.0, 0.0, 0.0]
    for name, L in LINKS.items():
        R, p = P[name]
        w = [p[i] + mv(R, L["com"])[i] for i in range(3)]
        mt += L["mass"]
        mc = [mc[i] + L["mass"] * w[i] for i in range(3)]
    R, p = P["r_foot"]
    sole = [p[i] + mv(R, SOLE_IN_FOOT)[i] for i in range(3)]
    return mt, [x / mt for x in mc], sole, R


def check_inertia(name, I):
    d = [I[0][0], I[1][1], I[2][2]]
    assert all(x > 0 for x in d), name
    assert d[0] <= d[1] + d[2] and d[1] <= d[0] + d[2] and d[2] <= d[0] + d[1], name
    # Sylvester's criterion: leading minors > 0
    m2 = I[0][0] * I[1][1] - I[0][1] * I[1][0]
    det = (I[0][0] * (I[1][1] * I[2][2] - I[1][2] * I[2][1]) - I[0][1] * (I[1][0] * I[2][2] - I[1][2] * I[2][0])
           + I[0][2] * (I[1][0] * I[2][1] - I[1][1] * I[2][0]))
    assert m2 > 0 and det > 0, name


def fmt(x):
    return "%.6g" % x


def urdf_text(summary):
    out = ['<?xml version="1.0"?>',
           '<!-- GENERATED by models/kestrel/generate_kestrel_urdf.py: edit the generator, not this file. -->',
           '<!-- Kestrel: a humanoid designed by the Plantar project (not a real robot), see docs/kestrel_model.md. -->',
           '<!-- Frames: x forward, y left, z up; all link frames parallel to pelvis at q = 0. pelvis is the root; -->',
           '<!-- the loader attaches it with a free-floating joint. Visuals: meshes (paths relative to this file), -->',
           '<!-- drawing only; collisions: the boxes/cylinders whose inertias the links carry. -->',
           '<!-- No sole links: the sole frame (centre of the sole bottom face) is at xyz = (%g, %g, %g) m, rpy = 0, -->'
           % SOLE_IN_FOOT,
           '<!-- in r_foot and in l_foot; a scene places it there. -->',
           '<!-- %s -->' % summary,
           '<robot name="kestrel">']
    for name, L in LINKS.items():
        I = L["inertia"]
        out.append('  <!-- %s -->' % L["comment"])
        out.append('  <link name="%s">' % name)
        out.append('    <inertial>')
        out.append('      <origin xyz="%s" rpy="0 0 0"/>' % " ".join(fmt(x) for x in L["com"]))
        out.append('      <mass value="%s"/>' % fmt(L["mass"]))
        out.append('      <inertia ixx="%s" ixy="%s" ixz="%s" iyy="%s" iyz="%s" izz="%s"/>'
                   % tuple(fmt(x) for x in (I[0][0], I[0][1], I[0][2], I[1][1], I[1][2], I[2][2])))
        out.append('    </inertial>')
        for mesh, scale, xyz, rpy in L["visuals"]:
            out.append('    <visual>')
            out.append('      <origin xyz="%s" rpy="%s"/>' % (" ".join(fmt(x) for x in xyz), " ".join(fmt(x) for x in rpy)))
            sc = (' scale="%s"' % " ".join(fmt(x) for x in scale)) if scale else ""
            out.append('      <geometry><mesh filename="%s/%s"%s/></geometry>' % (MESH_DIR, mesh, sc))
            out.append('    </visual>')
        for shape, size, xyz, rpy in L["collisions"]:
            out.append('    <collision>')
            out.append('      <origin xyz="%s" rpy="%s"/>' % (" ".join(fmt(x) for x in xyz), " ".join(fmt(x) for x in rpy)))
            if shape == "box":
                out.append('      <geometry><box size="%s"/></geometry>' % " ".join(fmt(x) for x in size))
            else:
                out.append('      <geometry><cylinder radius="%s" length="%s"/></geometry>' % (fmt(size[0]), fmt(size[1])))
            out.append('    </collision>')
        out.append('  </link>')
    for (name, parent, child, xyz, axis, lo, hi, eff, vel, comment) in JOINTS:
        out.append('  <!-- %s -->' % comment)
        out.append('  <joint name="%s" type="revolute">' % name)
        out.append('    <parent link="%s"/>' % parent)
        out.append('    <child link="%s"/>' % child)
        out.append('    <origin xyz="%s" rpy="0 0 0"/>' % " ".join(fmt(x) for x in xyz))
        out.append('    <axis xyz="%d %d %d"/>' % axis)
        out.append('    <limit lower="%s" upper="%s" effort="%g" velocity="%g"/>' % (fmt(lo), fmt(hi), eff, vel))
        out.append('  </joint>')
    out.append('</robot>')
    return "\n".join(out) + "\n"


def main():
    for name, L in LINKS.items():
        assert L["mass"] > 0, name
        check_inertia(name, L["inertia"])
    os.makedirs(os.path.join(HERE, MESH_DIR), exist_ok=True)
    sizes = {name: write_mesh(name, *spec) for name, spec in MESHES.items()}
    used = {v[0] for L in LINKS.values() for v in L["visuals"]}
    assert used == set(MESHES), used ^ set(MESHES)

    # Standing postures, pelvis upright, soles flat (hip pitch + knee + ankle pitch = 0).
    mt, c0, s0, _ = stance({})
    figures = []
    for knee in (0.5, 1.0):
        bent = {}
        for p in ("r_", "l_"):
            bent.update({p + "hip_pitch": -knee / 2, p + "knee": knee, p + "ankle_pitch": -knee / 2})
        _, c1, s1, R1 = stance(bent)
        assert abs(R1[2][2] - 1.0) < 1e-12  # sole flat
        figures.append((knee, c1, s1))
    lines = [
        "kestrel: total mass %.3f kg, %d revolute joints, %d links" % (mt, len(JOINTS), len(LINKS)),
        "sole frame (centre of the sole's bottom face, %.2f x %.2f m) in r_foot and in l_foot: xyz = (%g, %g, %g) m, rpy = (0, 0, 0)"
        % ((SOLE_L, SOLE_W) + SOLE_IN_FOOT),
        "straight legs (q = 0): pelvis origin %.4f m above the soles, CoM height %.4f m, CoM x - sole centre x %+.4f m"
        % (-s0[2], c0[2] - s0[2], c0[0] - s0[0]),
    ] + ["knees bent %.1f rad (hip pitch and ankle pitch %.2f rad): pelvis origin %.4f m, CoM height %.4f m, "
         "CoM x - sole centre x %+.4f m" % (knee, -knee / 2, -s1[2], c1[2] - s1[2], c1[0] - s1[0])
         for knee, c1, s1 in figures] + [
        "meshes: " + ", ".join("%s %d B" % (n, sizes[n]) for n in sorted(sizes)),
    ]
    summary = "Total mass %.3f kg; CoM height above the soles %.4f m with straight legs, %.4f m with knees bent 0.5 rad." % (
        mt, c0[2] - s0[2], figures[0][1][2] - figures[0][2][2])
    with open(os.path.join(HERE, "kestrel.urdf"), "w") as out:
        out.write(urdf_text(summary))
    print("\n".join(lines), file=sys.stderr)


if __name__ == "__main__":
    main()
