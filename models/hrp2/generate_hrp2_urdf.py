#!/usr/bin/env python3
"""Generates models/hrp2/hrp2.urdf, the HRP-2-like model of Plantar.

Run:  python3 models/hrp2/generate_hrp2_urdf.py > models/hrp2/hrp2.urdf
It also prints (to stderr) the total mass and the CoM heights it computes by
its own forward kinematics, the figures quoted in docs/hrp2_model.md.

Public dimensions (marked "public" in the URDF comments) come from
/work/shared/reference/hrp2.md (jrl-walkgen src/data/HRP2Specificities.xml).
Everything marked "ESTIMATE" is a Plantar estimate: HRP-2's real mass
distribution, inertias and most link offsets are not public.
No dependency beyond the Python standard library.
"""
import math
import sys

DEG = math.pi / 180.0

# ---------------------------------------------------------------- public numbers
THIGH = 0.30          # public: femur length
SHANK = 0.30          # public: tibia length
ANKLE_H = 0.105       # public: ankle height above the sole
FOOT_L, FOOT_W = 0.2172, 0.138   # public: sole size
ANKLE_IN_FOOT = (0.0933, 0.059, 0.105)  # public: ankle in the foot-corner frame
WAIST_TO_HIP_Y = 0.06  # public
HIP_OFFSET_Y = 0.035   # public
UPPER_ARM = 0.25       # public
FOREARM = 0.25         # public
# Sole frame: centre of the sole's bottom face. Plantar reads the corner of
# ANKLE_IN_FOOT as the rear, inner corner of each foot, so the sole centre is
# (L/2 - 0.0933) ahead of the ankle and (W/2 - 0.059) outwards.
SOLE_DX = FOOT_L / 2 - ANKLE_IN_FOOT[0]   # 0.0153
SOLE_DY_OUT = FOOT_W / 2 - ANKLE_IN_FOOT[1]  # 0.0100

# --------------------------------------------------------------------- estimates
CHEST_Z = 0.28        # ESTIMATE: chest yaw/pitch joints above the hip axes
SHOULDER = (0.0, 0.25, 0.26)   # ESTIMATE: shoulder centre in the chest frame
NECK_Z = 0.36         # ESTIMATE: neck joints above the chest joints
HAND = 0.04           # ESTIMATE: wrist to gripper joint


def box_inertia(m, a, b, c):
    return (m * (b * b + c * c) / 12.0, m * (a * a + c * c) / 12.0, m * (a * a + b * b) / 12.0)


def cyl_inertia(m, r, h):  # axis along z
    ixx = m * (3 * r * r + h * h) / 12.0
    return (ixx, ixx, m * r * r / 2.0)


# link name -> (mass, com xyz, (ixx, iyy, izz), comment); filled below
LINKS = {}
JOINTS = []  # (name, type, parent, child, xyz, axis, lower, upper, effort, velocity, comment)


def link(name, mass, com, inertia, comment):
    LINKS[name] = (mass, com, inertia, comment)


def joint(name, parent, child, xyz, axis, lim, effort, vel, comment):
    JOINTS.append((name, "revolute", parent, child, xyz, axis, lim[0] * DEG, lim[1] * DEG, effort, vel, comment))


def fixed(name, parent, child, xyz, comment):
    JOINTS.append((name, "fixed", parent, child, xyz, None, 0, 0, 0, 0, comment))


# link name -> (kind "box"/"cylinder", size, xyz, comment): <visual> geometry, drawing only
# (ParaView output); it does not enter the dynamics, which use the <inertial> blocks alone.
# Box size (x, y, z) m; cylinder size (radius, length) m, axis along the link's z.
VISUALS = {}


def visual(name, kind, size, xyz, comment):
    VISUALS[name] = (kind, size, xyz, comment)


# Masses (ESTIMATE, kg). Segment volumes: see docs/hrp2_model.md. Total 58.0.
M = {
    "BODY": 9.4, "HIPY": 0.7, "HIPR": 0.7, "THIGH": 3.6, "SHANK": 2.1, "ANKP": 0.3, "FOOT": 1.4,
    "CHEST0": 1.0, "CHEST1": 17.0, "HEAD0": 0.4, "HEAD1": 1.6,
    "ARM0": 0.7, "ARM1": 0.7, "ARM2": 1.7, "ARM3": 0.6, "ARM4": 1.0, "ARM5": 0.4, "ARM6": 0.4,
}
TORSO_COM_Z = 0.214    # ESTIMATE: CHEST_LINK1 CoM above the chest joints (tuned for CoM 0.814 m)

