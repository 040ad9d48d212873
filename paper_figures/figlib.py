"""Shared helpers of the figure scripts: OFF reading, VTK offscreen panels.

Every rendered figure is one vtkRenderWindow split into side-by-side
viewports (one per panel), each with the same camera when panels are
compared, a three-light kit, smooth shading from vertex normals, and a label.
Run under xvfb-run (make_figures.sh does).
"""

import json
import os

import numpy as np
import vtk
from vtk.util import numpy_support as nps

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
DATA = os.path.join(HERE, "data")  # generated, not committed
OUT = os.path.join(HERE, "out")

# Colours (RGB 0..1).
MESH_GREY = (0.82, 0.80, 0.76)
MOVEABLE = (0.85, 0.15, 0.15)   # moveable handle: red
FIXED = (0.15, 0.35, 0.85)      # fixed handles: blue
GROUP1 = (0.95, 0.55, 0.10)     # flexible particles (e' > T): orange
GROUP2 = (0.35, 0.65, 0.35)     # rigid particles: green


def read_off(path):
    """(V #V x 3 float, F #F x 3 int) of an OFF/COFF file; polygons are fanned."""
    with open(path) as f:
        lines = [l.split("#")[0].strip() for l in f]
    lines = [l for l in lines if l]
    header = lines[0].split()
    counts = header[1:] if len(header) > 1 else lines[1].split()
    nv, nf = int(counts[0]), int(counts[1])
    start = 1 if len(header) > 1 else 2  # first vertex line
    vlines = lines[start:start + nv]
    V = np.array([[float(x) for x in l.split()[:3]] for l in vlines])
    faces = []
    for l in lines[start + nv:start + nv + nf]:
        t = l.split()
        n = int(t[0])
        ids = [int(x) for x in t[1:1 + n]]
        for k in range(1, n - 1):
            faces.append((ids[0], ids[k], ids[k + 1]))
    return V, np.array(faces, dtype=np.int64)


def load_json(path):
    with open(path) as f:
        return json.load(f)


def point_polydata(P, scalars=None):
    """Points P (#P x 3) as vtkPolyData, with optional per-point scalars."""
    pts = vtk.vtkPoints()
    pts.SetData(nps.numpy_to_vtk(np.ascontiguousarray(P, dtype=np.float64), deep=True))
    pd = vtk.vtkPolyData()
    pd.SetPoints(pts)
    if scalars is not None:
        arr = nps.numpy_to_vtk(np.ascontiguousarray(scalars, dtype=np.float64), deep=True)
        arr.SetName("s")
        pd.GetPointData().SetScalars(arr)
    return pd


def polydata(V, F, scalars=None):
    pd = point_polydata(V, scalars)
    cells = vtk.vtkCellArray()
    conn = np.hstack([np.full((len(F), 1), 3, np.int64), F]).ravel()
    cells.SetCells(len(F), nps.numpy_to_vtkIdTypeArray(conn, deep=True))
    pd.SetPolys(cells)
    normals = vtk.vtkPolyDataNormals()
    normals.SetInputData(pd)
    normals.SetSplitting(False)      # vertex normals: smooth shading
    normals.ConsistencyOn()
    normals.AutoOrientNormalsOff()
    normals.Update()
    return normals.GetOutput()


def mesh_actor(V, F, color=MESH_GREY, opacity=1.0, scalars=None, lut=None, rng=None):
    pd = polydata(V, F, scalars)
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputData(pd)
    if scalars is not None:
        mapper.ScalarVisibilityOn()
        mapper.SetLookupTable(lut)
        mapper.SetScalarRange(*rng)
        mapper.InterpolateScalarsBeforeMappingOn()
    else:
        mapper.ScalarVisibilityOff()
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    p = actor.GetProperty()
    p.SetColor(*color)
    p.SetInterpolationToPhong()
    p.SetAmbient(0.15)
    p.SetDiffuse(0.8)
    p.SetSpecular(0.15)
    p.SetSpecularPower(30)
    p.SetOpacity(opacity)
    if opacity < 1.0:
        p.BackfaceCullingOff()
    return actor


