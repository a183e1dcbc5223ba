#!/usr/bin/python3
"""Writes the phantom patients' scenes: prm/patients/P1.prm ... P10.prm and
the quick-start prm/patient.prm.

The patients follow the paper's Table 2 (Mollemans et al. 2007): the same
procedures (MSB mandibular set-back, MA mandibular advancement, G
genioplasty, MxA maxillary advancement, MxSB maxillary set-back) with planned
bone motions whose largest magnitude is the paper's largest soft-tissue
motion M_max, and about the same numbers of tetrahedra. Their anatomy
(face width and height, soft-tissue thickness, mandible length and angle,
skeletal class) varies. Every patient gets the same osteotomy (Le Fort I,
bilateral sagittal split, genioplasty) and six bone segments; the planning
moves only the segments its procedure names.

Usage: /usr/bin/python3 benchmarks/patients/make_scenes.py  (from the
repository's root; it overwrites prm/patients/P*.prm and prm/patient.prm). Only the standard
library is needed.
"""
import math
import os
import random

# The phantom's landmarks (source/patient/phantom.cc, Phantom::Phantom) for
# the seed points, which must lie in each segment's bone.
OCCLUSION = -20.0


def place(gonion, p0, length, angle, shift):
    """A mandible point after length, gonial angle and profile."""
    p = [g + length * (q - g) for g, q in zip(gonion, p0)]
    turn = (angle - 120.0) * math.pi / 180.0
    dy, dz = p[1] - gonion[1], p[2] - gonion[2]
    c, s = math.cos(-turn), math.sin(-turn)
    p = [p[0], gonion[1] + c * dy + s * dz, gonion[2] - s * dy + c * dz]
    p[1] -= shift * (gonion[1] - p[1]) / (gonion[1] + 62.0)
    return p


# name, procedure, the paper's N_tetra and M_max, anatomy, motions (mm; -y is
# forward, +z up). A motion is (translation, rotation angle about x through
# the segment's join points, degrees).
PATIENTS = [
    ("P1", "MSB + G", 129955, 8.1,
     dict(width=1.04, height=1.05, tissue=2, length=1.06, angle=124,
          profile="class III", discrepancy=8),
     {"mandible": (0, 8.1, 0), "chin": (0, 5.0, 3.0)}),
    ("P2", "G + MxA", 74232, 9.5,
     dict(width=0.96, height=0.98, tissue=0, length=1.0, angle=120,
          profile="class I", discrepancy=0),
     {"maxilla": (0, -5.0, 0), "chin": (0, -9.2, 2.4)}),
    ("P3", "MSB + MxA", 85213, 4.9,
     dict(width=1.0, height=1.0, tissue=1, length=1.05, angle=122,
          profile="class III", discrepancy=5),
     {"mandible": (0, 4.9, 0), "maxilla": (0, -3.0, 0)}),
    ("P4", "MA", 66286, 4.3,
     dict(width=0.98, height=0.96, tissue=-1, length=0.95, angle=118,
          profile="class II", discrepancy=4),
     {"mandible": (0, -4.3, 0)}),
    ("P5", "MA + G + MxA", 79716, 16.7,
     dict(width=1.02, height=1.04, tissue=3, length=0.9, angle=126,
          profile="class II", discrepancy=10),
     {"maxilla": (0, -5.0, 0), "mandible": (0, -10.0, 0),
      "chin": (0, -16.2, -4.0)}),
    ("P6", "MA + MxA", 79125, 6.3,
     dict(width=1.0, height=1.02, tissue=1, length=0.94, angle=120,
          profile="class II", discrepancy=6),
     {"maxilla": (0, -4.0, 0), "mandible": (0, -6.3, 0)}),
    ("P7", "MA + MxA", 75314, 9.6,
     dict(width=0.95, height=1.0, tissue=2, length=0.92, angle=125,
          profile="class II", discrepancy=9),
     {"maxilla": (0, -5.0, 2.0), "mandible": (0, -9.6, 0)}),
    ("P8", "MA + G + MxA", 303745, 9.9,
     dict(width=1.06, height=1.0, tissue=4, length=0.95, angle=121,
          profile="class II", discrepancy=7),
     {"maxilla": (0, -4.0, 0), "mandible": (0, -7.0, 0),
      "chin": (0, -9.6, 2.5)}),
    ("P9", "MA + G + MxSB", 80654, 13.8,
     dict(width=0.97, height=1.06, tissue=0, length=0.92, angle=128,
          profile="class II", discrepancy=9),
     {"maxilla": (0, 3.0, 0), "mandible": (0, -9.0, 0),
      "chin": (0, -13.4, -3.3)}),
    ("P10", "MA + G + MxA", 91925, 9.5,
     dict(width=1.03, height=0.97, tissue=1, length=0.96, angle=119,
          profile="class II", discrepancy=6),
     {"maxilla": (0, -4.0, 0), "mandible": (0, -6.0, 0),
      "chin": (0, -9.3, 2.0)}),
]