link("BODY", M["BODY"], (0.0, 0.0, 0.06), box_inertia(M["BODY"], 0.20, 0.25, 0.16),
     "waist/pelvis: box 0.20 x 0.25 x 0.16 m")
visual("BODY", "box", (0.20, 0.25, 0.16), (0.0, 0.0, 0.06), "waist: the inertia's box (ESTIMATE), about its CoM")
# Leg limits (deg, ESTIMATE: typical HRP-2 ranges), right leg; left mirrors roll/yaw.
LEG_LIM_R = [(-45, 30), (-35, 20), (-125, 42), (-2, 150), (-75, 42), (-20, 35)]
LEG_EFFORT = [150, 250, 300, 300, 250, 150]  # N m, ESTIMATE
LEG_VEL = [4.0, 4.0, 6.0, 6.0, 6.0, 4.0]     # rad/s, ESTIMATE
for side, s, pre in (("R", -1.0, "RLEG"), ("L", 1.0, "LLEG")):
    lims = LEG_LIM_R if s < 0 else [(-b, -a) if i in (0, 1, 5) else (a, b) for i, (a, b) in enumerate(LEG_LIM_R)]
    link(pre + "_LINK0", M["HIPY"], (0.0, 0.0, 0.04), box_inertia(M["HIPY"], 0.10, 0.08, 0.08), "hip yaw bracket: box 0.10 x 0.08 x 0.08 m")
    link(pre + "_LINK1", M["HIPR"], (0.0, 0.0, 0.0), box_inertia(M["HIPR"], 0.10, 0.08, 0.08), "hip roll bracket: box 0.10 x 0.08 x 0.08 m")
    link(pre + "_LINK2", M["THIGH"], (0.0, s * HIP_OFFSET_Y / 2, -THIGH / 2), cyl_inertia(M["THIGH"], 0.06, THIGH), "thigh: cylinder r 0.06 m, 0.30 m")
    link(pre + "_LINK3", M["SHANK"], (0.0, 0.0, -SHANK / 2), cyl_inertia(M["SHANK"], 0.05, SHANK), "shank: cylinder r 0.05 m, 0.30 m")
    link(pre + "_LINK4", M["ANKP"], (0.0, 0.0, 0.0), box_inertia(M["ANKP"], 0.06, 0.06, 0.06), "ankle pitch cross: box 0.06 m")
    link(pre + "_LINK5", M["FOOT"], (SOLE_DX, s * SOLE_DY_OUT, -0.07), box_inertia(M["FOOT"], FOOT_L, FOOT_W, 0.07),
         "foot with its force sensor and rubber bush: box 0.2172 x 0.138 x 0.07 m")
    visual(pre + "_LINK0", "box", (0.10, 0.08, 0.08), (0.0, 0.0, 0.04), "hip yaw bracket: the inertia's box (ESTIMATE)")
    visual(pre + "_LINK1", "box", (0.10, 0.08, 0.08), (0.0, 0.0, 0.0), "hip roll bracket: the inertia's box (ESTIMATE)")
    visual(pre + "_LINK2", "cylinder", (0.06, THIGH), (0.0, s * HIP_OFFSET_Y / 2, -THIGH / 2),
           "thigh: public length 0.30 m hip to knee, radius 0.06 m ESTIMATE")
    visual(pre + "_LINK3", "cylinder", (0.05, SHANK), (0.0, 0.0, -SHANK / 2),
           "shank: public length 0.30 m knee to ankle, radius 0.05 m ESTIMATE")
    visual(pre + "_LINK4", "box", (0.06, 0.06, 0.06), (0.0, 0.0, 0.0), "ankle pitch cross: the inertia's box (ESTIMATE)")
    visual(pre + "_LINK5", "box", (FOOT_L, FOOT_W, 0.07), (SOLE_DX, s * SOLE_DY_OUT, -ANKLE_H + 0.035),
           "foot: public sole 0.2172 x 0.138 m centred on the sole frame, bottom face on the sole frame "
           "(public: 0.105 m below the ankle), height 0.07 m ESTIMATE")
    joint(pre + "_JOINT0", "BODY", pre + "_LINK0", (0.0, s * WAIST_TO_HIP_Y, 0.0), (0, 0, 1), lims[0], LEG_EFFORT[0], LEG_VEL[0],
          "hip yaw; public: waist to hip 0.06 m lateral. Yaw, roll and pitch axes meet at the hip point")
    joint(pre + "_JOINT1", pre + "_LINK0", pre + "_LINK1", (0.0, 0.0, 0.0), (1, 0, 0), lims[1], LEG_EFFORT[1], LEG_VEL[1], "hip roll")
    joint(pre + "_JOINT2", pre + "_LINK1", pre + "_LINK2", (0.0, 0.0, 0.0), (0, 1, 0), lims[2], LEG_EFFORT[2], LEG_VEL[2], "hip pitch")
    joint(pre + "_JOINT3", pre + "_LINK2", pre + "_LINK3", (0.0, s * HIP_OFFSET_Y, -THIGH), (0, 1, 0), lims[3], LEG_EFFORT[3], LEG_VEL[3],
          "knee; public: thigh 0.30 m; public: hip offset 0.035 m (placed along the pitch axis, in the thigh)")
    joint(pre + "_JOINT4", pre + "_LINK3", pre + "_LINK4", (0.0, 0.0, -SHANK), (0, 1, 0), lims[4], LEG_EFFORT[4], LEG_VEL[4], "ankle pitch; public: shank 0.30 m")
    joint(pre + "_JOINT5", pre + "_LINK4", pre + "_LINK5", (0.0, 0.0, 0.0), (1, 0, 0), lims[5], LEG_EFFORT[5], LEG_VEL[5], "ankle roll (same point as ankle pitch)")
    sole = ("r_sole" if s < 0 else "l_sole")
    LINKS[sole] = None
    fixed(side + "_SOLE_FIXED", pre + "_LINK5", sole, (SOLE_DX, s * SOLE_DY_OUT, -ANKLE_H),
          "sole frame = centre of the sole's bottom face; public: ankle 0.105 m above the sole, foot 0.2172 x 0.138 m, "
          "ankle at (0.0933, 0.059, 0.105) from the rear inner corner -> (+%.4f, %+.4f, -0.105)" % (SOLE_DX, s * SOLE_DY_OUT))

