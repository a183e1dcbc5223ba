#!/usr/bin/python3
"""Render a phantom patient's skin and skull surfaces to one PNG.

Draws a 2x2 grid -- skin front, skin right profile, skull front, skull
right profile -- with orthographic projection, z up, equal aspect and a mm
scale bar, so a reader sees at a glance what the patient looks like.
Inputs are triangle surfaces in PLY (binary little-endian or ascii, as
written by VTK's vtkPLYWriter) in mm in the LPS patient frame: x to the
patient's left, y posterior (the face looks towards -y), z superior.

Shading is done by a small numpy z-buffer rasteriser (Gouraud-interpolated
Lambert + ambient, light from the viewer, slightly up and to the left), so
hidden surfaces such as the skull's inner table are correctly hidden.

Usage:
    /usr/bin/python3 benchmarks/patients/render.py SKIN.ply SKULL.ply \\
        OUT.png [--title "P1: MSB"]

Needs the Debian packages python3-numpy and python3-matplotlib.
"""
import argparse
import sys

import numpy as np
import matplotlib
matplotlib.use("Agg")  # headless: no display on the build machines
import matplotlib.pyplot as plt  # noqa: E402

PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
             "short": "i2", "int16": "i2", "ushort": "u2", "uint16": "u2",
             "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
             "float": "f4", "float32": "f4", "double": "f8",
             "float64": "f8"}
PANEL_PX = 600                        # panel height in pixels
SKIN_RGB = np.array([0.93, 0.74, 0.62])
BONE_RGB = np.array([0.97, 0.95, 0.86])
# View name -> (image-right axis, towards-viewer axis); up is always +z.
# Front: the viewer faces the patient, so the patient's left is on the
# right.  Right profile: the viewer stands at the patient's right (-x) and
# looks towards +x, so without mirroring the face (-y) is on the right.
VIEWS = {"front": ((1, 0, 0), (0, -1, 0)),
         "right profile": ((0, -1, 0), (-1, 0, 0))}


def read_ply(path):
    """Return (vertices (n,3) float, triangles (m,3) int) from a PLY file."""
    with open(path, "rb") as f:
        if f.readline().strip() != b"ply":
            sys.exit(f"{path}: not a PLY file")
        fmt, elements = None, []
        while True:
            words = f.readline().decode("ascii").split()
            if not words or words[0] in ("comment", "obj_info"):
                continue
            if words[0] == "end_header":
                break
            if words[0] == "format":
                fmt = words[1]
            elif words[0] == "element":
                elements.append((words[1], int(words[2]), []))
            elif words[0] == "property":
                elements[-1][2].append(words[1:])
        if fmt not in ("binary_little_endian", "ascii"):
            sys.exit(f"{path}: unsupported PLY format {fmt}")
        data = {}
        if fmt == "ascii":
            tokens = iter(f.read().split())
            for name, count, props in elements:
                rows = []
                for _ in range(count):
                    row = []
                    for p in props:
                        n = int(next(tokens)) if p[0] == "list" else 1
                        row += [float(next(tokens)) for _ in range(n)]
                    rows.append(row)
                data[name] = rows
            verts = np.array(data["vertex"])[:, :3]
            polys = data["face"]
        else:
            for name, count, props in elements:
                if all(p[0] != "list" for p in props):
                    dt = np.dtype([(p[-1], "<" + PLY_TYPES[p[0]])
                                   for p in props])
                    data[name] = np.frombuffer(f.read(count * dt.itemsize),
                                               dt, count)
                    continue
                # A list element: fast path assumes every polygon is a
                # triangle (true for VTK output) and checks that it was.
                if len(props) != 1 or name != "face":
                    sys.exit(f"{path}: unsupported list element {name}")
                cnt_t, idx_t = (PLY_TYPES[t] for t in props[0][1:3])
                dt = np.dtype([("n", "<" + cnt_t), ("i", "<" + idx_t, 3)])
                start = f.tell()
                tri = np.frombuffer(f.read(count * dt.itemsize), dt, count)
                if len(tri) == count and np.all(tri["n"] == 3):
                    data[name] = tri["i"]
                    continue
                f.seek(start)  # mixed polygons: slow generic path
                cs, isz = np.dtype(cnt_t).itemsize, np.dtype(idx_t).itemsize
                polys = []
                for _ in range(count):
                    n = int(np.frombuffer(f.read(cs), "<" + cnt_t)[0])
                    polys.append(np.frombuffer(f.read(n * isz), "<" + idx_t))
                data[name] = polys
            v = data["vertex"]
            verts = np.stack([v["x"], v["y"], v["z"]], axis=1)
            polys = data["face"]
    if isinstance(polys, np.ndarray):
        tris = polys
    else:  # fan-triangulate general polygons
        tris = [(p[0], p[k], p[k + 1]) for p in polys
                for k in range(1, len(p) - 1)]
    return (np.asarray(verts, dtype=np.float64),
            np.asarray(tris, dtype=np.int64).reshape(-1, 3))


