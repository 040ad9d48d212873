#!/usr/bin/python3
"""Checks of msdeform_editor's outputs for tests/editor/editor_test.sh.

Reads PNGs with stb_image through ctypes (no imaging module here), the editor's camera
JSON (apps/editor/screenshot.h) to project vertices onto a screenshot, plain
OFF meshes as the editor and msdeform write them, and .sel/.def files.

  check_outputs.py pixels PNG CAMERA MESH SEL        handle red, fixed blue, the rest shaded grey
  check_outputs.py same_mesh A B [TOLERANCE]          max |a - b| / diagonal <= TOLERANCE (1e-9)
  check_outputs.py drag CAMERA REST SEL DEF_A DEF_B DX DY   the handle moved (DX, DY) pixels
  check_outputs.py lasso CAMERA MESH SEL X0 Y0 X1 Y1  fixed vertices: inside the box, and some
  check_outputs.py label SEL VERTEX STATUS            the vertex has this .sel status
  check_outputs.py panels CAMERA NAME...               the named panels are drawn, inside the
                                                       image, nothing cut or scrolled away
  check_outputs.py handle_pixels PNG MIN_RED [MIN_BLUE]   at least MIN_RED handle-red pixels
                                                       (and MIN_BLUE fixed-blue ones)

Each prints one line and exits 1 when the check fails.
"""

import ctypes
import json
import sys

import numpy as np

BACKGROUND = np.array([236, 238, 242])  # apps/editor/overlays.h, kBackgroundColor


def fail(message):
    print("FAIL " + message)
    sys.exit(1)


def read_png(path):
    """height x width x 3 uint8, decoded by stb_image (Debian's libstb, the editor's own
    image library; the Python here has no imaging module)."""
    stb = ctypes.CDLL("libstb.so.0")
    stb.stbi_load.restype = ctypes.POINTER(ctypes.c_ubyte)
    stb.stbi_load.argtypes = [ctypes.c_char_p, ctypes.POINTER(ctypes.c_int),
                              ctypes.POINTER(ctypes.c_int), ctypes.POINTER(ctypes.c_int),
                              ctypes.c_int]
    stb.stbi_image_free.argtypes = [ctypes.c_void_p]
    width, height, channels = ctypes.c_int(), ctypes.c_int(), ctypes.c_int()
    with open(path, "rb") as f:
        if f.read(8) != b"\x89PNG\r\n\x1a\n":
            fail(path + ": not a PNG")
    data = stb.stbi_load(path.encode(), ctypes.byref(width), ctypes.byref(height),
                         ctypes.byref(channels), 3)
    if not data:
        fail(path + ": stb_image cannot decode it")
    size = width.value * height.value * 3
    image = np.ctypeslib.as_array(data, shape=(size,)).astype(np.int32).reshape(
        height.value, width.value, 3)
    stb.stbi_image_free(data)
    return image


def read_off(path):
    """Vertices (n x 3) and triangles (m x 3) of a plain OFF file."""
    tokens = [t for line in open(path) for t in line.split("#")[0].split()]
    if tokens[0] != "OFF":
        fail(path + ": expected a plain OFF file")
    n, m = int(tokens[1]), int(tokens[2])
    vertices = np.array(tokens[4:4 + 3 * n], dtype=float).reshape(n, 3)
    faces, at = [], 4 + 3 * n
    for _ in range(m):
        count = int(tokens[at])
        faces.append([int(x) for x in tokens[at + 1:at + 1 + count]])
        at += 1 + count
    return vertices, np.array(faces)


def read_sel(path):
    return np.array([int(line) for line in open(path) if line.strip() and not line.startswith("#")])


def read_def(path):
    values = [float(x) for line in open(path) if not line.startswith("#") for x in line.split()]
    return np.array(values).reshape(4, 4)


def project(camera, points):
    """Pixel coordinates (x right, y down from the top-left) and eye-space points."""
    view = np.array(camera["view"]).reshape(4, 4)
    projection = np.array(camera["projection"]).reshape(4, 4)
    homogeneous = np.c_[points, np.ones(len(points))]
    eye = homogeneous @ view.T
    clip = eye @ projection.T
    ndc = clip[:, :3] / clip[:, 3:4]
    x = (ndc[:, 0] + 1) / 2 * camera["width"]
    y = (1 - ndc[:, 1]) / 2 * camera["height"]
    return np.c_[x, y], eye[:, :3]


def vertex_normals(vertices, faces):
    normals = np.zeros_like(vertices)
    a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    face_normals = np.cross(b - a, c - a)
    for k in range(3):
        np.add.at(normals, faces[:, k], face_normals)
    return normals / np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-300)


def classify(pixel):
    r, g, b = (int(v) for v in pixel)
    if np.abs(np.array([r, g, b]) - BACKGROUND).max() <= 2:
        return "background"
    if r > 60 and r > 2 * g and r > 2 * b:
        return "red"
    if b > 80 and b > 1.6 * r and b > 1.2 * g:
        return "blue"
    if max(r, g, b) - min(r, g, b) <= 24:
        return "grey"
    return "other"


