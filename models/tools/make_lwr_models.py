#!/usr/bin/env python3
"""Writes models/dlr_lwr3.urdf, models/dlr_lwr3.dcg and models/obj/tip.obj.

Run from the repository root: python3 models/tools/make_lwr_models.py
Plain Python (no numpy). The figures it prints are quoted in models/README.md.
"""
import math

# ---- Published inertial data (facts, cited per link in the URDF) ----------------------------
# kuka-isir/rtt_lwr, lwr_description/urdf/lwr.urdf.xacro (KUKA LWR 4+, CAD-derived): mass,
# COM (link frame) and inertia (ixx ixy ixz iyy iyz izz, about the COM). Link frames there sit
# at z = 0, 0.102, 0.3105, 0.502, 0.7105, 0.902, 1.1005, 1.1785 m with every joint at zero.
ISIR = {
    0: (1.21032454350876, (-0.000638499331014356, 5.02538509694617e-06, 0.0482289968116927),
        (0.0262560565710656, -5.2754950052563e-07, 3.77940202490646e-05, 0.0280724642508563, -2.56972470148208e-07, 0.0306998250407766)),
    1: (2.30339938771869, (-6.33965437334127e-08, 0.0233273473346096, 0.118146290406178),
        (0.156081163626041, 5.97319920503909e-08, -1.64780770629425e-07, 0.153467542173805, 0.0319168949093809, 0.0440736079943446)),
    2: (2.30343543179071, (1.26774962153076e-06, -0.032746486541291, 0.0736556727355962),
        (0.0142348526057094, -3.73763310100809e-08, 1.70703603169075e-07, 0.0141319978448755, 0.00228090337255746, 0.00424792208583136)),
    3: (2.30342143971329, (-1.40921289121243e-06, -0.0233297626126898, 0.11815047247629),
        (0.0156098024078732, 4.75479645197283e-08, 1.17852233217589e-07, 0.0153476851366831, -0.00319215869825882, 0.0044071430916942)),
    4: (2.30343586527606, (1.12239473548659e-07, 0.0327442387470235, 0.073658815701594),
        (0.0142336552604204, -5.89296043886227e-08, -1.568273589226e-07, 0.0141315528954361, -0.00228056254422505, 0.00424816761410708)),
    5: (1.60059828363332, (-6.00824789920296e-07, 0.0207751869661564, 0.0862053948486382),
        (0.00880806620496216, 1.22820321842462e-07, -5.66844221164893e-08, 0.00813520145401624, 0.00261443543508601, 0.00359712267754715)),
    6: (1.49302436988808, (-2.64519244286276e-08, -0.00451753627467652, -0.00295324741635017), None),
    7: (0.108688241139613, (0.0, 0.0, -0.015814675599801), None),
}
ISIR_FRAME_Z = [0.0, 0.102, 0.3105, 0.502, 0.7105, 0.902, 1.1005, 1.1785]

# ---- Our kinematics (thesis appendix C): joint origins with every joint at zero ------------------
JOINT_Z = [None, 0.31, 0.31, 0.71, 0.71, 1.10, 1.10, 1.16]   # J1..J7
VERTICAL = [None, True, False, True, False, True, False, True]  # about z; else about x
# ISIR's shoulder (J2) sits at 0.3105 m, ours at 0.31: links beyond J2 move down 0.5 mm.
SHIFT = [0.0, 0.0, -0.0005, -0.0005, -0.0005, -0.0005, -0.0005, -0.0005]

def rot_zm90_vec(v):  # R_z(-90°): ISIR's y axis (their J2, J4, J6) -> our x axis
    x, y, z = v
    return (y, -x, z)

def rot_zm90_inertia(i):
    ixx, ixy, ixz, iyy, iyz, izz = i
    return (iyy, -ixy, iyz, ixx, -ixz, izz)

def cylinder_inertia(m, r, h, axis):  # solid cylinder about its COM
    a = m * r * r / 2.0
    t = m * (3 * r * r + h * h) / 12.0
    d = {'x': (a, t, t), 'y': (t, a, t), 'z': (t, t, a)}[axis]
    return (d[0], 0.0, 0.0, d[1], 0.0, d[2])

# Estimates replacing ISIR figures that cannot be right (documented in the URDF and README):
# link_0 (I ~ 0.03 kg·m² for 1.2 kg), link_1 (ixx, iyy ten times those of its twin link_3),
# link_6 (0.03 kg·m² for a 1.5 kg wrist), link_7 (0.04-0.07 kg·m² for a 0.11 kg flange).
BASE_EST = cylinder_inertia(ISIR[0][0], 0.07, 0.11, 'z')
LINK6_EST = cylinder_inertia(ISIR[6][0], 0.055, 0.13, 'x')   # in our frame (J6 axis = x)
FLANGE_R, FLANGE_H = 0.04, 0.02
CONE_R, CONE_H, CONE_DENSITY, CONE_SEGMENTS = 0.03, 0.15, 1000.0, 48

