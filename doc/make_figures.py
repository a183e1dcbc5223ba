#!/usr/bin/python3
"""The explanatory figures of the manual, drawn from softface's outputs.

Run by doc/make_figures.sh, which runs the scenes first:

    /usr/bin/python3 doc/make_figures.py --cube CUBE_OUTPUT --patient PATIENT_OUTPUT \
        --out doc/images [--only NAME ...]

CUBE_OUTPUT is the output folder of `softface prm/default.prm` (solution.vtu);
PATIENT_OUTPUT the output folder of `softface prm/patient.prm` (solution.vtu,
skin_*.vtp, and its work directory patient/ with mesh.vtu and skin.vtp).

VTK reads the files and finds closest points; matplotlib draws (Agg, no
display needed): surfaces are drawn as flat-shaded triangles sorted back to
front under an orthographic camera, which needs no OpenGL (VTK's offscreen
rendering needs an X server in Debian's VTK 9.1).

The figures and what they read:
- cube_boundary_conditions.png, solution_view.png: the cube's solution.vtu;
- join_and_free_points.png: the patient's solution.vtu (join_point,
  segment_id) and input.prm (the segments' names);
- mesh_and_skin.png: patient/mesh.vtu (its skin triangles) and patient/skin.vtp;
- closest_vs_corresponding.png: skin_<lip model>_sf.vtp ('to correspondence',
  'to exact partner'), skin_postoperative.vtp, skin_preoperative.vtp;
- predicted_face.png: skin_<model>_sf.vtp ('signed distance').
All output is deterministic: the same inputs give the same PNGs, byte for byte.
"""

import argparse
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import vtk  # noqa: E402
from matplotlib import colors as mcolors  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from vtk.util.numpy_support import (numpy_to_vtk, numpy_to_vtkIdTypeArray,  # noqa: E402
                                    vtk_to_numpy)

DPI = 100
plt.rcParams.update({
    "font.size": 13,
    "axes.titlesize": 14,
    "axes.labelsize": 13,
    "legend.fontsize": 12,
    "savefig.dpi": DPI,
    "font.family": "DejaVu Sans",
})


# --------------------------------------------------------------------------
# Reading
# --------------------------------------------------------------------------

def read_vtu(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def read_vtp(path):
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def point_array(data, name):
    array = data.GetPointData().GetArray(name)
    if array is None:
        names = [data.GetPointData().GetArrayName(i)
                 for i in range(data.GetPointData().GetNumberOfArrays())]
        raise KeyError(f"no point array '{name}' (has: {', '.join(names)})")
    return vtk_to_numpy(array).astype(float)


def points_of(data):
    return vtk_to_numpy(data.GetPoints().GetData()).astype(float)


def cells_of(grid, cell_type, size):
    """Connectivity of the cells of one VTK type, as an (n, size) array."""
    offsets = vtk_to_numpy(grid.GetCells().GetOffsetsArray())
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray())
    types = vtk_to_numpy(grid.GetCellTypesArray())
    chosen = np.nonzero(types == cell_type)[0]
    starts = offsets[chosen]
    return conn[starts[:, None] + np.arange(size)[None, :]], chosen


def polys_of(poly):
    cells = poly.GetPolys()
    offsets = vtk_to_numpy(cells.GetOffsetsArray())
    conn = vtk_to_numpy(cells.GetConnectivityArray())
    if not np.all(np.diff(offsets) == 3):
        raise ValueError("not a triangle surface")
    return conn.reshape(-1, 3)


def merged_solution(path):
    """solution.vtu (deal.II writes every cell's vertices apart) with its
    vertices merged: points, tetrahedra and the point arrays."""
    grid = read_vtu(path)
    pts = points_of(grid)
    tets, _ = cells_of(grid, 10, 4)
    key = np.round(pts, 6)
    unique, first, inverse = np.unique(key, axis=0, return_index=True,
                                       return_inverse=True)
    inverse = inverse.reshape(-1)
    arrays = {}
    pd = grid.GetPointData()
    for i in range(pd.GetNumberOfArrays()):
        name = pd.GetArrayName(i)
        arrays[name] = vtk_to_numpy(pd.GetArray(i)).astype(float)[first]
    return pts[first], inverse[tets], arrays


def boundary_faces(tets):
    """The faces of a tetrahedral mesh that belong to one tetrahedron only."""
    faces = np.concatenate([tets[:, [0, 1, 2]], tets[:, [0, 1, 3]],
                            tets[:, [0, 2, 3]], tets[:, [1, 2, 3]]])
    key = np.sort(faces, axis=1)
    _, index, counts = np.unique(key, axis=0, return_index=True,
                                 return_counts=True)
    return faces[index[counts == 1]]


def scene_segments(prm_path):
    """The bone segment names of a scene file, in their order (their ids)."""
    with open(prm_path) as f:
        for line in f:
            m = re.match(r"\s*set\s+Bone segments\s*=\s*(.*)", line)
            if m:
                return [s.strip() for s in m.group(1).split(",")]
    raise ValueError(f"{prm_path}: no 'Bone segments'")


