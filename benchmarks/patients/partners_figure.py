"""The paper's Fig. 6 on a phantom: a few predicted points of the lips and
their three partners on the post-operative skin, the closest point, the
corresponding point of the TPS-RPM variant and the true partner (the same
skin point, moved by the truth).

Called by skin_report.py. Reads, in a patient's output folder,
skin_<model>_sf.ply (the prediction), skin_<model>_sf_distance.csv (its
correspondence and exact columns) and skin_postoperative.ply.
"""
import os

import numpy as np
import matplotlib
matplotlib.use("Agg")  # headless
import matplotlib.pyplot as plt  # noqa: E402

import render  # noqa: E402  (benchmarks/patients/render.py)


def closest_on_triangles(p, a, b, c):
    """The point of each triangle (rows of A, B, C) closest to P (Ericson,
    Real-Time Collision Detection, 5.1.5), vectorised over the triangles."""
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = (ab * ap).sum(1), (ac * ap).sum(1)
    bp, cp = p - b, p - c
    d3, d4 = (ab * bp).sum(1), (ac * bp).sum(1)
    d5, d6 = (ab * cp).sum(1), (ac * cp).sum(1)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    denom = va + vb + vc
    denom = np.where(denom == 0, 1e-300, denom)
    v, w = vb / denom, vc / denom
    out = a + ab * v[:, None] + ac * w[:, None]  # inside the face
    # Edge regions, then vertex regions (these override the edges).
    on_bc = (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0)
    t = (d4 - d3) / np.where((d4 - d3) + (d5 - d6) == 0, 1e-300,
                             (d4 - d3) + (d5 - d6))
    out[on_bc] = (b + (c - b) * t[:, None])[on_bc]
    on_ac = (vb <= 0) & (d2 >= 0) & (d6 <= 0)
    t = d2 / np.where(d2 - d6 == 0, 1e-300, d2 - d6)
    out[on_ac] = (a + ac * t[:, None])[on_ac]
    on_ab = (vc <= 0) & (d1 >= 0) & (d3 <= 0)
    t = d1 / np.where(d1 - d3 == 0, 1e-300, d1 - d3)
    out[on_ab] = (a + ab * t[:, None])[on_ab]
    out[(d6 >= 0) & (d5 <= d6)] = c[(d6 >= 0) & (d5 <= d6)]
    out[(d3 >= 0) & (d4 <= d3)] = b[(d3 >= 0) & (d4 <= d3)]
    out[(d1 <= 0) & (d2 <= 0)] = a[(d1 <= 0) & (d2 <= 0)]
    return out


def closest_point(p, verts, tris, radius=15.0):
    """The point of the surface (VERTS, TRIS) closest to P, searched among
    the triangles with a corner within RADIUS mm."""
    near = np.linalg.norm(verts - p, axis=1) < radius
    t = tris[near[tris].any(1)]
    q = closest_on_triangles(p, verts[t[:, 0]], verts[t[:, 1]],
                             verts[t[:, 2]])
    return q[np.argmin(np.linalg.norm(q - p, axis=1))]


def plane_cut(verts, tris, x, centre, radius):
    """The segments (k, 2, 2) in (y, z) where the plane at X cuts the
    triangles of (VERTS, TRIS) that have a corner within RADIUS of CENTRE."""
    near = np.linalg.norm(verts - centre, axis=1) < radius
    t = tris[near[tris].any(1)]
    s = verts[t, 0] - x  # (m, 3) signed distances of the corners
    crossing = (s.min(1) < 0) & (s.max(1) > 0)
    segments = []
    for tri, d in zip(t[crossing], s[crossing]):
        ends = []
        for a, b in ((0, 1), (1, 2), (2, 0)):
            if (d[a] < 0) != (d[b] < 0):
                w = d[a] / (d[a] - d[b])
                q = verts[tri[a]] + w * (verts[tri[b]] - verts[tri[a]])
                ends.append(q[1:])
        if len(ends) == 2:
            segments.append(ends)
    return np.array(segments).reshape(-1, 2, 2)