def add(a, b): return tuple(x + y for x, y in zip(a, b))
def sub(a, b): return tuple(x - y for x, y in zip(a, b))
def scale(a, s): return tuple(x * s for x in a)

links = {}  # k -> (mass, com_world(our frame), inertia6 about COM, our frame)
for k in range(0, 7):
    m, com, inertia = ISIR[k]
    world = list(rot_zm90_vec(com))
    world[2] += ISIR_FRAME_Z[k] + SHIFT[k]
    if k == 0:
        inertia6 = BASE_EST
    elif k == 1:   # twin of link_3 (same mass and shape, mirrored): use link_3's moments
        i3 = rot_zm90_inertia(ISIR[3][2])
        inertia6 = (i3[0], -i3[1], -i3[2], i3[3], i3[4], i3[5])  # mirror x -> -x
    elif k == 6:
        inertia6 = LINK6_EST
    else:
        inertia6 = rot_zm90_inertia(inertia)
    links[k] = (m, tuple(world), inertia6)

# link_7 = ISIR flange (cylinder estimate) + our tip cone (the thesis replaced the hand by a cone)
flange_m = ISIR[7][0]
flange_com = (0.0, 0.0, ISIR_FRAME_Z[7] + SHIFT[7] + ISIR[7][1][2])
flange_top = ISIR_FRAME_Z[7] + SHIFT[7]
cone_m = CONE_DENSITY * math.pi * CONE_R ** 2 * CONE_H / 3.0
cone_com = (0.0, 0.0, flange_top + CONE_H / 4.0)
m7 = flange_m + cone_m
com7 = scale(add(scale(flange_com, flange_m), scale(cone_com, cone_m)), 1.0 / m7)
fi = cylinder_inertia(flange_m, FLANGE_R, FLANGE_H, 'z')
cone_axial = 0.3 * cone_m * CONE_R ** 2
cone_perp = cone_m * (3.0 / 20.0 * CONE_R ** 2 + 3.0 / 80.0 * CONE_H ** 2)
def shifted_perp(i, m, dz): return i + m * dz * dz
ixx7 = shifted_perp(fi[0], flange_m, flange_com[2] - com7[2]) + shifted_perp(cone_perp, cone_m, cone_com[2] - com7[2])
izz7 = fi[5] + cone_axial
links[7] = (m7, com7, (ixx7, 0.0, 0.0, ixx7, 0.0, izz7))
EE_OFFSET = flange_top + CONE_H - JOINT_Z[7]

def frame_z(k):  # our link frame origin (world z) at zero configuration
    return 0.0 if k == 0 else JOINT_Z[k]

def fmt(x): return f"{x:.6g}"
def fmtv(v): return " ".join(fmt(x) for x in v)

# ---- Effort, velocity, position limits, damping, armature ---------------------------------------
EFFORT = [None, 176, 176, 100, 100, 100, 30, 30]
VEL_DEG = [None, 112.5, 112.5, 112.5, 112.5, 180.0, 112.5, 112.5]
LIMIT_DEG = [None, 170, 120, 170, 120, 170, 120, 170]
DAMPING = [None, 0.2, 0.2, 0.1, 0.1, 0.05, 0.05, 0.05]
REDUCTION = 160
ROTOR = [None, 1.0e-5, 1.0e-5, 1.0e-5, 1.0e-5, 0.4e-5, 0.4e-5, 0.4e-5]
START_DEG = [None, 0, -45, 90, 90, 0, 0, 0]   # thesis appendix C a(...)

SOURCE = {
    0: "mass, COM: kuka-isir/rtt_lwr lwr_description/urdf/lwr.urdf.xacro link_0; inertia: estimate (solid cylinder r 0.07 m, h 0.11 m) because the published 0.026-0.031 kg m^2 is ten times what a 1.2 kg base can have",
    1: "mass, COM: rtt_lwr link_1; inertia: that of its mirror twin link_3 (the published ixx, iyy = 0.156, 0.153 are ten times link_3's 0.0156, 0.0153: a decimal slip)",
    2: "mass, COM, inertia: rtt_lwr link_2",
    3: "mass, COM, inertia: rtt_lwr link_3",
    4: "mass, COM, inertia: rtt_lwr link_4",
    5: "mass, COM, inertia: rtt_lwr link_5",
    6: "mass, COM: rtt_lwr link_6; inertia: estimate (solid cylinder r 0.055 m, h 0.13 m along the J6 axis) because the published 0.03 kg m^2 is twenty times too large for a 1.5 kg wrist",
    7: "flange mass, COM: rtt_lwr link_7 (its 0.04-0.07 kg m^2 inertia is impossible for 0.11 kg; estimate: cylinder r 0.04 m, h 0.02 m) plus the tip cone that replaces the hand (thesis 5.4): r 0.03 m, h 0.15 m, 1000 kg/m^3",
}