def vec(v):
    return ", ".join(f"{x:g}" for x in v)


def scene(name, procedure, n_tets, m_max, a, motions, models, directory,
          comment, truth=None, errors=None):
    """truth: the file name of the scene that makes this one's post-operative
    skin; errors (a truth scene's): segment -> (translation error, rotation
    axis, angle in degrees) added to the planned motion, the rotation about
    the segment's seed point."""
    W, H = a["width"], a["height"]
    shift = {"class II": -a["discrepancy"], "class III": a["discrepancy"],
             "class I": 0.0}[a["profile"]]
    gonion = [46.0 * W, 10.0, -60.0]
    body = place(gonion, [30.0 * W, -38.0, -52.0], a["length"], a["angle"],
                 shift)
    symphysis = place(gonion, [0.0, -62.0, -52.0], a["length"], a["angle"],
                      shift)
    # The lower alveolus (and the teeth's roots in it) moves with the chin.
    chin_advance = -(symphysis[1] + 62.0)
    chin_drop = -(symphysis[2] + 52.0)
    # The genioplasty runs below the lower teeth's roots, out through the
    # lower border on both sides.
    g_top = OCCLUSION - 30.0 * H - chin_drop
    # Seeds: the mandible's alveolus above the genioplasty, the chin below
    # it, the rami above the split.
    mandible = [-15.0 * W, -58.4 - chin_advance, g_top + 8.0]
    chin = [0.0, symphysis[1], symphysis[2] - 6.0]
    ramus = [48.0 * W, 12.0, -30.0]
    g_box_y = symphysis[1] + 45.0
    # A setback moves the mandible's body backwards into the rami across the
    # splits. The surgeon trims the overlapping bone and strips the tissue
    # around it; a frontal cut with the 3 mm margin of the other cuts would
    # crush the tissue pinned to both parts instead (every Neo-Hooke model
    # then inverts tetrahedra there before full load). The splits' margin is
    # the setback plus 2 mm.
    setback = max(0.0, motions.get("mandible", (0, 0, 0))[1])
    setback_comment, setback_margin = [], []
    if setback > 0:
        margin = round(setback + 2.0, 1)
        setback_comment = [
            f"      # A setback of {setback:g} mm: the surgeon trims the bone "
            "that the",
            "      # body pushes into the rami and strips the tissue around "
            "it; the",
            "      # splits' detached margin is the setback plus 2 mm.",
        ]
        setback_margin = [f"        set Detached margin = {margin:g}"]
    lines = [f"# {comment}", "#",
             "# Written by benchmarks/patients/make_scenes.py; run with",
             f"#   ./run.sh prm/patients/{name}.prm", ""]
    lines += [
        "subsection Scene",
        "  set Mesh source   = patient",
        "  set Bone segments = cranium, maxilla, ramus right, ramus left, "
        "mandible, chin",
        "  subsection Segment cranium",
        "    set Seed point = 0, -40, 30",
        "  end",
        "  subsection Segment maxilla",
        f"    set Seed point = 0, -66, {OCCLUSION + 12.0 * H:g}",
        "  end",
        "  subsection Segment ramus right",
        f"    set Seed point = {vec([-ramus[0], ramus[1], ramus[2]])}",
        "  end",
        "  subsection Segment ramus left",
        f"    set Seed point = {vec(ramus)}",
        "  end",
        "  subsection Segment mandible",
        f"    set Seed point = {vec([round(x, 1) for x in mandible])}",
        "  end",
        "  subsection Segment chin",
        f"    set Seed point = {vec([round(x, 1) for x in chin])}",
        "  end",
        "  subsection Patient",
        "    # The region of the face that deforms (the paper, Sec. 3.1): below the "
        "eyes, in",
        "    # front of the ears, down to the neck. Where it cuts the soft "
        "tissue, the",
        "    # tissue is held by the cranium.",
        "    set Cut held by = cranium",
        "    subsection Region of interest",
        "      set Box = -85, -130, -100; 85, 25, 35",
        "    end",
        "    subsection Phantom",
        f"      set Face width            = {W:g}",
        f"      set Face height           = {H:g}",
        f"      set Soft tissue thickness = {a['tissue']:g}",
        f"      set Mandible length       = {a['length']:g}",
        f"      set Mandible angle        = {a['angle']:g}",
        f"      set Profile               = {a['profile']}",
        f"      set Jaw discrepancy       = {a['discrepancy']:g}",
        f"      set Seed                  = {name[1:]}",
        "    end",
        "    subsection Mesh",
        f"      set Target number of tetrahedra = {n_tets}",
        "    end",
        "    subsection Osteotomy",
        "      set Cuts = le fort I, bsso right, bsso left, genioplasty",
        "      subsection Cut le fort I",
        "        set Point  = 0, 0, 0",
        "        set Normal = 0, 0, 1",
        "        set Box    = -80, -110, -8; 80, 0, 8",
        "      end",
        "      # The sagittal splits, simplified to frontal planes through the",
        "      # mandibular body in front of the gonial angles.",
    ] + setback_comment + [
        "      subsection Cut bsso right",
        "        set Point  = 0, -5, 0",
        "        set Normal = 0, 1, 0",
        "        set Box    = -80, -20, -95; -20, 10, -15",
    ] + setback_margin + [
        "      end",
        "      subsection Cut bsso left",
        "        set Point  = 0, -5, 0",
        "        set Normal = 0, 1, 0",
        "        set Box    = 20, -20, -95; 80, 10, -15",
    ] + setback_margin + [
        "      end",
        "      subsection Cut genioplasty",
        "        set Type            = swept polyline",
        f"        set Polyline        = -32, 0, -95; -20, 0, {g_top:g}; "
        f"20, 0, {g_top:g}; 32, 0, -95",
        "        set Sweep direction = 0, 1, 0",
        f"        set Box             = -40, -115, -115; 40, {g_box_y:g}, "
        "-40",
        "      end",
        "    end",
        "  end",
        "end",
        "",
        "subsection Material",
        "  set Young's modulus = 3000",
        "  set Poisson's ratio = 0.46",
        "end",
        "",
        "subsection Planning",
        f"  # {procedure}: largest planned bone motion {m_max:g} mm "
        "(the paper's M_max).",
        f"  set Moved segments = {', '.join(motions)}",
    ]
    seeds = {"maxilla": [0, -66, round(OCCLUSION + 12.0 * H, 6)],
             "mandible": [round(x, 1) for x in mandible],
             "chin": [round(x, 1) for x in chin]}
    for segment, t in motions.items():
        lines += [f"  subsection Motion {segment}"]
        if errors and segment in errors:
            dt, axis, angle = errors[segment]
            lines += [
                f"    # Planned: translation {vec(t)}; the known error: "
                f"{vec(dt)} mm and {angle:.3f} degrees",
                f"    # about {vec(axis)} through the seed point.",
                f"    set Translation     = {vec([a + b for a, b in zip(t, dt)])}",
                f"    set Rotation axis   = {vec(axis)}",
                f"    set Rotation angle  = {angle:.4f}",
                f"    set Rotation centre = {vec(seeds[segment])}"]
        else:
            lines += [f"    set Translation = {vec(t)}"]
        lines += ["  end"]
    lines += [
        "end",
        "",
        "subsection Models",
        f"  set Models = {models}",
        "  subsection linear fem",
        "    set Solver = cg amg",
        "  end",
        "  subsection mass tensor",
        "    set Stop gradient threshold = 0.001",
        "  end",
        "  subsection mass spring",
        "    set Stop threshold = 0.001",
        "  end",
        "  subsection nonlinear fem",
        "    set Material law = neo-hooke",
        "    set Solver       = cg amg",
        "  end",
        "  subsection reference fem",
        "    set Material law = neo-hooke",
        "    set Solver       = cg amg",
        "  end",
        "end",
        "",
        "subsection Output",
        f"  set Output directory = {directory}",
        "end",
        "",
    ]
    if errors is not None:
        lines += [
            "# The truth is richer than the models it judges: skin, fat and",
            "# muscle with their own moduli (doc/effects.md). Gravity is left",
            "# out: the CT shows the face already in equilibrium under gravity",
            "# (supine), so adding it would move the face before any surgery.",
            "# Sliding contact and separated lips are not simulated by the",
            "# quadratic reference model.",
            "subsection Effects",
            "  set Effects = heterogeneous tissue",
            "  subsection heterogeneous tissue",
            "    set Young's moduli = 1: 15000, 2: 3000, 3: 6000",
            "  end",
            "end",
            ""]
    if truth is not None:
        lines += [
            "subsection Skin",
            "  # Every model's prediction mapped onto the dense skin both ways",
            "  # (the paper, Sec. 3.4) and measured against the post-operative skin that",
            f"  # {truth} makes (run first, then reused).",
            "  set Mapping             = shape functions, inverse distance",
            f"  set Post-operative skin = {truth}",
            "end",
            ""]
    return "\n".join(lines)