def lip_points(verts, usable, count=6):
    """COUNT points of the midsagittal profile (|x| < 1 mm) of the lips:
    among the usable points between z = -50 and -10 mm (the phantoms' mouth
    region) the front-most (smallest y) per 1 mm of height, evenly spaced
    in height."""
    band = np.nonzero(usable & (np.abs(verts[:, 0]) < 1.0) &
                      (verts[:, 2] > -50) & (verts[:, 2] < -10))[0]
    if len(band) < count:
        return []
    front = {}
    for i in band:
        z = int(np.floor(verts[i, 2]))
        if z not in front or verts[i, 1] < verts[front[z], 1]:
            front[z] = i
    profile = [front[z] for z in sorted(front)]
    picks = np.linspace(0, len(profile) - 1, count).round().astype(int)
    return [profile[k] for k in picks]


def partners_picture(patient_dir, out_png, title, model="linear_fem"):
    """Writes OUT_PNG; returns the rows of a table (point, distances) or
    None if the files are missing."""
    ply = os.path.join(patient_dir, f"skin_{model}_sf.ply")
    dist = os.path.join(patient_dir, f"skin_{model}_sf_distance.csv")
    post = os.path.join(patient_dir, "skin_postoperative.ply")
    if not all(os.path.exists(f) for f in (ply, dist, post)):
        return None
    with open(dist) as f:
        header = f.readline().strip().split(",")
    needed = ["exact distance mm", "correspondence distance mm",
              "to correspondence x mm"]
    if any(h not in header for h in needed):
        return None
    table = np.genfromtxt(dist, delimiter=",", skip_header=1)
    predicted, _ = render.read_ply(ply)
    post_verts, post_tris = render.read_ply(post)
    if len(post_verts) != len(predicted):
        return None
    k = header.index("to correspondence x mm")
    to_rpm = table[:, k:k + 3]
    usable = np.isfinite(to_rpm).all(1)
    points = lip_points(predicted, usable)
    if not points:
        return None

    rows = []
    from matplotlib.collections import LineCollection
    predicted_tris = render.read_ply(ply)[1]
    fig, axes = plt.subplots(2, (len(points) + 1) // 2,
                             figsize=(3.3 * ((len(points) + 1) // 2), 7.2))
    axes = axes.ravel()
    for ax, i in zip(axes, points):
        p = predicted[i]
        partners = {"closest point": closest_point(p, post_verts, post_tris),
                    "TPS-RPM": p + to_rpm[i],
                    "exact": post_verts[i]}
        d = {name: float(np.linalg.norm(q - p))
             for name, q in partners.items()}
        rows.append(dict(point=int(i), x=p[0], y=p[1], z=p[2], **d))
        # The sagittal plane through the point (forward is -y, up z).
        window = max(1.5, 1.3 * max(d.values()))
        for verts, tris, color, label in (
                (post_verts, post_tris, "0.45", "post-operative skin"),
                (predicted, predicted_tris, "C9", "predicted skin")):
            cut = plane_cut(verts, tris, p[0], p, 4 * window)
            cut[..., 0] *= -1
            ax.add_collection(LineCollection(cut, colors=color, lw=1.2,
                                             label=label))
        ax.plot(-p[1], p[2], "ko", ms=4)
        for (name, q), color in zip(partners.items(), ("C0", "C1", "C3")):
            ax.annotate("", xy=(-q[1], q[2]), xytext=(-p[1], p[2]),
                        arrowprops=dict(arrowstyle="->", color=color, lw=1.4))
            ax.plot(-q[1], q[2], "o", color=color, ms=3,
                    label=f"{name} {d[name]:.2f} mm")
        ax.set_xlim(-p[1] - window, -p[1] + window)
        ax.set_ylim(p[2] - window, p[2] + window)
        ax.set_aspect("equal")
        ax.set_title(f"x = {p[0]:.1f}, z = {p[2]:.1f} mm", fontsize=9)
        ax.set_xlabel("forward (-y, mm)", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.legend(fontsize=6, loc="lower left")
    for ax in axes[::(len(points) + 1) // 2]:
        ax.set_ylabel("up (z, mm)", fontsize=8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(out_png, dpi=110)
    plt.close(fig)
    return rows