def urdf():
    out = []
    w = out.append
    w('<?xml version="1.0"?>')
    w('<!-- A 7-DOF arm modelled on the DLR LWR III / KUKA LWR 4+, written for armfarm.')
    w('     Generated by models/tools/make_lwr_models.py (see models/README.md for every convention).')
    w('     Kinematics: thesis appendix C (shoulder 0.31 m, upper arm 0.40 m, forearm 0.39 m, J7 0.06 m')
    w('     above the wrist); all joints at zero = arm straight up; J1, J3, J5, J7 turn about z, J2, J4, J6 about x.')
    w('     Link frames sit at their joint origin, parallel to the world frame at zero angles.')
    w('     Masses/COMs/inertias: KUKA LWR 4+ figures from kuka-isir/rtt_lwr (CAD-derived), rotated by')
    w('     -90 deg about z so that their J2/J4/J6 axis (y) becomes our x; per-link notes below.')
    w('     Effort limits 176/176/100/100/100/30/30 N m: the KUKA LWR 4+ torque limits as commonly quoted')
    w('     (rtt_lwr uses 200/200/100/100/100/30/30). Velocity limits 112.5 deg/s (J5 180 deg/s): rtt_lwr.')
    w('     Position limits +-170 deg (J1, J3, J5, J7) and +-120 deg (J2, J4, J6): rtt_lwr / LWR data sheet.')
    w('     Armature: Harmonic Drive reduction 160 (DLR LWR III, Albu-Schaeffer et al. 2007) and rotor')
    w('     inertia 1e-5 kg m^2 (Robotics Toolbox LWR IV model lwr_create, Jm) for J1-J4; 0.4e-5 kg m^2 for')
    w('     the smaller wrist motors J5-J7 (estimate). armature = rotorInertia * reduction^2. -->')
    w('<robot name="dlr_lwr3" xmlns:armfarm="https://armfarm.invalid/urdf-extensions">')
    w('  <link name="world"/>')
    w('  <joint name="mount" type="fixed">')
    w('    <parent link="world"/>')
    w('    <child link="link_0"/>')
    w('    <origin xyz="0 0 0" rpy="0 0 0"/>')
    w('  </joint>')
    for k in range(0, 8):
        m, com_world, i6 = links[k]
        com = sub(com_world, (0.0, 0.0, frame_z(k)))
        w(f'  <!-- link_{k}: {SOURCE[k]} -->')
        w(f'  <link name="link_{k}">')
        w('    <inertial>')
        w(f'      <origin xyz="{fmtv(com)}" rpy="0 0 0"/>')
        w(f'      <mass value="{fmt(m)}"/>')
        w(f'      <inertia ixx="{fmt(i6[0])}" ixy="{fmt(i6[1])}" ixz="{fmt(i6[2])}" iyy="{fmt(i6[3])}" iyz="{fmt(i6[4])}" izz="{fmt(i6[5])}"/>')
        w('    </inertial>')
        w('  </link>')
        if k == 7:
            break
        j = k + 1
        parent_z = frame_z(k)
        w(f'  <joint name="joint_{j}" type="revolute">')
        w(f'    <parent link="link_{k}"/>')
        w(f'    <child link="link_{j}"/>')
        w(f'    <origin xyz="0 0 {fmt(JOINT_Z[j] - parent_z)}" rpy="0 0 0"/>')
        w(f'    <axis xyz="{"0 0 1" if VERTICAL[j] else "1 0 0"}"/>')
        lim = math.radians(LIMIT_DEG[j])
        w(f'    <limit lower="{-lim:.10g}" upper="{lim:.10g}" effort="{EFFORT[j]}" velocity="{math.radians(VEL_DEG[j]):.10g}"/>')
        w(f'    <dynamics damping="{DAMPING[j]}" friction="0"/>')
        w('  </joint>')
    for j in range(1, 8):
        w(f'  <transmission name="transmission_{j}">')
        w('    <type>transmission_interface/SimpleTransmission</type>')
        w(f'    <joint name="joint_{j}"><hardwareInterface>hardware_interface/EffortJointInterface</hardwareInterface></joint>')
        w(f'    <actuator name="motor_{j}">')
        w(f'      <mechanicalReduction>{REDUCTION}</mechanicalReduction>')
        w(f'      <rotorInertia>{ROTOR[j]:g}</rotorInertia>')
        w('    </actuator>')
        w('  </transmission>')
    w(f'  <!-- End effector: the apex of the tip cone, {fmt(EE_OFFSET)} m beyond J7. -->')
    w(f'  <armfarm:end_effector link="link_7" offset="0 0 {fmt(EE_OFFSET)}"/>')
    w('  <!-- Start posture of thesis appendix C: a(0) a(-45) a(90) a(90) a(0) a(0) a(0). -->')
    for j in range(1, 8):
        if START_DEG[j] != 0:
            w(f'  <armfarm:start_position joint="joint_{j}" value="{math.radians(START_DEG[j]):.10g}"/>')
    w('</robot>')
    return "\n".join(out) + "\n"