link("CHEST_LINK0", M["CHEST0"], (0.0, 0.0, 0.0), box_inertia(M["CHEST0"], 0.10, 0.10, 0.06), "chest yaw bracket: box 0.10 x 0.10 x 0.06 m")
link("CHEST_LINK1", M["CHEST1"], (-0.02, 0.0, TORSO_COM_Z), box_inertia(M["CHEST1"], 0.26, 0.34, 0.45),
     "torso with computers and battery: box 0.26 x 0.34 x 0.45 m")
visual("CHEST_LINK0", "box", (0.10, 0.10, 0.06), (0.0, 0.0, 0.0), "chest yaw bracket: the inertia's box (ESTIMATE)")
visual("CHEST_LINK1", "box", (0.26, 0.34, 0.45), (-0.02, 0.0, TORSO_COM_Z), "torso: the inertia's box (ESTIMATE), about its CoM")
joint("CHEST_JOINT0", "BODY", "CHEST_LINK0", (0.0, 0.0, CHEST_Z), (0, 0, 1), (-45, 45), 150, 4.0, "chest yaw; position ESTIMATE")
joint("CHEST_JOINT1", "CHEST_LINK0", "CHEST_LINK1", (0.0, 0.0, 0.0), (0, 1, 0), (-5, 60), 200, 4.0, "chest pitch")
link("HEAD_LINK0", M["HEAD0"], (0.0, 0.0, 0.0), box_inertia(M["HEAD0"], 0.06, 0.06, 0.06), "neck yaw bracket: box 0.06 m")
link("HEAD_LINK1", M["HEAD1"], (0.02, 0.0, 0.09), box_inertia(M["HEAD1"], 0.18, 0.16, 0.185), "head with cameras: box 0.18 x 0.16 x 0.185 m")
visual("HEAD_LINK0", "box", (0.06, 0.06, 0.06), (0.0, 0.0, 0.0), "neck yaw bracket: the inertia's box (ESTIMATE)")
visual("HEAD_LINK1", "box", (0.18, 0.16, 0.185), (0.02, 0.0, 0.09), "head: the inertia's box (ESTIMATE); top at 1.54 m, public height")
joint("HEAD_JOINT0", "CHEST_LINK1", "HEAD_LINK0", (0.0, 0.0, NECK_Z), (0, 0, 1), (-45, 45), 20, 4.0, "neck yaw; position ESTIMATE (head top at 1.54 m, public height)")
joint("HEAD_JOINT1", "HEAD_LINK0", "HEAD_LINK1", (0.0, 0.0, 0.0), (0, 1, 0), (-30, 45), 20, 4.0, "neck pitch")