def check_pixels(png, camera_path, mesh_path, sel_path):
    image = read_png(png)
    camera = json.load(open(camera_path))
    height, width, _ = image.shape
    if width < 800 or height < 600:
        fail(f"{png}: {width} x {height}, expected at least 800 x 600")
    if (width, height) != (camera["width"], camera["height"]):
        fail(f"{png}: {width} x {height} but the camera says "
             f"{camera['width']} x {camera['height']}")
    vertices, faces = read_off(mesh_path)
    status = read_sel(sel_path)
    pixels, eye = project(camera, vertices)
    # Vertices facing the eye (at the eye-space origin) clearly, not at the silhouette,
    # where the pixel centre may fall just outside the surface.
    view = np.array(camera["view"]).reshape(4, 4)
    normals_eye = vertex_normals(vertices, faces) @ view[:3, :3].T
    to_eye = -eye / np.linalg.norm(eye, axis=1, keepdims=True)
    front = np.einsum("ij,ij->i", normals_eye, to_eye) > 0.3
    inside = (pixels[:, 0] >= 1) & (pixels[:, 0] < width - 1) & (pixels[:, 1] >= 1) & (
        pixels[:, 1] < height - 1)
    for corner in [(0, 0), (0, width - 1), (height - 1, 0), (height - 1, width - 1)]:
        if classify(image[corner]) != "background":
            fail(f"{png}: corner {corner} is {image[corner]}, not the background {BACKGROUND}")
    # The shaded mesh is where the vertices project, and nowhere else.
    mesh_mask = np.abs(image - BACKGROUND).max(axis=2) > 2
    ys, xs = np.nonzero(mesh_mask)
    low, high = pixels[inside].min(axis=0) - 3, pixels[inside].max(axis=0) + 3
    if xs.min() < low[0] or xs.max() > high[0] or ys.min() < low[1] or ys.max() > high[1]:
        fail(f"{png}: drawn pixels span x {xs.min()}..{xs.max()}, y {ys.min()}..{ys.max()}; the "
             f"mesh projects to x {low[0]:.0f}..{high[0]:.0f}, y {low[1]:.0f}..{high[1]:.0f}")

    def window(v, r):
        x, y = int(pixels[v, 0]), int(pixels[v, 1])
        return mesh_mask[max(y - r, 0):y + r + 1, max(x - r, 0):x + r + 1]

    candidates = np.where(front & inside)[0]
    covered = np.mean([window(v, 1).any() for v in candidates])
    if covered < 0.99:
        fail(f"{png}: only {covered:.3f} of the vertices facing the eye land on drawn pixels")
    # Colours away from the silhouette (a 5 x 5 window all drawn), where the pixel
    # centre is surely on the surface.
    interior = np.array([window(v, 2).all() for v in range(len(vertices))]) & front & inside
    if interior.sum() < 0.5 * len(candidates):
        fail(f"{png}: only {interior.sum()} of {len(candidates)} vertices lie inside the drawing")
    expected = {0: "blue", 2: "red", 1: "grey"}
    report = []
    for label, colour in expected.items():
        chosen = np.where((status == label) & interior)[0]
        if len(chosen) < 5:
            fail(f"{png}: only {len(chosen)} visible vertices with status {label}")
        seen = [classify(image[int(pixels[v, 1]), int(pixels[v, 0])]) for v in chosen]
        share = seen.count(colour) / len(seen)
        report.append(f"{colour} {share:.2f} of {len(seen)}")
        if share < 0.8:
            counts = {c: seen.count(c) for c in set(seen)}
            fail(f"{png}: status-{label} vertices should look {colour}; pixels there: {counts}")
    grey = [image[int(pixels[v, 1]), int(pixels[v, 0])].mean()
            for v in np.where((status == 1) & interior)[0]]
    if np.std(grey) < 3:
        fail(f"{png}: the free region is flat (luminance std {np.std(grey):.1f}): not shaded")
    print(f"ok {png}: {width} x {height}; " + ", ".join(report) +
          f"; shading std {np.std(grey):.1f}")


def colour_masks(image):
    """Boolean masks of the handle-red and fixed-blue pixels, as classify() decides."""
    r, g, b = image[:, :, 0], image[:, :, 1], image[:, :, 2]
    red = (r > 60) & (r > 2 * g) & (r > 2 * b)
    blue = (b > 80) & (b > 1.6 * r) & (b > 1.2 * g)
    return red, blue


def check_handle_pixels(png, min_red, min_blue=0):
    """The handle is seen: at least min_red red pixels (and min_blue blue ones)."""
    image = read_png(png)
    red, blue = colour_masks(image)
    height, width, _ = image.shape
    line = (f"{png}: {red.sum()} handle-red pixels ({100 * red.mean():.2f}% of {width} x "
            f"{height}), {blue.sum()} fixed-blue")
    if red.sum() < min_red or blue.sum() < min_blue:
        fail(f"{line}; expected at least {min_red} red and {min_blue} blue")
    print("ok " + line)