# ---- DCG: primitive bodies approximating the URDF's links -------------------------------------
def capsule(m, r, l):
    cyl = math.pi * r * r * l
    caps = 4.0 / 3.0 * math.pi * r ** 3
    v = cyl + caps
    mc, mh = m * cyl / v, m * caps / v
    t = mc * (r * r / 4 + l * l / 12) + mh * (0.4 * r * r + 0.375 * r * l + 0.25 * l * l)
    a = mc * r * r / 2 + mh * 0.4 * r * r
    return t, a

def fit_capsule(m, transverse, axial):
    best = None
    for i in range(1, 400):
        r = i * 0.0005
        for j in range(0, 800):
            l = j * 0.001
            t, a = capsule(m, r, l)
            err = ((t - transverse) / transverse) ** 2 + ((a - axial) / axial) ** 2
            if best is None or err < best[0]:
                best = (err, r, l)
    return best[1], best[2]

def cone_obj():
    lines = ["# Tip cone of dlr_lwr3.dcg link7 (generated by models/tools/make_lwr_models.py).",
             f"# Base circle radius {CONE_R} m at z = {fmt(flange_top - JOINT_Z[7])} m, apex at z = {fmt(flange_top - JOINT_Z[7] + CONE_H)} m (link7 frame = J7 frame).",
             "# Faces are counter-clockwise seen from outside; the base is one polygon (fan-triangulated on reading)."]
    z0 = flange_top - JOINT_Z[7]
    for s in range(CONE_SEGMENTS):
        a = 2 * math.pi * s / CONE_SEGMENTS
        lines.append(f"v {CONE_R * math.cos(a):.9f} {CONE_R * math.sin(a):.9f} {z0:.9f}")
    lines.append(f"v 0 0 {z0 + CONE_H:.9f}")
    apex = CONE_SEGMENTS + 1
    for s in range(CONE_SEGMENTS):
        a, b = s + 1, (s + 1) % CONE_SEGMENTS + 1
        lines.append(f"f {a} {b} {apex}")
    lines.append("f " + " ".join(str(CONE_SEGMENTS - s) for s in range(CONE_SEGMENTS)))
    return "\n".join(lines) + "\n"