ARM_LIM_R = [(-180, 60), (-95, 10), (-90, 90), (-135, 0), (-90, 90), (-90, 90), (-16, 60)]
ARM_EFFORT = [120, 120, 60, 80, 30, 30, 10]
ARM_AXES = [(0, 1, 0), (1, 0, 0), (0, 0, 1), (0, 1, 0), (0, 0, 1), (0, 1, 0), (0, 1, 0)]
for s, pre in ((-1.0, "RARM"), (1.0, "LARM")):
    lims = ARM_LIM_R if s < 0 else [(-b, -a) if i in (1, 2, 4) else (a, b) for i, (a, b) in enumerate(ARM_LIM_R)]
    xyz = [(SHOULDER[0], s * SHOULDER[1], SHOULDER[2]), (0, 0, 0), (0, 0, 0), (0, 0, -UPPER_ARM), (0, 0, 0), (0, 0, -FOREARM), (0, 0, -HAND)]
    names = ["shoulder pitch; shoulder position ESTIMATE", "shoulder roll", "upper-arm yaw",
             "elbow; public: upper arm 0.25 m", "wrist yaw", "wrist pitch; public: forearm 0.25 m", "gripper (7th joint); offset ESTIMATE"]
    coms = [(0, 0, 0), (0, 0, 0), (0, 0, -UPPER_ARM / 2), (0, 0, 0), (0, 0, -FOREARM / 2), (0, 0, 0), (0, 0, -0.05)]
    inert = [box_inertia(M["ARM0"], 0.08, 0.08, 0.08), box_inertia(M["ARM1"], 0.08, 0.08, 0.08), cyl_inertia(M["ARM2"], 0.045, UPPER_ARM),
             box_inertia(M["ARM3"], 0.07, 0.07, 0.07), cyl_inertia(M["ARM4"], 0.04, FOREARM), box_inertia(M["ARM5"], 0.05, 0.05, 0.05),
             box_inertia(M["ARM6"], 0.04, 0.08, 0.10)]
    shapes = ["shoulder bracket: box 0.08 m", "shoulder bracket: box 0.08 m", "upper arm: cylinder r 0.045 m, 0.25 m",
              "elbow: box 0.07 m", "forearm: cylinder r 0.04 m, 0.25 m", "wrist: box 0.05 m", "gripper: box 0.04 x 0.08 x 0.10 m"]
    vis = [("box", (0.08, 0.08, 0.08), coms[0], "shoulder bracket: the inertia's box (ESTIMATE)"),
           ("box", (0.08, 0.08, 0.08), coms[1], "shoulder bracket: the inertia's box (ESTIMATE)"),
           ("cylinder", (0.045, UPPER_ARM), coms[2], "upper arm: public length 0.25 m shoulder to elbow, radius 0.045 m ESTIMATE"),
           ("box", (0.07, 0.07, 0.07), coms[3], "elbow: the inertia's box (ESTIMATE)"),
           ("cylinder", (0.04, FOREARM), coms[4], "forearm: public length 0.25 m elbow to wrist, radius 0.04 m ESTIMATE"),
           ("box", (0.05, 0.05, 0.05), coms[5], "wrist: the inertia's box (ESTIMATE)"),
           ("box", (0.04, 0.08, 0.10), coms[6], "gripper: the inertia's box (ESTIMATE)")]
    for i in range(7):
        parent = "CHEST_LINK1" if i == 0 else "%s_LINK%d" % (pre, i - 1)
        link("%s_LINK%d" % (pre, i), M["ARM%d" % i], coms[i], inert[i], shapes[i])
        visual("%s_LINK%d" % (pre, i), *vis[i])
        joint("%s_JOINT%d" % (pre, i), parent, "%s_LINK%d" % (pre, i), xyz[i], ARM_AXES[i], lims[i], ARM_EFFORT[i], 4.0, names[i])


# ---------------------------------------------------------------- checks (FK)
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


def com_height(q, base_z):
    children = {}
    for j in JOINTS:
        children.setdefault(j[2], []).append(j)
    stack = [("BODY", [[1, 0, 0], [0, 1, 0], [0, 0, 1]], [0.0, 0.0, base_z])]
    mt, mc = 0.0, [0.0, 0.0, 0.0]
    while stack:
        name, R, p = stack.pop()
        if LINKS[name] is not None:
            m, c, _, _ = LINKS[name]
            w = [p[i] + mv(R, c)[i] for i in range(3)]
            mt += m
            mc = [mc[i] + m * w[i] for i in range(3)]
        for j in children.get(name, []):
            pj = [p[i] + mv(R, j[4])[i] for i in range(3)]
            Rj = mm(R, rot(j[5], q.get(j[0], 0.0))) if j[1] == "revolute" else R
            stack.append((j[3], Rj, pj))
    return mt, [x / mt for x in mc]