def planning_errors(name, motions):
    """The truth's known planning error for each moved segment (the paper, Sec. 3.2:
    the residual mismatch between planned and achieved bone positions, about
    1 mm): a translation of 0.7 mm and a rotation of 0.6 degrees about the
    segment's seed point (about 0.5 mm at 50 mm), in random directions drawn
    from a generator seeded with the patient's name."""
    generator = random.Random(name)
    errors = {}
    for segment in motions:
        directions = []
        for _ in range(2):
            v = [generator.gauss(0, 1) for _ in range(3)]
            norm = math.sqrt(sum(x * x for x in v))
            directions.append([round(x / norm, 4) for x in v])
        errors[segment] = ([round(0.7 * x, 3) for x in directions[0]],
                           directions[1], 0.6)
    return errors


ALL = "linear fem, mass tensor, mass spring, nonlinear fem"
TRUTH_COMMENT = (
    "The post-operative truth of phantom patient {name}: made by a "
    "model richer\n# than the ones it judges (quadratic Neo-Hooke, skin, fat "
    "and muscle) and driven by\n# the planning plus a known error. Distances "
    "to it measure what the predicting\n# models leave out, not the distance "
    "to a real patient. Its skin_reference_fem.ply\n# is the post-operative "
    "skin of {name}.prm, which runs it.")