def save(fig, out, limit=400_000):
    """Save a figure; a PNG over `limit` bytes (the shaded surfaces) is
    stored with a palette of 256 colours, as doc/make_preview_pictures.sh
    does."""
    fig.savefig(out)
    plt.close(fig)
    if limit is not None and os.path.getsize(out) > limit:
        from PIL import Image
        Image.open(out).convert("RGB").quantize(256).save(out, optimize=True)


# --------------------------------------------------------------------------
# Drawing surfaces without OpenGL
# --------------------------------------------------------------------------

class Camera:
    """An orthographic camera looking along `direction` (towards the scene),
    with `up` projected to the screen's vertical."""

    def __init__(self, direction, up):
        d = np.asarray(direction, float)
        self.d = d / np.linalg.norm(d)
        u = np.asarray(up, float)
        u = u - np.dot(u, self.d) * self.d
        self.u = u / np.linalg.norm(u)
        self.r = np.cross(self.d, self.u)

    def screen(self, p):
        p = np.asarray(p, float)
        return np.stack([p @ self.r, p @ self.u], axis=-1)

    def depth(self, p):
        return np.asarray(p, float) @ self.d


def face_normals(pts, tris):
    n = np.cross(pts[tris[:, 1]] - pts[tris[:, 0]],
                 pts[tris[:, 2]] - pts[tris[:, 0]])
    length = np.linalg.norm(n, axis=1)
    length[length == 0] = 1
    return n / length[:, None]


def shade(rgb, normals, camera, ambient=0.35, key=(-0.35, 0.45)):
    """Lambert shading by a light near the camera (two-sided)."""
    light = camera.d + key[0] * camera.r - key[1] * camera.u
    light /= np.linalg.norm(light)
    lam = np.abs(normals @ light)
    spec = np.abs(normals @ camera.d) ** 24 * 0.12
    f = ambient + (1 - ambient) * lam
    out = rgb[:, :3] * f[:, None] + spec[:, None]
    return np.clip(out, 0, 1)


def draw_surface(ax, pts, tris, face_rgb, camera, cull=None, edges=None,
                 edge_kw=None, zorder=1, lit=True):
    """Draw triangles flat shaded, back to front. `cull`: a boolean mask of
    the triangles to leave out. `edges`: (m, 2) point index pairs drawn over
    the surface."""
    if cull is not None:
        keep = ~cull
        tris, face_rgb = tris[keep], face_rgb[keep]
    centre = pts[tris].mean(axis=1)
    order = np.argsort(-camera.depth(centre), kind="stable")
    tris, face_rgb = tris[order], face_rgb[order]
    xy = camera.screen(pts)
    rgb = shade(face_rgb, face_normals(pts, tris), camera) if lit else face_rgb
    coll = PolyCollection(xy[tris], facecolors=rgb, edgecolors=rgb,
                          linewidths=0.15, antialiased=True, zorder=zorder)
    ax.add_collection(coll)
    if edges is not None:
        kw = dict(colors="k", linewidths=0.5, zorder=zorder + 1)
        kw.update(edge_kw or {})
        ax.add_collection(LineCollection(xy[edges], **kw))
    return xy


def tri_edges(tris):
    e = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    return np.unique(np.sort(e, axis=1), axis=0)


def setup_axes(ax, xy, margin=0.03):
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    pad = (hi - lo).max() * margin
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.axis("off")


# --------------------------------------------------------------------------
# The cube (prm/default.prm)
# --------------------------------------------------------------------------

def cube_section(pts, tets, y0):
    """The triangles of tetrahedron faces lying in the plane y = y0."""
    on = np.abs(pts[:, 1] - y0) < 1e-6
    faces = np.concatenate([tets[:, [0, 1, 2]], tets[:, [0, 1, 3]],
                            tets[:, [0, 2, 3]], tets[:, [1, 2, 3]]])
    faces = faces[on[faces].all(axis=1)]
    faces = np.unique(np.sort(faces, axis=1), axis=0)
    return faces, np.nonzero(on)[0]