def vertex_normals(verts, tris, smooth=6):
    """Area-weighted vertex normals, then a few rounds of averaging.

    The averaging hides the 1 mm voxel terraces of marching-cubes surfaces,
    which otherwise dominate the shading; geometry is left untouched.
    """
    a, b, c = (verts[tris[:, k]] for k in range(3))
    fn = np.cross(b - a, c - a)  # length = 2 x area, i.e. area-weighted
    area = np.linalg.norm(fn, axis=1)
    n, corner = len(verts), tris.T.ravel()

    def scatter(face_vals):  # sum face values onto their three corners
        vals = np.tile(face_vals, (3, 1))
        return np.stack([np.bincount(corner, vals[:, d], n)
                         for d in range(3)], axis=1)

    def unit(vn):
        return vn / np.maximum(np.linalg.norm(vn, axis=1, keepdims=True),
                               1e-12)

    vn = unit(scatter(fn))
    for _ in range(smooth):
        vn = unit(scatter(vn[tris].sum(axis=1) * area[:, None]))
    return vn


def rasterise(xy, depth, shade, tris, height, width):
    """Z-buffer triangles given in pixel coords; return (shade, mask) images.

    Every pixel centre inside a triangle (edge functions, inclusive) gets a
    fragment; triangles are grouped by bounding-box size so each group is
    handled by size^2 vectorised passes, one per pixel offset in the box.
    """
    x, y = xy[tris, 0], xy[tris, 1]
    x0, x1 = np.ceil(x.min(1)).astype(int), np.floor(x.max(1)).astype(int)
    y0, y1 = np.ceil(y.min(1)).astype(int), np.floor(y.max(1)).astype(int)
    x0, y0 = np.maximum(x0, 0), np.maximum(y0, 0)
    x1, y1 = np.minimum(x1, width - 1), np.minimum(y1, height - 1)
    area = ((x[:, 1] - x[:, 0]) * (y[:, 2] - y[:, 0])
            - (x[:, 2] - x[:, 0]) * (y[:, 1] - y[:, 0]))
    size = np.maximum(x1 - x0, y1 - y0) + 1
    ok = (x1 >= x0) & (y1 >= y0) & (np.abs(area) > 1e-12)
    zbuf = np.full(height * width, np.inf)
    frags = []
    for s in np.unique(size[ok]):
        sel = np.nonzero(ok & (size == s))[0]
        tx, ty, inv = x[sel], y[sel], 1.0 / area[sel]
        tz, ts = depth[tris[sel]], shade[tris[sel]]
        for dy in range(s):
            for dx in range(s):
                px, py = x0[sel] + dx, y0[sel] + dy
                # Barycentric weights from the three edge functions.
                w = np.empty((len(sel), 3))
                for k in range(3):
                    i, j = (k + 1) % 3, (k + 2) % 3
                    w[:, k] = ((tx[:, j] - tx[:, i]) * (py - ty[:, i])
                               - (ty[:, j] - ty[:, i]) * (px - tx[:, i])) * inv
                hit = (np.all(w >= -1e-9, axis=1)
                       & (px <= x1[sel]) & (py <= y1[sel]))
                w = w[hit]
                pix = py[hit] * width + px[hit]
                z = np.einsum("ij,ij->i", w, tz[hit])
                np.minimum.at(zbuf, pix, z)
                frags.append((pix, z, np.einsum("ij,ij->i", w, ts[hit])))
    img = np.ones(height * width)
    for pix, z, s in frags:  # keep only the nearest fragment of each pixel
        win = z <= zbuf[pix]
        img[pix[win]] = s[win]
    return img.reshape(height, width), np.isfinite(zbuf).reshape(height, width)