def check_panels(camera_path, names):
    """The panel windows of a screenshot with the panels (the camera JSON's "panels"):
    the named ones are there, each lies inside the image, and its contents fit it
    (overflow <= 0: no line cut at the right, nothing below the bottom to scroll to)."""
    camera = json.load(open(camera_path))
    panels = {p["name"]: p for p in camera.get("panels", [])}
    for name in names:
        if name not in panels:
            fail(f"{camera_path}: no panel {name!r} (panels: {sorted(panels)})")
    for name, p in panels.items():
        if (p["x"] < 0 or p["y"] < 0 or p["x"] + p["width"] > camera["width"] or
                p["y"] + p["height"] > camera["height"]):
            fail(f"{camera_path}: panel {name!r} at {p['x']}, {p['y']} size {p['width']} x "
                 f"{p['height']} runs past the {camera['width']} x {camera['height']} image")
        if p["overflow_x"] > 0 or p["overflow_y"] > 0:
            fail(f"{camera_path}: panel {name!r}: contents reach {p['overflow_x']} px past its "
                 f"right and {p['overflow_y']} px past its bottom")
    print(f"ok {camera_path}: " + ", ".join(
        f"{n} {p['width']:.0f} x {p['height']:.0f} (room {-p['overflow_y']:.0f} px)"
        for n, p in panels.items()))


def check_same_mesh(a_path, b_path, tolerance=1e-9):
    a, fa = read_off(a_path)
    b, fb = read_off(b_path)
    if a.shape != b.shape or not np.array_equal(fa, fb):
        fail(f"{a_path} and {b_path}: different sizes or faces")
    diagonal = np.linalg.norm(b.max(axis=0) - b.min(axis=0))
    gap = np.abs(a - b).max() / diagonal
    if not gap <= tolerance:
        fail(f"{a_path} vs {b_path}: max difference {gap:.3g} of the diagonal > {tolerance:g}")
    print(f"ok {a_path} = {b_path} within {gap:.3g} of the diagonal")


def check_drag(camera_path, rest_path, sel_path, def_a, def_b, dx, dy):
    camera = json.load(open(camera_path))
    rest, _ = read_off(rest_path)
    status = read_sel(sel_path)
    centroid = rest[status == 2].mean(axis=0)
    points = []
    for path in (def_a, def_b):
        m = read_def(path)
        points.append(m[:3, :3] @ centroid + m[:3, 3])
    pixels, _ = project(camera, np.array(points))
    moved = pixels[1] - pixels[0]
    if np.abs(moved - np.array([dx, dy])).max() > 0.05:
        fail(f"the handle's centroid moved {moved} pixels, expected ({dx}, {dy})")
    print(f"ok the mouse moved the handle by {moved[0]:.3f}, {moved[1]:.3f} pixels")


def check_lasso(camera_path, mesh_path, sel_path, x0, y0, x1, y1):
    camera = json.load(open(camera_path))
    vertices, _ = read_off(mesh_path)
    status = read_sel(sel_path)
    pixels, _ = project(camera, vertices)
    fixed = np.where(status == 0)[0]
    if len(fixed) == 0:
        fail("the lasso selected nothing")
    box = (pixels[fixed, 0] >= x0) & (pixels[fixed, 0] <= x1) & (pixels[fixed, 1] >= y0) & (
        pixels[fixed, 1] <= y1)
    if not box.all():
        fail(f"{(~box).sum()} lasso-selected vertices project outside the lasso")
    print(f"ok the lasso selected {len(fixed)} vertices, all inside it")


def check_label(sel_path, vertex, expected):
    status = read_sel(sel_path)
    if status[vertex] != expected:
        fail(f"{sel_path}: vertex {vertex} has status {status[vertex]}, expected {expected}")
    print(f"ok {sel_path}: vertex {vertex} has status {expected} ({(status == expected).sum()} do)")


if __name__ == "__main__":
    command, args = sys.argv[1], sys.argv[2:]
    if command == "pixels":
        check_pixels(*args)
    elif command == "same_mesh":
        check_same_mesh(args[0], args[1], *(float(x) for x in args[2:]))
    elif command == "drag":
        check_drag(*args[:5], float(args[5]), float(args[6]))
    elif command == "lasso":
        check_lasso(args[0], args[1], args[2], *(float(x) for x in args[3:]))
    elif command == "panels":
        check_panels(args[0], args[1:])
    elif command == "handle_pixels":
        check_handle_pixels(args[0], *(int(x) for x in args[1:]))
    elif command == "label":
        check_label(args[0], int(args[1]), int(args[2]))
    else:
        fail("unknown check " + command)