def dcg():
    out = []
    w = out.append
    w("# dlr_lwr3.dcg: the arm of dlr_lwr3.urdf in the thesis's DCG format (appendix B/C), with")
    w("# primitive bodies. Generated by models/tools/make_lwr_models.py; conventions in models/README.md.")
    w("# Each body frame sits at the link's centre of mass (parallel to the world at zero angles), so the")
    w("# primitive is centred on it; w(...) gives the URDF's mass, the primitive's shape the inertia")
    w("# (an approximation: see models/README.md for the per-link differences). Hinges turn about the")
    w("# joint frame's x axis; d(90 0 -1 0) || d(90 0 1 0) makes a joint about the parent's z axis.")
    w("# Extension tags: effort(N m) vel(deg/s) damp(N m s/rad) arm(kg m^2) ee(x y z).")
    w("<DCGraph>")
    w("B floor <t(0 0 -0.05)> o(1) s(1 1 0.1) c(0.2 0.2 1) fix;")
    body_origin = {}
    for k in range(0, 8):
        m, com, i6 = links[k]
        name = "base" if k == 0 else f"link{k}"
        if k == 7:
            # trimesh: body frame at J7, mesh vertices in it; X places the combined COM.
            body_origin[k] = (0.0, 0.0, JOINT_Z[7])
            comb = sub(com, body_origin[k])
            w(f"B {name} <> f[obj/tip.obj] o(3) w({fmt(m)}) X({fmtv(comb)}) c(0.8 0.25 0.25) ee(0 0 {fmt(EE_OFFSET)});")
        elif k == 6:
            body_origin[k] = com
            mean = (i6[0] + i6[3] + i6[5]) / 3.0
            r = math.sqrt(mean / (0.4 * m))
            density = m / (4.0 / 3.0 * math.pi * r ** 3)
            w(f"B {name} <> o(0) s({fmt(r)}) m({density:.8g}) c(0.5 0.5 1);")
        elif k == 0:
            body_origin[k] = com  # a box reproduces a diagonal inertia exactly
            sx = math.sqrt(6 * (i6[3] + i6[5] - i6[0]) / m)
            sy = math.sqrt(6 * (i6[0] + i6[5] - i6[3]) / m)
            sz = math.sqrt(6 * (i6[0] + i6[3] - i6[5]) / m)
            w(f"B {name} <> o(1) s({fmt(sx)} {fmt(sy)} {fmt(sz)}) w({fmt(m)}) c(0.7 0.7 0.7);")
        else:
            body_origin[k] = com
            r, l = fit_capsule(m, (i6[0] + i6[3]) / 2.0, i6[5])
            w(f"B {name} <> o(2) s({fmt(r)} {fmt(l)}) w({fmt(m)}) c({'0.15 0.15 1' if k % 2 else '0.5 0.5 1'});")
        if k == 0:
            w(f"J floor-base <t({fmtv(sub(body_origin[0], (0.0, 0.0, -0.05)))})> j(7);")
        else:
            joint = (0.0, 0.0, JOINT_Z[k])
            parent = "base" if k == 1 else f"link{k-1}"
            before = f"t({fmtv(sub(joint, body_origin[k-1]))})"
            after = f"t({fmtv(sub(body_origin[k], joint))})"
            rot_b, rot_a = ("d(90 0 -1 0) ", "d(90 0 1 0) ") if VERTICAL[k] else ("", "")
            lim = LIMIT_DEG[k]
            w(f"J {parent}-{name} <{before} {rot_b}|| {rot_a}{after}> a({START_DEG[k]}) p({-lim} {lim}) "
              f"effort({EFFORT[k]}) vel({VEL_DEG[k]:g}) damp({DAMPING[k]}) arm({ROTOR[k] * REDUCTION ** 2:.6g});")
    w("</DCGraph>")
    return "\n".join(out) + "\n"

if __name__ == "__main__":
    with open("models/dlr_lwr3.urdf", "w") as f: f.write(urdf())
    with open("models/dlr_lwr3.dcg", "w") as f: f.write(dcg())
    with open("models/obj/tip.obj", "w") as f: f.write(cone_obj())
    total = sum(links[k][0] for k in links)
    reach = 0.4 + 0.39 + 0.06 + EE_OFFSET
    print(f"total mass {total:.4f} kg (links 0-7), moving links 1-7 {total - links[0][0]:.4f} kg")
    print(f"end-effector offset {EE_OFFSET:.4f} m, reach from J1 {reach:.4f} m")

def report_inertia_differences():
    """Relative Frobenius difference |I_dcg - I_urdf| / |I_urdf| per link (both about the COM, world-aligned frames)."""
    for k in range(0, 8):
        m, com, i6 = links[k]
        full = [[i6[0], i6[1], i6[2]], [i6[1], i6[3], i6[4]], [i6[2], i6[4], i6[5]]]
        if k == 0:
            approx = (i6[0], i6[3], i6[5])
        elif k == 6:
            mean = (i6[0] + i6[3] + i6[5]) / 3.0
            approx = (mean, mean, mean)
        elif k == 7:
            axial = 0.3 * m * CONE_R ** 2
            perp = m * (3.0 / 20.0 * CONE_R ** 2 + 3.0 / 80.0 * CONE_H ** 2)
            approx = (perp, perp, axial)
        else:
            r, l = fit_capsule(m, (i6[0] + i6[3]) / 2.0, i6[5])
            t, a = capsule(m, r, l)
            approx = (t, t, a)
        diff = sum((full[i][j] - (approx[i] if i == j else 0.0)) ** 2 for i in range(3) for j in range(3))
        norm = sum(full[i][j] ** 2 for i in range(3) for j in range(3))
        print(f"link {k}: mass {m:.4f} kg, inertia difference {100 * math.sqrt(diff / norm):.1f} %")

if __name__ == "__main__":
    report_inertia_differences()