if __name__ == "__main__":
    os.makedirs("prm/patients", exist_ok=True)
    for name, procedure, n_tets, m_max, anatomy, motions in PATIENTS:
        text = scene(name, procedure, n_tets, m_max, anatomy, motions, ALL,
                     f"output/patients/{name}",
                     f"Phantom patient {name} after the paper's Table 2: "
                     f"{procedure}, {n_tets} tetrahedra in the paper.",
                     truth=f"{name}_truth.prm")
        with open(f"prm/patients/{name}.prm", "w") as f:
            f.write(text)
        text = scene(name, procedure, n_tets, m_max, anatomy, motions,
                     "reference fem", f"output/patients/{name}_truth",
                     TRUTH_COMMENT.format(name=name),
                     errors=planning_errors(name, motions))
        text = text.replace(f"prm/patients/{name}.prm",
                            f"prm/patients/{name}_truth.prm")
        with open(f"prm/patients/{name}_truth.prm", "w") as f:
            f.write(text)
    # The quick-start patient: an average class II face, mandibular
    # advancement and genioplasty, all four models, and its truth.
    p0 = ("P0", "MA + G", 60000, 8.2,
          dict(width=1.0, height=1.0, tissue=1, length=0.96, angle=120,
               profile="class II", discrepancy=6),
          {"mandible": (0, -6.0, 0), "chin": (0, -8.0, 2.0)})
    text = scene(*p0, ALL, "output/patient",
                 "A phantom patient end to end (the paper, Sec. 3.1-3.4): CT -> labels "
                 "-> surfaces -> mesh ->\n# bone segments -> the four models "
                 "-> the predicted skins and their distance to\n# the "
                 "post-operative skin (made by prm/patient_truth.prm). Files "
                 "of the patient\n# stages go to output/patient/patient/ and "
                 "are reused while their inputs do\n# not change.",
                 truth="patient_truth.prm")
    text = text.replace("prm/patients/P0.prm", "prm/patient.prm")
    with open("prm/patient.prm", "w") as f:
        f.write(text)
    text = scene(*p0, "reference fem", "output/patient_truth",
                 TRUTH_COMMENT.format(name="prm/patient.prm").replace(
                     "skin of prm/patient.prm.prm", "skin of prm/patient.prm"),
                 errors=planning_errors("P0", p0[5]))
    text = text.replace("prm/patients/P0.prm", "prm/patient_truth.prm")
    with open("prm/patient_truth.prm", "w") as f:
        f.write(text)
    print("wrote prm/patients/P1.prm ... P10.prm, their truths P*_truth.prm, "
          "prm/patient.prm and prm/patient_truth.prm")