def dimension(ax, p0, p1, text, offset, color="k", fontsize=13, side=1):
    """A dimension line from p0 to p1 with arrow heads and a label."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    ax.annotate("", xy=p1, xytext=p0,
                arrowprops=dict(arrowstyle="<|-|>", color=color, lw=1.3,
                                shrinkA=0, shrinkB=0, mutation_scale=14))
    mid = (p0 + p1) / 2
    ax.text(mid[0] + offset[0], mid[1] + offset[1], text, ha="center",
            va="center", color=color, fontsize=fontsize,
            bbox=dict(fc="white", ec="none", alpha=0.85, pad=1.5))


def cube_sketch(ax, lo, hi, inner_lo, inner_hi, y0, lift):
    """The cube, its inner cube and the section plane, in perspective-free
    3D (orthographic)."""
    cam = Camera((-0.75, 1.0, -0.6), (0, 0, 1))

    def box(a, b, **kw):
        c = np.array([[x, y, z] for x in (a[0], b[0]) for y in (a[1], b[1])
                      for z in (a[2], b[2])])
        xy = cam.screen(c)
        lines = [xy[[i, j]] for i in range(8) for j in range(i + 1, 8)
                 if np.sum(c[i] != c[j]) == 1]
        ax.add_collection(LineCollection(lines, **kw))
        return xy

    xy = box(lo, hi, colors="#1f4e9c", linewidths=1.4)
    box(inner_lo, inner_hi, colors="#d62728", linewidths=1.6)
    plane = np.array([[lo[0], y0, lo[2]], [hi[0], y0, lo[2]],
                      [hi[0], y0, hi[2]], [lo[0], y0, hi[2]]])
    ax.add_patch(plt.Polygon(cam.screen(plane), closed=True, fc="#f0a030",
                             ec="#c07000", alpha=0.35, lw=1.2))
    top = cam.screen([(inner_lo + inner_hi) / 2 + [0, 0, 5],
                      (inner_lo + inner_hi) / 2 + [0, 0, 5 + 3 * lift]])
    ax.annotate("", xy=top[1], xytext=top[0],
                arrowprops=dict(arrowstyle="-|>", color="#d62728", lw=2,
                                mutation_scale=14))
    ax.text(*(cam.screen([hi[0], y0, lo[2]]) + [0, -6]),
            f"section y = {y0:.0f} mm", color="#a05a00", fontsize=11.5,
            ha="center", va="top")
    ax.text(*(cam.screen((inner_lo + inner_hi) / 2 + [0, 0, 5 + 1.5 * lift])
              + [-3, 0]), f"lift {lift:.0f} mm", color="#d62728",
            fontsize=11.5, ha="right", va="center")
    setup_axes(ax, xy, margin=0.08)
    ax.set_title("The cube, its inner cube\nand the section", loc="left")


def fig_cube_boundary_conditions(cube_dir, out):
    pts, tets, arrays = merged_solution(os.path.join(cube_dir, "solution.vtu"))
    size = pts.max(axis=0) - pts.min(axis=0)
    y0 = float(np.round((pts[:, 1].min() + pts[:, 1].max()) / 2, 6))
    tris, on = cube_section(pts, tets, y0)
    seg = arrays["segment_id"]
    u = arrays["displacement_linear_fem"]
    mag = np.linalg.norm(u, axis=1)
    edge = size[0]
    inner = pts[seg == 1]
    inner_lo, inner_hi = inner.min(axis=0), inner.max(axis=0)
    inner_size = inner_hi[0] - inner_lo[0]
    lift = float(np.median(u[seg == 1, 2]))

    fig, axes = plt.subplots(1, 3, figsize=(14.0, 6.2),
                             gridspec_kw=dict(width_ratios=[0.62, 1, 1.12]))
    fig.subplots_adjust(left=0.01, right=0.96, top=0.86, bottom=0.03,
                        wspace=0.06)
    cube_sketch(axes[0], pts.min(axis=0), pts.max(axis=0), inner_lo,
                inner_hi, y0, lift)
    axes = axes[1:]

    # (a) the section at rest with the three kinds of points
    ax = axes[0]
    x, z = pts[:, 0], pts[:, 2]
    segs = np.stack([np.stack([x, z], 1)[tris[:, [0, 1]]],
                     np.stack([x, z], 1)[tris[:, [1, 2]]],
                     np.stack([x, z], 1)[tris[:, [2, 0]]]]).reshape(-1, 2, 2)
    ax.add_collection(LineCollection(segs, colors="0.75", linewidths=0.6,
                                     zorder=1))
    kinds = [(seg[on] == -1, "0.55", 14, "o", "free points (move with the tissue)"),
             (seg[on] == 0, "#1f4e9c", 30, "s", "held points (the border, segment 'fixed')"),
             (seg[on] == 1, "#d62728", 46, "o", "moved join points (segment 'bone')")]
    for mask, color, s, marker, label in kinds:
        idx = on[mask]
        ax.scatter(x[idx], z[idx], s=s, c=color, marker=marker, zorder=3,
                   edgecolors="none", label=label)
    ax.set_xlim(-14, edge + 6)
    ax.set_ylim(-24, edge + 4)
    ax.set_aspect("equal")
    ax.axis("off")
    dimension(ax, (0, -7), (edge, -7), f"{edge:.0f} mm", (0, -5))
    dimension(ax, (-7, 0), (-7, edge), f"{edge:.0f} mm", (-5, 0))
    # the inner cube, with its size
    ax.add_patch(plt.Rectangle((inner_lo[0], inner_lo[2]), inner_size,
                               inner_hi[2] - inner_lo[2], fill=False,
                               ec="#d62728", lw=1.5, zorder=2))
    ax.annotate(f"inner cube {inner_size:.0f} mm\n(the 'bone', lifted {lift:.0f} mm)",
                xy=(inner_hi[0], inner_hi[2]), xytext=(inner_hi[0] + 9, inner_hi[2] + 16),
                fontsize=12, color="#d62728",
                bbox=dict(fc="white", ec="none", alpha=0.9, pad=2),
                arrowprops=dict(arrowstyle="-", color="#d62728", lw=1))
    ax.set_title("(a) The section at rest: boundary conditions", loc="left")
    ax.legend(loc="lower center", bbox_to_anchor=(0.5, -0.06), ncol=1,
              frameon=False, fontsize=11.5, markerscale=1.2,
              handletextpad=0.3)

    # (b) the deformed section coloured by |u|
    ax = axes[1]
    xd, zd = x + u[:, 0], z + u[:, 2]
    norm = mcolors.Normalize(0, max(mag.max(), 1e-9))
    tpc = ax.tripcolor(xd, zd, tris, mag, shading="gouraud", cmap="viridis",
                       norm=norm, zorder=1)
    segs = np.stack([np.stack([xd, zd], 1)[tris[:, [0, 1]]],
                     np.stack([xd, zd], 1)[tris[:, [1, 2]]],
                     np.stack([xd, zd], 1)[tris[:, [2, 0]]]]).reshape(-1, 2, 2)
    ax.add_collection(LineCollection(segs, colors="k", linewidths=0.25,
                                     alpha=0.45, zorder=2))
    # the inner cube at rest (dashed) and moved (solid), with the lift
    ax.add_patch(plt.Rectangle((inner_lo[0], inner_lo[2]), inner_size,
                               inner_hi[2] - inner_lo[2], fill=False,
                               ec="white", lw=1.3, ls="--", zorder=3))
    ax.add_patch(plt.Rectangle((inner_lo[0], inner_lo[2] + lift), inner_size,
                               inner_hi[2] - inner_lo[2], fill=False,
                               ec="#d62728", lw=1.8, zorder=3))
    xa = inner_hi[0] + 4
    ax.annotate("", xy=(xa, inner_hi[2] + lift), xytext=(xa, inner_hi[2]),
                arrowprops=dict(arrowstyle="-|>", color="white", lw=2.2,
                                mutation_scale=16, shrinkA=0, shrinkB=0),
                zorder=4)
    ax.text(xa + 1.5, inner_hi[2] + lift / 2, f"{lift:.0f} mm", color="white",
            fontsize=13, fontweight="bold", va="center", zorder=4)
    ax.set_xlim(-14, edge + 6)
    ax.set_ylim(-24, edge + 4)
    ax.set_aspect("equal")
    ax.axis("off")
    dimension(ax, (0, -7), (edge, -7), "border held: u = 0", (0, -5))
    ax.set_title("(b) Deformed section (linear FEM)", loc="left")
    cb = fig.colorbar(tpc, ax=ax, fraction=0.045, pad=0.02, shrink=0.85)
    cb.set_label("|u| (mm)")
    fig.suptitle("The cube benchmark (prm/default.prm): 80 mm cube, border "
                 "held, central 10 mm cube lifted 6 mm", fontsize=15)
    save(fig, out)


def outward_boundary_faces(pts, tets):
    """The boundary faces of a tetrahedral mesh, wound outwards."""
    local = np.array([[0, 1, 2, 3], [0, 1, 3, 2], [0, 2, 3, 1], [1, 2, 3, 0]])
    faces = np.concatenate([tets[:, l[:3]] for l in local])
    other = np.concatenate([tets[:, l[3]] for l in local])
    key = np.sort(faces, axis=1)
    _, index, counts = np.unique(key, axis=0, return_index=True,
                                 return_counts=True)
    keep = index[counts == 1]
    faces, other = faces[keep], other[keep]
    n = np.cross(pts[faces[:, 1]] - pts[faces[:, 0]],
                 pts[faces[:, 2]] - pts[faces[:, 0]])
    inward = np.einsum("ij,ij->i", n, pts[other] - pts[faces[:, 0]]) > 0
    faces[inward] = faces[inward][:, [0, 2, 1]]
    return faces


def fig_solution_view(cube_dir, out, model="linear_fem"):
    pts, tets, arrays = merged_solution(os.path.join(cube_dir, "solution.vtu"))
    u = arrays[f"displacement_{model}"]
    mag = np.linalg.norm(u, axis=1)
    y0 = (pts[:, 1].min() + pts[:, 1].max()) / 2
    # Clip: keep the half y <= y0 (a mesh plane, so the cells' faces are the cut).
    half = tets[(pts[tets, 1] <= y0 + 1e-6).all(axis=1)]
    warped = pts + u
    faces = outward_boundary_faces(warped, half)
    camera = Camera(direction=(-0.6, -1.0, -0.5), up=(0, 0, 1))
    normals = face_normals(warped, faces)
    faces = faces[normals @ camera.d < 0]          # the faces seen
    normals = normals[normals @ camera.d < 0]
    cmap = plt.get_cmap("viridis")
    norm = mcolors.Normalize(0, mag.max())
    fig = plt.figure(figsize=(12.0, 9.0))
    ax = fig.add_axes([0.0, 0.02, 0.84, 0.86])
    xy = camera.screen(warped)
    tpc = ax.tripcolor(xy[:, 0], xy[:, 1], faces, mag, shading="gouraud",
                       cmap=cmap, norm=norm, zorder=1)
    # Lighting: each face darkened by its Lambert factor (a light near the camera).
    lit = shade(np.ones((len(faces), 3)), normals, camera)[:, 0]
    dark = np.zeros((len(faces), 4))
    dark[:, 3] = np.clip(1 - lit, 0, 1) * 0.6
    ax.add_collection(PolyCollection(xy[faces], facecolors=dark,
                                     edgecolors="none", zorder=2))
    ax.add_collection(LineCollection(xy[tri_edges(faces)], colors="k",
                                     linewidths=0.3, alpha=0.4, zorder=3))
    # the outline of the whole cube at rest, as ParaView's Outline
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    corners = np.array([[a, b, c] for a in (lo[0], hi[0])
                        for b in (lo[1], hi[1]) for c in (lo[2], hi[2])])
    box = [(i, j) for i in range(8) for j in range(i + 1, 8)
           if np.sum(corners[i] != corners[j]) == 1]
    cxy = camera.screen(corners)
    ax.add_collection(LineCollection([cxy[[i, j]] for i, j in box],
                                     colors="0.45", linewidths=0.9,
                                     linestyles="--", zorder=0))
    setup_axes(ax, np.concatenate([xy, cxy]))
    cax = fig.add_axes([0.86, 0.2, 0.025, 0.55])
    cb = fig.colorbar(tpc, cax=cax)
    cb.set_label(f"|displacement_{model}| (mm)")
    fig.text(0.02, 0.95, "solution.vtu of prm/default.prm in ParaView: "
             f"Warp By Vector (displacement_{model}),", fontsize=14)
    fig.text(0.02, 0.915, f"Clip at y = {y0:.0f} mm (crinkle), Surface With "
             "Edges, coloured by |u|; dashed: the outline of the cube at rest",
             fontsize=14)
    save(fig, out)


# --------------------------------------------------------------------------
# The patient (prm/patient.prm)
# --------------------------------------------------------------------------

SEGMENT_COLOURS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#d62728",
                   "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"]


def patient_segments(patient_dir):
    for name in ("input.prm", "parameters.prm"):
        path = os.path.join(patient_dir, name)
        if os.path.exists(path):
            return scene_segments(path)
    raise FileNotFoundError(f"{patient_dir}: no input.prm")


def fig_join_and_free_points(patient_dir, out, model=None):
    pts, tets, arrays = merged_solution(os.path.join(patient_dir, "solution.vtu"))
    join = arrays["join_point"] > 0.5
    seg = np.round(arrays["segment_id"]).astype(int)
    names = patient_segments(patient_dir)
    views = [("front", Camera((0, 1, 0), (0, 0, 1))),
             ("right side", Camera((1, 0, 0), (0, 0, 1)))]
    fig, axes = plt.subplots(1, 3, figsize=(14.0, 6.4),
                             gridspec_kw=dict(width_ratios=[1, 1.05, 1.05]))
    fig.subplots_adjust(left=0.01, right=0.99, top=0.86, bottom=0.13,
                        wspace=0.02)
    colours = np.array([mcolors.to_rgba(SEGMENT_COLOURS[s % 10]) if j else
                        (0.6, 0.6, 0.6, 1.0) for s, j in zip(seg, join)])
    for ax, (title, cam) in zip(axes[:2], views):
        xy = cam.screen(pts)
        depth = cam.depth(pts)
        free = np.nonzero(~join)[0]
        free = free[np.argsort(-depth[free], kind="stable")]
        ax.scatter(xy[free, 0], xy[free, 1], s=2.5, c="0.55", alpha=0.35,
                   edgecolors="none", rasterized=True)
        jp = np.nonzero(join)[0]
        jp = jp[np.argsort(-depth[jp], kind="stable")]
        ax.scatter(xy[jp, 0], xy[jp, 1], s=7, c=colours[jp], edgecolors="none")
        setup_axes(ax, xy)
        ax.set_title(f"{title}: every mesh point", fontsize=13)
    # a sagittal slab through the middle
    ax = axes[2]
    slab = np.abs(pts[:, 0] - 0.0) < 2.5
    cam = Camera((1, 0, 0), (0, 0, 1))
    xy = cam.screen(pts)
    idx = np.nonzero(slab & ~join)[0]
    ax.scatter(xy[idx, 0], xy[idx, 1], s=6, c="0.6", edgecolors="none")
    idx = np.nonzero(slab & join)[0]
    ax.scatter(xy[idx, 0], xy[idx, 1], s=16, c=colours[idx], edgecolors="none")
    setup_axes(ax, xy[slab])
    ax.set_title("right side: the mid-sagittal slab |x| < 2.5 mm", fontsize=13)
    handles = [Line2D([], [], ls="none", marker="o", ms=8,
                      color=SEGMENT_COLOURS[i % 10],
                      label=f"join points of '{n}' ({np.sum(join & (seg == i))}"
                      + (", with the region's cut it holds)" if n == "cranium"
                         else ")"))
               for i, n in enumerate(names)]
    handles.append(Line2D([], [], ls="none", marker="o", ms=6, color="0.6",
                          label=f"free points ({np.sum(~join)})"))
    fig.legend(handles=handles, loc="lower center", ncol=3, frameon=False,
               fontsize=11.5, columnspacing=1.2, handletextpad=0.2)
    fig.suptitle(f"Join and free points of the phantom patient's mesh "
                 f"(prm/patient.prm, {len(pts)} points, {len(tets)} tetrahedra)",
                 fontsize=15)
    save(fig, out)


def mesh_skin_triangles(mesh_path):
    """The patient mesh's points, tetrahedra and its skin triangles (boundary
    id 1, stored in mesh.vtu as triangles with MaterialID 1), wound outwards."""
    grid = read_vtu(mesh_path)
    pts = points_of(grid)
    tets, _ = cells_of(grid, 10, 4)
    tris, chosen = cells_of(grid, 5, 3)
    ids = vtk_to_numpy(grid.GetCellData().GetArray("MaterialID"))[chosen]
    skin = tris[ids == 1]
    outward = outward_boundary_faces(pts, tets)
    table = {tuple(sorted(f)): f for f in outward}
    skin = np.array([table.get(tuple(sorted(f)), f) for f in skin])
    return pts, tets, skin


def fig_mesh_and_skin(patient_dir, out, model=None):
    work = os.path.join(patient_dir, "patient")
    mpts, tets, mskin = mesh_skin_triangles(os.path.join(work, "mesh.vtu"))
    skin = read_vtp(os.path.join(work, "skin.vtp"))
    spts, stris = points_of(skin), polys_of(skin)
    # the close-up: lips and nose, seen from the front and the patient's right
    cam = Camera((0.9, 1.0, 0.15), (0, 0, 1))
    lo = np.array([-45.0, -200.0, -66.0])
    hi = np.array([45.0, -60.0, 28.0])
    inside = lambda p: np.all((p >= lo) & (p <= hi), axis=-1)
    stris = stris[inside(spts[stris]).all(axis=1)]
    mskin = mskin[inside(mpts[mskin]).all(axis=1)]
    # the dense skin's triangles facing the camera (flying edges winds them
    # consistently; which way is found from the nose tip, which faces front)
    n = face_normals(spts, stris)
    tip = np.argmin(spts[stris].mean(axis=1)[:, 1])
    sign = 1 if n[tip, 1] < 0 else -1
    stris = stris[(sign * n) @ cam.d < 0.05]
    mn = face_normals(mpts, mskin)
    mskin = mskin[mn @ cam.d < 0.05]
    # one painter's list: dense triangles filled, coarse triangles as outlines
    # drawn just in front of the dense skin under them
    both = np.concatenate([spts[stris], mpts[mskin]])
    depth = cam.depth(both.mean(axis=1))
    depth[len(stris):] -= 1.5
    order = np.argsort(-depth, kind="stable")
    skin_rgb = shade(np.tile([[0.96, 0.84, 0.74]], (len(stris), 1)),
                     sign * smooth_normals(spts, stris), cam, ambient=0.45)
    face = np.concatenate([np.c_[skin_rgb, np.ones(len(stris))],
                           np.zeros((len(mskin), 4))])
    edge = np.concatenate([np.c_[skin_rgb * 0.8, np.ones(len(stris))],
                           np.tile([[0.05, 0.15, 0.55, 1.0]], (len(mskin), 1))])
    width = np.concatenate([np.full(len(stris), 0.25),
                            np.full(len(mskin), 0.9)])
    xy = np.stack([both @ cam.r, both @ cam.u], axis=-1)
    view = np.stack([spts[stris].reshape(-1, 3) @ cam.r,
                     spts[stris].reshape(-1, 3) @ cam.u], axis=-1)
    extent = view.max(axis=0) - view.min(axis=0)
    fig = plt.figure(figsize=(10.0, 10.0 * 0.93 * extent[1] / extent[0] + 0.9))
    ax = fig.add_axes([0.0, 0.0, 1.0, 1 - 0.9 / fig.get_figheight()])
    ax.add_collection(PolyCollection(xy[order], facecolors=face[order],
                                     edgecolors=edge[order],
                                     linewidths=width[order]))
    setup_axes(ax, view, margin=-0.02)
    handles = [Line2D([], [], color=(0.05, 0.15, 0.55), lw=1.5,
                      label=f"coarse mesh: skin triangles of the tetrahedral "
                      f"mesh ({len(tets)} tetrahedra, {len(mpts)} points)"),
               plt.Rectangle((0, 0), 1, 1, fc=(0.96, 0.84, 0.74), ec="0.5",
                             label=f"dense skin surface from the CT "
                             f"(skin.vtp, {skin.GetNumberOfPoints()} points)")]
    ax.legend(handles=handles, loc="lower right", fontsize=12, framealpha=0.9)
    fig.suptitle("The coarse mesh's skin against the dense skin surface: "
                 "lips and nose (prm/patient.prm)", fontsize=15, y=1 - 0.35 / fig.get_figheight())
    save(fig, out)


def outward_sign(pts, tris):
    """+1 if the surface's triangles are wound outwards (found at the point
    farthest to the front, -y, whose normal must point to the front)."""
    n = face_normals(pts, tris)
    front = np.argmin(pts[tris].mean(axis=1)[:, 1])
    return 1 if n[front, 1] < 0 else -1


def smooth_normals(pts, tris):
    """Face normals of a copy of the surface smoothed by a windowed sinc
    filter: shading without the CT's voxel terraces (the drawn geometry is
    not smoothed)."""
    poly = vtk.vtkPolyData()
    p = vtk.vtkPoints()
    p.SetData(numpy_to_vtk(np.ascontiguousarray(pts), deep=True))
    poly.SetPoints(p)
    cells = vtk.vtkCellArray()
    offsets = np.arange(0, 3 * len(tris) + 1, 3, dtype=np.int64)
    cells.SetData(numpy_to_vtkIdTypeArray(offsets, deep=True),
                  numpy_to_vtkIdTypeArray(tris.astype(np.int64).ravel(), deep=True))
    poly.SetPolys(cells)
    smooth = vtk.vtkWindowedSincPolyDataFilter()
    smooth.SetInputData(poly)
    smooth.SetNumberOfIterations(25)
    smooth.SetPassBand(0.02)
    smooth.NonManifoldSmoothingOn()
    smooth.NormalizeCoordinatesOn()
    smooth.BoundarySmoothingOff()
    smooth.Update()
    return face_normals(points_of(smooth.GetOutput()), tris)


def draw_coloured_skin(ax, pts, tris, values, cmap, norm, cam, normals):
    sign = outward_sign(pts, tris)
    n = sign * normals
    seen = n @ cam.d < 0.02
    t = tris[seen]
    rgb = cmap(norm(values[t].mean(axis=1)))[:, :3]
    rgb = shade(rgb, n[seen], cam, ambient=0.4)
    return draw_surface(ax, pts, t, rgb, cam, lit=False)


def fig_predicted_face(patient_dir, out, model="linear_fem"):
    skin = read_vtp(os.path.join(patient_dir, f"skin_{model}_sf.vtp"))
    pts, tris = points_of(skin), polys_of(skin)
    dist = point_array(skin, "signed distance")
    cmap = plt.get_cmap("RdBu_r")
    norm = mcolors.Normalize(-3, 3)
    # the face: the front of the head, above the neck's cut
    keep = ((pts[tris][:, :, 1] < 20) & (pts[tris][:, :, 2] > -100)
            & (pts[tris][:, :, 2] < 55)).all(axis=1)
    tris = tris[keep]
    normals = smooth_normals(pts, tris)
    fig, axes = plt.subplots(1, 2, figsize=(13.0, 7.6),
                             gridspec_kw=dict(width_ratios=[1.0, 1.0]))
    fig.subplots_adjust(left=0.0, right=0.88, top=0.88, bottom=0.02,
                        wspace=0.0)
    views = [("front", Camera((0, 1, 0), (0, 0, 1))),
             ("profile (the patient's right)", Camera((1, 0, 0), (0, 0, 1)))]
    for ax, (title, cam) in zip(axes, views):
        xy = draw_coloured_skin(ax, pts, tris, dist, cmap, norm, cam, normals)
        setup_axes(ax, xy[np.unique(tris)], margin=0.02)
        ax.set_title(title, fontsize=13)
    cax = fig.add_axes([0.9, 0.15, 0.022, 0.6])
    cb = fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=cmap), cax=cax,
                      extend="both")
    cb.set_label("signed distance to the post-operative face (mm)")
    fig.text(0.9, 0.78, "outside", fontsize=11, color="#b2182b")
    fig.text(0.9, 0.11, "behind", fontsize=11, color="#2166ac")
    label = model.replace("_", " ")
    fig.suptitle(f"Predicted face of the phantom patient (prm/patient.prm, "
                 f"{label}, shape functions mapping)\ncoloured by its signed "
                 "distance to the post-operative face", fontsize=15)
    save(fig, out, limit=None)  # a palette would band the colour map


def section(poly, x0):
    """The curve of a surface in the plane x = x0, as (y, z) segments."""
    plane = vtk.vtkPlane()
    plane.SetOrigin(x0, 0, 0)
    plane.SetNormal(1, 0, 0)
    cutter = vtk.vtkCutter()
    cutter.SetCutFunction(plane)
    cutter.SetInputData(poly)
    cutter.Update()
    cut = cutter.GetOutput()
    p = points_of(cut)
    lines = cut.GetLines()
    conn = vtk_to_numpy(lines.GetConnectivityArray()).reshape(-1, 2)
    return p[conn][:, :, 1:]


def fig_closest_vs_corresponding(patient_dir, out, model="mass_spring"):
    pred = read_vtp(os.path.join(patient_dir, f"skin_{model}_sf.vtp"))
    post = read_vtp(os.path.join(patient_dir, "skin_postoperative.vtp"))
    pre = read_vtp(os.path.join(patient_dir, "skin_preoperative.vtp"))
    p = points_of(pred)
    p0 = points_of(pre)
    to_exact = point_array(pred, "to exact partner")
    to_corr = point_array(pred, "to correspondence")
    # the lower lip in the mid-sagittal plane: points near x = 0 between the
    # mouth and the chin's fold, at the front of the face
    band = (np.abs(p0[:, 0]) < 1) & (p0[:, 2] > -39) & (p0[:, 2] < -26)
    x0 = float(p0[np.nonzero(band)[0][np.argmin(p0[band, 1])], 0])
    lip = band & (np.abs(p0[:, 0] - x0) < 0.05) & (p0[:, 1] < -70)
    idx = np.nonzero(lip)[0]
    idx = idx[np.argsort(p[idx, 2])]
    # a few, spread along the lip
    chosen = idx[np.linspace(0, len(idx) - 1, min(7, len(idx))).astype(int)]
    locator = vtk.vtkCellLocator()
    locator.SetDataSet(post)
    locator.BuildLocator()
    closest = np.zeros((len(chosen), 3))
    for k, i in enumerate(chosen):
        c = [0.0, 0.0, 0.0]
        cell, sub, d2 = vtk.reference(0), vtk.reference(0), vtk.reference(0.0)
        locator.FindClosestPoint(p[i], c, cell, sub, d2)
        closest[k] = c
    fig, ax = plt.subplots(figsize=(12.0, 9.5))
    fig.subplots_adjust(left=0.08, right=0.98, top=0.9, bottom=0.2)
    ax.add_collection(LineCollection(section(pre, x0), colors="0.6", lw=1.4,
                                     linestyles=":"))
    ax.add_collection(LineCollection(section(post, x0), colors="k", lw=2.2,
                                     label="post-operative skin"))
    ax.add_collection(LineCollection(section(pred, x0), colors="#e08214",
                                     lw=2.2, linestyles="--",
                                     label=f"predicted skin ({model.replace('_', ' ')})"))
    q = p[chosen]
    kw = dict(angles="xy", scale_units="xy", scale=1, width=0.0022,
              headwidth=4.5, headlength=6, headaxislength=5.5, zorder=5)
    ax.quiver(q[:, 1], q[:, 2], closest[:, 1] - q[:, 1],
              closest[:, 2] - q[:, 2], color="#1b7837", **kw)
    ax.quiver(q[:, 1], q[:, 2], to_exact[chosen, 1], to_exact[chosen, 2],
              color="#762a83", **kw)
    ok = np.isfinite(to_corr[chosen]).all(axis=1)
    ax.quiver(q[ok, 1], q[ok, 2], to_corr[chosen][ok, 1],
              to_corr[chosen][ok, 2], color="#2166ac", alpha=0.8, **kw)
    ax.scatter(q[:, 1], q[:, 2], s=36, c="#e08214", zorder=6,
               edgecolors="k", linewidths=0.6)
    ax.set_xlim(q[:, 1].min() - 5, q[:, 1].max() + 8)
    ax.set_ylim(q[:, 2].min() - 3, q[:, 2].max() + 3)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("y (mm, anterior to the left)")
    ax.set_ylabel("z (mm)")
    ax.grid(True, color="0.9", lw=0.6)
    # where: the whole profile, with the close-up's frame
    inset = fig.add_axes([0.085, 0.6, 0.2, 0.28])
    inset.add_collection(LineCollection(section(post, x0), colors="k", lw=1))
    inset.set_xlim(-125, -40)
    inset.set_ylim(-100, 40)
    inset.set_aspect("equal")
    inset.set_xticks([])
    inset.set_yticks([])
    ax.apply_aspect()
    x_lo, x_hi = ax.get_xlim()
    y_lo, y_hi = ax.get_ylim()
    inset.add_patch(plt.Rectangle((x_lo, y_lo), x_hi - x_lo, y_hi - y_lo,
                                  fill=False, ec="#e08214", lw=1.5))
    inset.set_title("the profile at x = %.1f mm" % x0, fontsize=10)
    handles = [Line2D([], [], color="0.6", lw=1.4, ls=":",
                      label="pre-operative skin"),
               Line2D([], [], color="k", lw=2.2, label="post-operative skin"),
               Line2D([], [], color="#e08214", lw=2.2, ls="--",
                      marker="o", mec="k", ms=6,
                      label=f"predicted skin ({model.replace('_', ' ')}) and "
                      "some of its points"),
               Line2D([], [], color="#1b7837", lw=2.5,
                      label="to the closest point (what the signed distance measures)"),
               Line2D([], [], color="#2166ac", lw=2.5,
                      label="to the corresponding point (TPS-RPM, 'to correspondence')"),
               Line2D([], [], color="#762a83", lw=2.5,
                      label="to the true partner (a phantom's, 'to exact partner')")]
    fig.legend(handles=handles, loc="lower center", fontsize=12, ncol=2,
               frameon=False, columnspacing=1.5)
    fig.suptitle("Closest point against corresponding point on the lower lip "
                 f"(prm/patient.prm, section x = {x0:.1f} mm)", fontsize=15)
    ax.set_title("arrows: the vectors' y and z components, to scale",
                 fontsize=12, color="0.3")
    save(fig, out)


# --------------------------------------------------------------------------
# Main
# --------------------------------------------------------------------------

FIGURES = ["cube_boundary_conditions", "solution_view", "join_and_free_points",
           "mesh_and_skin", "closest_vs_corresponding", "predicted_face"]


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cube", help="output folder of prm/default.prm")
    parser.add_argument("--patient", help="output folder of prm/patient.prm")
    parser.add_argument("--out", default="doc/images")
    parser.add_argument("--model", default="linear_fem",
                        help="the model of the patient figures (file name form)")
    parser.add_argument("--lip-model", default="mass_spring",
                        help="the model of closest_vs_corresponding.png")
    parser.add_argument("--only", nargs="*", choices=FIGURES)
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    chosen = args.only or FIGURES
    for name in chosen:
        out = os.path.join(args.out, name + ".png")
        if name in ("cube_boundary_conditions", "solution_view"):
            if not args.cube:
                continue
            globals()["fig_" + name](args.cube, out)
        else:
            if not args.patient:
                continue
            model = (args.lip_model if name == "closest_vs_corresponding"
                     else args.model)
            globals()["fig_" + name](args.patient, out, model)
        print("wrote", out)


if __name__ == "__main__":
    sys.exit(main())