def spheres_actor(P, radius, color=None, scalars=None, lut=None, rng=None, resolution=10):
    """Glyph spheres at points P (#P x 3), one colour or scalars through lut."""
    pd = point_polydata(P, scalars)
    src = vtk.vtkSphereSource()
    src.SetRadius(radius)
    src.SetThetaResolution(resolution)
    src.SetPhiResolution(max(6, resolution // 2 + 2))
    glyph = vtk.vtkGlyph3DMapper()
    glyph.SetInputData(pd)
    glyph.SetSourceConnection(src.GetOutputPort())
    glyph.ScalingOff()
    if scalars is not None:
        glyph.SetLookupTable(lut)
        glyph.SetScalarRange(*rng)
        glyph.ScalarVisibilityOn()
        glyph.SetScalarModeToUsePointData()
    else:
        glyph.ScalarVisibilityOff()
    actor = vtk.vtkActor()
    actor.SetMapper(glyph)
    if color is not None:
        actor.GetProperty().SetColor(*color)
    actor.GetProperty().SetSpecular(0.3)
    actor.GetProperty().SetSpecularPower(20)
    return actor


def cubes_actor(P, width, color, opacity=1.0):
    """Axis-aligned boxes of side `width` at points P (lattice cells)."""
    pts = vtk.vtkPoints()
    pts.SetData(nps.numpy_to_vtk(np.ascontiguousarray(P, dtype=np.float64), deep=True))
    pd = vtk.vtkPolyData()
    pd.SetPoints(pts)
    src = vtk.vtkCubeSource()
    src.SetXLength(width)
    src.SetYLength(width)
    src.SetZLength(width)
    glyph = vtk.vtkGlyph3DMapper()
    glyph.SetInputData(pd)
    glyph.SetSourceConnection(src.GetOutputPort())
    glyph.ScalingOff()
    glyph.ScalarVisibilityOff()
    actor = vtk.vtkActor()
    actor.SetMapper(glyph)
    actor.GetProperty().SetColor(*color)
    actor.GetProperty().SetOpacity(opacity)
    return actor


def lines_actor(P, edges, color=(0.1, 0.1, 0.1), width=1.5):
    pts = vtk.vtkPoints()
    pts.SetData(nps.numpy_to_vtk(np.ascontiguousarray(P, dtype=np.float64), deep=True))
    E = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    cells = vtk.vtkCellArray()
    conn = np.hstack([np.full((len(E), 1), 2, np.int64), E]).ravel()
    cells.SetCells(len(E), nps.numpy_to_vtkIdTypeArray(conn, deep=True))
    pd = vtk.vtkPolyData()
    pd.SetPoints(pts)
    pd.SetLines(cells)
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputData(pd)
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(*color)
    actor.GetProperty().SetLineWidth(width)
    actor.GetProperty().LightingOff()
    return actor


def lut_blue_red():
    """Blue (0) -> white -> red (1): a diverging map for e' and displacement."""
    ctf = vtk.vtkColorTransferFunction()
    ctf.SetColorSpaceToDiverging()
    ctf.AddRGBPoint(0.0, 0.23, 0.30, 0.75)
    ctf.AddRGBPoint(1.0, 0.71, 0.02, 0.15)
    lut = vtk.vtkLookupTable()
    lut.SetNumberOfTableValues(256)
    lut.Build()
    for i in range(256):
        c = ctf.GetColor(i / 255.0)
        lut.SetTableValue(i, c[0], c[1], c[2], 1.0)
    return lut


def lut_viridis():
    import matplotlib
    cmap = matplotlib.colormaps["viridis"]
    lut = vtk.vtkLookupTable()
    lut.SetNumberOfTableValues(256)
    lut.Build()
    for i in range(256):
        c = cmap(i / 255.0)
        lut.SetTableValue(i, c[0], c[1], c[2], 1.0)
    return lut


def handle_lut():
    lut = vtk.vtkLookupTable()
    lut.SetNumberOfTableValues(3)
    lut.Build()
    for i, c in enumerate((MESH_GREY, FIXED, MOVEABLE)):
        lut.SetTableValue(i, c[0], c[1], c[2], 1.0)
    return lut


def handle_scalars(d, n):
    s = np.zeros(n)
    s[np.asarray(d["fixed"], dtype=int)] = 1
    s[np.asarray(d["moveable"], dtype=int)] = 2
    return s


def handles_mesh_actor(d, V, F, opacity=1.0):
    """Mesh with fixed handles blue and the moveable handle red."""
    lut = handle_lut()
    a = mesh_actor(V, F, scalars=handle_scalars(d, len(V)), lut=lut, rng=(0, 2), opacity=opacity)
    a.GetMapper().InterpolateScalarsBeforeMappingOff()
    return a


def text(renderer, s, size=18, pos=(0.02, 0.94), color=(0, 0, 0), bold=True):
    t = vtk.vtkTextActor()
    t.SetInput(s)
    t.GetTextProperty().SetFontSize(size)
    t.GetTextProperty().SetColor(*color)
    t.GetTextProperty().SetBold(bold)
    t.GetTextProperty().SetVerticalJustificationToTop()
    t.GetTextProperty().SetBackgroundColor(1, 1, 1)
    t.GetTextProperty().SetBackgroundOpacity(0.75)
    t.GetPositionCoordinate().SetCoordinateSystemToNormalizedViewport()
    t.SetPosition(*pos)
    renderer.AddActor2D(t)
    return t


def scalar_bar(renderer, lut, title, rng=None, pos=(0.82, 0.12)):
    bar = vtk.vtkScalarBarActor()
    bar.SetLookupTable(lut)
    bar.SetTitle(title)
    bar.SetNumberOfLabels(5)
    bar.SetLabelFormat("%.2g")
    bar.SetWidth(0.09)
    bar.SetHeight(0.42)
    bar.GetPositionCoordinate().SetCoordinateSystemToNormalizedViewport()
    bar.GetPositionCoordinate().SetValue(*pos)
    bar.UnconstrainedFontSizeOn()
    for tp in (bar.GetTitleTextProperty(), bar.GetLabelTextProperty()):
        tp.SetColor(0, 0, 0)
        tp.SetFontSize(14)
        tp.ShadowOff()
        tp.ItalicOff()
    bar.GetTitleTextProperty().SetFontSize(16)
    # The labels are centred on their ticks, so the top one reaches half a line above the
    # bar: keep the title clear of it (without this "0.1" sits on "E_i/N_i").
    bar.SetVerticalTitleSeparation(12)
    # A white backing behind the title and the labels: a bar drawn over the mesh (the free
    # limb's legs, Fig. 4's armadillo) stays legible.
    for tp in (bar.GetTitleTextProperty(), bar.GetLabelTextProperty()):
        tp.SetBackgroundColor(1, 1, 1)
        tp.SetBackgroundOpacity(0.85)
    at = bar.GetAnnotationTextProperty()  # lut.SetAnnotation marks, e.g. a threshold
    at.SetColor(0, 0, 0)
    at.SetFontSize(14)
    at.ItalicOff()
    at.ShadowOff()
    at.BoldOn()
    renderer.AddActor2D(bar)
    return bar


def camera_for(V, view_dir, up=(0, 1, 0), zoom=1.0, center=None):
    """A vtkCamera looking at the bounding box centre of V from view_dir."""
    V = np.asarray(V)
    c = 0.5 * (V.min(0) + V.max(0)) if center is None else np.asarray(center)
    r = 0.5 * np.linalg.norm(V.max(0) - V.min(0))
    d = np.asarray(view_dir, float)
    d /= np.linalg.norm(d)
    cam = vtk.vtkCamera()
    cam.SetFocalPoint(*c)
    cam.SetPosition(*(c + d * r * 3.6 / zoom))
    cam.SetViewUp(*up)
    cam.SetViewAngle(30)
    cam.SetClippingRange(r * 0.1, r * 10)
    return cam


def render_panels(panels, path, panel_size=(520, 600), title=None, columns=None):
    """panels: list of dicts {actors, label, camera, bar: (lut, title) or None,
    texts: [(str, pos, size)]}. Writes one PNG with the panels side by side."""
    n = len(panels)
    cols = columns or n
    rows = (n + cols - 1) // cols
    title_h = 40 if title else 0
    W, H = panel_size[0] * cols, panel_size[1] * rows + title_h
    win = vtk.vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetSize(W, H)
    win.SetMultiSamples(8)
    ph = panel_size[1] * rows / H
    background = vtk.vtkRenderer()  # white behind empty cells of the grid
    background.SetBackground(1, 1, 1)
    background.SetViewport(0, 0, 1, 1)
    win.AddRenderer(background)
    for i, p in enumerate(panels):
        r_, c_ = divmod(i, cols)
        ren = vtk.vtkRenderer()
        x0, x1 = c_ / cols, (c_ + 1) / cols
        y1 = ph * (1 - r_ / rows)
        y0 = ph * (1 - (r_ + 1) / rows)
        ren.SetViewport(x0, y0, x1, y1)
        ren.SetBackground(1, 1, 1)
        # Depth peeling drops translucent actors with multisampling under
        # Xvfb's Mesa; plain alpha blending is fine for faint shells.
        ren.SetUseDepthPeeling(0)
        for a in p["actors"]:
            ren.AddActor(a)
        kit = vtk.vtkLightKit()
        kit.AddLightsToRenderer(ren)
        ren.SetActiveCamera(p["camera"])
        ren.ResetCameraClippingRange()
        text(ren, p["label"], size=p.get("label_size", 18))
        for s, pos, size in p.get("texts", []):
            text(ren, s, size=size, pos=pos, bold=False)
        if p.get("bar"):
            scalar_bar(ren, p["bar"][0], p["bar"][1])
        win.AddRenderer(ren)
    if title:
        ren = vtk.vtkRenderer()
        ren.SetViewport(0, ph, 1, 1)
        ren.SetBackground(1, 1, 1)
        text(ren, title, size=20, pos=(0.01, 0.85))
        win.AddRenderer(ren)
    win.SetAlphaBitPlanes(1)
    win.Render()
    w2i = vtk.vtkWindowToImageFilter()
    w2i.SetInput(win)
    w2i.ReadFrontBufferOff()
    w2i.Update()
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputConnection(w2i.GetOutputPort())
    writer.Write()
    win.Finalize()
    shrink_png(path)
    print("wrote", path, os.path.getsize(path) // 1024, "KB")


def shrink_png(path, limit_kb=200):
    """Re-encodes a PNG with an adaptive palette when it is larger than limit_kb,
    so committed figures stay small: 256 colours, fewer (192, 128, 96) only while
    the file is still over 205 KiB (Fig. 6 with its translucent rest poses needs 96).
    libimagequant (in Debian's Pillow) keeps smooth shading and colour maps free of
    banding."""
    if os.path.getsize(path) <= limit_kb * 1024:
        return
    from PIL import Image, features
    method = (Image.Quantize.LIBIMAGEQUANT if features.check_feature("libimagequant")
              else Image.Quantize.MEDIANCUT)
    image = Image.open(path).convert("RGB")
    for colors in (256, 192, 128, 96):
        image.quantize(colors=colors, method=method,
                       dither=Image.Dither.FLOYDSTEINBERG).save(path, optimize=True)
        if os.path.getsize(path) <= 205 * 1024:
            break


def arap_energy_per_vertex(V, F, Vd):
    """(E_i, N_i) per vertex: the cotangent ARAP energy of experiments/metrics.h
    (Sorkine & Alexa 2007; w_ij = (cot a + cot b) / 2 clamped at 0, the best
    rotation per vertex without reflection) and its normaliser sum w |e|^2.
    sum(E) / sum(N) is experiments' arap_energy."""
    V = np.asarray(V, float)
    Vd = np.asarray(Vd, float)
    F = np.asarray(F, np.int64)
    n = len(V)
    keys, weights = [], []
    for c in range(3):
        i, j, k = F[:, c], F[:, (c + 1) % 3], F[:, (c + 2) % 3]
        a, b = V[j] - V[i], V[k] - V[i]
        cross = np.linalg.norm(np.cross(a, b), axis=1)
        dot = (a * b).sum(1)
        cot = np.where(cross > 0, dot / np.where(cross > 0, cross, 1.0), 0.0)
        keys.append(np.minimum(j, k) * n + np.maximum(j, k))
        weights.append(0.5 * cot)
    keys = np.concatenate(keys)
    weights = np.concatenate(weights)
    uniq, inv = np.unique(keys, return_inverse=True)
    w = np.maximum(np.bincount(inv, weights=weights), 0.0)
    ea, eb = uniq // n, uniq % n
    e0 = V[ea] - V[eb]
    e1 = Vd[ea] - Vd[eb]
    outer = w[:, None, None] * e1[:, :, None] * e0[:, None, :]
    S = np.zeros((n, 3, 3))
    np.add.at(S, ea, outer)
    np.add.at(S, eb, outer)
    N = np.zeros(n)
    l2 = w * (e0 ** 2).sum(1)
    np.add.at(N, ea, l2)
    np.add.at(N, eb, l2)
    U, _, Vt = np.linalg.svd(S)
    det = np.linalg.det(U @ Vt)
    U[:, :, 2] *= np.where(det < 0, -1.0, 1.0)[:, None]
    R = U @ Vt
    E = np.zeros(n)
    for ends in (ea, eb):
        r = e1 - np.einsum("nij,nj->ni", R[ends], e0)
        np.add.at(E, ends, w * (r ** 2).sum(1))
    return E, N


def group1_stats(d, V, up=None):
    """Numbers of an edit's group 1 (DG1 nodes with e' > T) for figures and captions:
    group1, dg1 (counts), reach (largest distance of a group-1 node from the moveable
    handle's centroid over the diagonal) and, with `up` an axis, top (the highest
    group-1 node) and free_top (the highest vertex that is not a fixed handle), both
    as fractions of the height; `where` is a one-line summary."""
    P = np.asarray(d["dg1"]["positions"])
    e = np.asarray(d["dg1"]["e_prime"])
    g1 = P[e > d["threshold"]]
    c = V[np.asarray(d["moveable"], dtype=int)].mean(0)
    out = dict(group1=len(g1), dg1=len(P),
               reach=float(np.linalg.norm(g1 - c, axis=1).max()) / d["diag"] if len(g1) else 0.0)
    if up is None:
        out["where"] = "all within %.2f diag of the handle" % out["reach"]
        return out
    lo, hi = V[:, up].min(), V[:, up].max()
    free = np.ones(len(V), bool)
    free[np.asarray(d["fixed"], dtype=int)] = False
    out["top"] = float(g1[:, up].max() - lo) / (hi - lo) if len(g1) else 0.0
    out["free_top"] = float(V[free, up].max() - lo) / (hi - lo)
    out["where"] = "up to %.0f%% of the height (free leg: 0-%.0f%%)" % (
        100 * out["top"], 100 * out["free_top"])
    return out


def vertices_near(V, F, sources, radius):
    """Vertices not in `sources` whose distance along mesh edges (Dijkstra) from the
    nearest source is at most `radius`: experiments' VerticesNear, the band around
    the fixed region where arap_energy_joint is measured."""
    import heapq
    E = np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    E = np.unique(np.sort(E, axis=1), axis=0)
    length = np.linalg.norm(V[E[:, 0]] - V[E[:, 1]], axis=1)
    adj = [[] for _ in range(len(V))]
    for (a, b), l in zip(E.tolist(), length.tolist()):
        adj[a].append((b, l))
        adj[b].append((a, l))
    dist = np.full(len(V), np.inf)
    heap = []
    for s in np.asarray(sources, dtype=int).tolist():
        dist[s] = 0.0
        heap.append((0.0, s))
    heapq.heapify(heap)
    while heap:
        d, v = heapq.heappop(heap)
        if d > dist[v] or d > radius:
            continue
        for w, l in adj[v]:
            if d + l < dist[w] and d + l <= radius:
                dist[w] = d + l
                heapq.heappush(heap, (d + l, w))
    near = dist <= radius
    near[np.asarray(sources, dtype=int)] = False
    return np.where(near)[0]


def edit_metrics(d, V, F, Vd, V_ref=None, joint_band=0.05):
    """Numbers of one exported edit (the figures' captions): arap (experiments'
    arap_energy), arap_joint (over the vertices within joint_band diag of the fixed
    region along edges), local_max (largest E_i / N_i), fixed_max (largest fixed-
    vertex displacement) and, with V_ref, diff_max (largest |Vd - V_ref|), lengths
    over the diagonal; `local` is E_i / N_i per vertex."""
    E, N = arap_energy_per_vertex(V, F, Vd)
    local = E / np.maximum(N, 1e-300)
    fixed = np.asarray(d["fixed"], dtype=int)
    band = vertices_near(V, F, fixed, joint_band * d["diag"]) if len(fixed) else []
    out = dict(arap=E.sum() / N.sum(), local=local, local_max=float(local.max()),
               arap_joint=E[band].sum() / N[band].sum() if len(band) else float("nan"),
               fixed_max=float(np.linalg.norm(Vd[fixed] - V[fixed], axis=1).max()) / d["diag"]
               if len(fixed) else 0.0)
    if V_ref is not None:
        out["diff_max"] = float(np.linalg.norm(Vd - V_ref, axis=1).max()) / d["diag"]
    return out