if __name__ == "__main__":
    straight_z = THIGH + SHANK + ANKLE_H
    mt, c0 = com_height({}, straight_z)
    hs = {}
    for pre in ("RLEG", "LLEG"):
        hs.update({pre + "_JOINT2": -26 * DEG, pre + "_JOINT3": 50 * DEG, pre + "_JOINT4": -24 * DEG})
    hip_z = THIGH * math.cos(26 * DEG) + SHANK * math.cos(24 * DEG) + ANKLE_H
    _, c1 = com_height(hs, hip_z)
    print("total mass %.3f kg; straight legs: waist %.4f m, CoM (%.4f, %.4f, %.4f) m; "
          "half-sitting legs (-26, 50, -24 deg): waist %.4f m, CoM (%.4f, %.4f, %.4f) m"
          % (mt, straight_z, c0[0], c0[1], c0[2], hip_z, c1[0], c1[1], c1[2]), file=sys.stderr)
    out = ['<?xml version="1.0"?>',
           '<!-- GENERATED by models/hrp2/generate_hrp2_urdf.py: edit the generator, not this file. -->',
           '<!-- HRP-2-LIKE model for Plantar. NOT the manufacturer\'s model (which is not public). -->',
           '<!-- Public numbers: /work/shared/reference/hrp2.md (jrl-walkgen HRP2Specificities.xml). -->',
           '<!-- All masses, inertias, CoM positions, limits, efforts and velocities are ESTIMATES (segment volumes, -->',
           '<!-- scaled so that the total is 58 kg, public, and the half-sitting CoM height is about 0.814 m, public). -->',
           '<!-- Frames: x forward, y left, z up. Zero configuration: straight legs, arms hanging. BODY is the waist; -->',
           '<!-- its origin is at the height of the hip axes; the loader attaches it with a free-floating joint. -->',
           '<!-- Total mass %.3f kg; straight-leg CoM height %.4f m (waist %.4f m); half-sitting CoM height %.4f m (waist %.4f m). -->'
           % (mt, c0[2], straight_z, c1[2], hip_z),
           '<robot name="hrp2_like">']
    for name, val in LINKS.items():
        if val is None:
            out.append('  <link name="%s"/>' % name)
            continue
        m, c, I, comment = val
        out.append('  <!-- %s; mass, CoM and inertia ESTIMATE -->' % comment)
        out.append('  <link name="%s">' % name)
        out.append('    <inertial>')
        out.append('      <origin xyz="%.5f %.5f %.5f" rpy="0 0 0"/>' % c)
        out.append('      <mass value="%.4f"/>' % m)
        out.append('      <inertia ixx="%.6g" ixy="0" ixz="0" iyy="%.6g" iyz="0" izz="%.6g"/>' % I)
        out.append('    </inertial>')
        if name in VISUALS:
            kind, size, xyz, vcomment = VISUALS[name]
            out.append('    <!-- visual (drawing only, no dynamics): %s -->' % vcomment)
            out.append('    <visual>')
            out.append('      <origin xyz="%.5f %.5f %.5f" rpy="0 0 0"/>' % tuple(float(v) for v in xyz))
            if kind == "box":
                out.append('      <geometry><box size="%.5f %.5f %.5f"/></geometry>' % size)
            else:
                out.append('      <geometry><cylinder radius="%.5f" length="%.5f"/></geometry>' % size)
            out.append('    </visual>')
        out.append('  </link>')
    for (name, typ, parent, child, xyz, axis, lo, hi, eff, vel, comment) in JOINTS:
        out.append('  <!-- %s -->' % comment)
        out.append('  <joint name="%s" type="%s">' % (name, typ))
        out.append('    <parent link="%s"/>' % parent)
        out.append('    <child link="%s"/>' % child)
        out.append('    <origin xyz="%.5f %.5f %.5f" rpy="0 0 0"/>' % xyz)
        if typ == "revolute":
            out.append('    <axis xyz="%d %d %d"/>' % axis)
            out.append('    <!-- limits, effort (N m) and velocity (rad/s): ESTIMATES -->')
            out.append('    <limit lower="%.6f" upper="%.6f" effort="%g" velocity="%g"/>' % (lo, hi, eff, vel))
        out.append('  </joint>')
    out.append('</robot>')
    print("\n".join(out))