def render(verts, normals, tris, view, lo, hi, mm_per_px, rgb):
    """Orthographic shaded image (H, W, 3) of one surface for one view."""
    right, toward = (np.array(a, float) for a in VIEWS[view])
    up = np.array([0.0, 0.0, 1.0])
    light = toward + 0.4 * up - 0.3 * right  # from the viewer, up-left
    light /= np.linalg.norm(light)
    u, v = verts @ right, verts @ up
    umin, umax = min(lo @ right, hi @ right), max(lo @ right, hi @ right)
    width = int(np.ceil((umax - umin) / mm_per_px)) + 1
    height = int(np.ceil((hi[2] - lo[2]) / mm_per_px)) + 1
    xy = np.stack([(u - umin) / mm_per_px, (hi[2] - v) / mm_per_px], axis=1)
    # Two-sided Lambert so inconsistently oriented patches still shade.
    lam = np.abs(normals @ light)
    shade = 0.25 + 0.75 * lam
    img, mask = rasterise(xy, -(verts @ toward), shade, tris, height, width)
    rgb_img = np.where(mask[..., None], img[..., None] * rgb, 1.0)
    return rgb_img, (umin, umax, lo[2], hi[2])


def scale_bar(ax, extent):
    """Draw a 50 mm bar in the panel's lower-left corner (in the margin)."""
    x0, y0 = extent[0] + 0.05 * (extent[1] - extent[0]), extent[2] + 3.0
    ax.plot([x0, x0 + 50], [y0, y0], color="k", lw=3, solid_capstyle="butt")
    ax.text(x0 + 25, y0 + 1.5, "50 mm", ha="center", va="bottom", fontsize=9)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("skin")
    ap.add_argument("skull")
    ap.add_argument("out")
    ap.add_argument("--title", default=None)
    args = ap.parse_args()

    surfaces = []
    for path in (args.skin, args.skull):
        verts, tris = read_ply(path)
        surfaces.append((verts, vertex_normals(verts, tris), tris))
    # One scale for all panels (from the skin's height) so sizes compare;
    # each panel is cropped to its own surface to avoid wasted space.
    mm_per_px = np.ptp(surfaces[0][0][:, 2]) / PANEL_PX

    panels = []
    for (verts, normals, tris), name, rgb in zip(
            surfaces, ("Skin", "Skull"), (SKIN_RGB, BONE_RGB)):
        # Extra room at the bottom keeps the scale bar off the surface.
        lo, hi = verts.min(0) - [2.0, 2.0, 14.0], verts.max(0) + 2.0
        for view in VIEWS:
            img, ext = render(verts, normals, tris, view, lo, hi,
                              mm_per_px, rgb)
            panels.append((img, ext, f"{name}, {view}"))

    col_w = [max(panels[c][0].shape[1], panels[c + 2][0].shape[1])
             for c in range(2)]
    row_h = [panels[r][0].shape[0] for r in (0, 2)]
    dpi = 100
    fig_w = (sum(col_w) + 40) / dpi
    fig_h = (sum(row_h) + 80 + (40 if args.title else 0)) / dpi
    fig, axes = plt.subplots(2, 2, figsize=(fig_w, fig_h), dpi=dpi,
                             gridspec_kw={"width_ratios": col_w,
                                          "height_ratios": row_h})
    for ax, (img, ext, caption) in zip(axes.ravel(), panels):
        ax.imshow(img, extent=ext, interpolation="antialiased")
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
        for spine in ax.spines.values():
            spine.set_visible(False)
        ax.set_title(caption, fontsize=11)
        scale_bar(ax, ext)
    if args.title:
        fig.suptitle(args.title, fontsize=14)
    fig.tight_layout()
    fig.savefig(args.out, dpi=dpi, facecolor="white")


if __name__ == "__main__":
    main()
