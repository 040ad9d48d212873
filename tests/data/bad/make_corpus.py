#!/usr/bin/env python3
"""Writes the bad-input corpus of tests/data/bad/ (run once; the files are
committed). Each file is small and named after what is wrong with it;
MANIFEST.tsv says what msdeform must do with it."""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def bar(nx=8, ny=2, nz=2, scale=0.5, offset=(0.0, 0.0, 0.0)):
    """Closed box [0, nx*scale] x [0, ny*scale] x [0, nz*scale] as quads."""
    ids = {}
    verts = []
    quads = []

    def vid(i, j, k):
        key = (i, j, k)
        if key not in ids:
            ids[key] = len(verts)
            verts.append((i * scale + offset[0], j * scale + offset[1], k * scale + offset[2]))
        return ids[key]

    n = (nx, ny, nz)
    for axis in range(3):
        u, v = (axis + 1) % 3, (axis + 2) % 3
        for side in (0, n[axis]):
            for a in range(n[u]):
                for b in range(n[v]):
                    def p(da, db):
                        c = [0, 0, 0]
                        c[axis] = side
                        c[u] = a + da
                        c[v] = b + db
                        return vid(*c)
                    q = [p(0, 0), p(1, 0), p(1, 1), p(0, 1)]
                    if side == 0:
                        q.reverse()
                    quads.append(q)
    return verts, quads


def tris(quads):
    out = []
    for q in quads:
        out.append([q[0], q[1], q[2]])
        out.append([q[0], q[2], q[3]])
    return out


def off(verts, faces, header=None):
    lines = [header or "OFF", "%d %d 0" % (len(verts), len(faces))]
    lines += ["%s %s %s" % tuple(repr(float(c)) if isinstance(c, float) else str(c) for c in v)
              for v in verts]
    lines += ["%d %s" % (len(f), " ".join(str(i) for i in f)) for f in faces]
    return "\n".join(lines) + "\n"


def obj(verts, faces):
    lines = ["v %s %s %s" % tuple(str(c) for c in v) for v in verts]
    lines += ["f " + " ".join(str(i + 1) for i in f) for f in faces]
    return "\n".join(lines) + "\n"


def stl_ascii(verts, faces):
    lines = ["solid bar"]
    for f in faces:
        lines += ["  facet normal 0 0 0", "    outer loop"]
        lines += ["      vertex %s %s %s" % tuple(repr(float(c)) for c in verts[i]) for i in f]
        lines += ["    endloop", "  endfacet"]
    return "\n".join(lines + ["endsolid bar"]) + "\n"


def stl_binary(verts, faces):
    data = b" " * 80 + struct.pack("<I", len(faces))
    for f in faces:
        data += struct.pack("<3f", 0, 0, 0)
        for i in f:
            data += struct.pack("<3f", *verts[i])
        data += b"\0\0"
    return data


def write(name, text, binary=False):
    with open(os.path.join(HERE, name), "wb" if binary else "w") as f:
        f.write(text)


def sel(n, status):
    return ("# per vertex status: 0=fixed, 1=deformable-region, 2=handle\n# %d vertices\n" % n +
            "".join("%d\n" % status(i) for i in range(n)))


V, Q = bar()
T = tris(Q)
n = len(V)
# The good inputs every handle case uses.
write("bar.off", off(V, T))
write("bar.sel", sel(n, lambda i: 0 if V[i][0] <= 0.0 else (2 if V[i][0] >= 4.0 else 1)))
write("bar.def", "# 4x4\n1 0 0 0\n0 1 0 0.5\n0 0 1 0\n0 0 0 1\n")
write("slab_x.json", '{\n  "fixed": [{"slab": {"axis": "x", "from": 0, "to": 0.05}}],\n'
      '  "mesh": "bar.off",\n'
      '  "handle": {"slab": {"axis": "x", "from": 0.95, "to": 1}},\n'
      '  "transform": {"translation_rel": [0, 0.1, 0]},\n  "frames": 2\n}\n')

# Meshes.
write("mesh_empty.off", "")
write("mesh_truncated.off", off(V, T)[:400])
write("mesh_wrong_header.off", off(V, T).replace("OFF", "OFX", 1))
write("mesh_face_out_of_range.off", off(V, T[:-1] + [[0, 1, n + 5]]))
write("mesh_face_negative_index.off", off(V, T[:-1] + [[0, 1, -1]]))
# Faces that repeat a vertex, or repeat an earlier face in the same cyclic
# order, are dropped with a notice; a mesh of nothing else is an error.
write("mesh_face_repeated_index.off", off(V, T[:-1] + [[0, 1, 1]]))
write("mesh_all_faces_repeat_a_vertex.off", off(V, [[a, a, b] for a, b, c in T]))
write("mesh_duplicate_faces.off", off(V, T + [T[0][1:] + T[0][:1], T[5]]))
# STL: a facet with two corners at one position, a facet repeated; and a
# facet cut short.
write("mesh_stl_drops.stl", stl_binary(V, T + [[0, 1, 1], T[3]]), binary=True)
write("mesh_stl_truncated.stl", stl_ascii(V, T).rsplit("      vertex", 1)[0])
write("mesh_face_two_vertices.off", off(V, T + [[0, 1]]))
write("mesh_quads.off", off(V, Q))
write("mesh_pentagon_fan.off", off(V + [(2.0, 0.5, -0.5)], T + [[0, 1, 2, 3, n]]))
write("mesh_nan.off", off(V[:5] + [("nan", 0, 0)] + V[6:], T))
write("mesh_inf.off", off(V[:5] + [(0, "inf", 0)] + V[6:], T))
write("mesh_not_a_number.off", off(V[:5] + [(0, "1.2.3", 0)] + V[6:], T))
write("mesh_degenerate_faces.off", off(V + [(1.0, 0.0, 0.0)], T + [[0, 1, n]]))
write("mesh_duplicate_vertices.off", off(V + [V[0], V[1]], T + [[n, n + 1, 2]]))
write("mesh_isolated_vertices.off", off(V + [(9.0, 9.0, 9.0), (1.0, 0.5, 0.5)], T))
V2, Q2 = bar(offset=(0.0, 3.0, 0.0))
write("mesh_two_components.off", off(V + V2, T + [[a + n, b + n, c + n] for a, b, c in tris(Q2)]))
write("mesh_two_components.sel",
      sel(2 * n, lambda i: 1 if i >= n else (0 if V[i][0] <= 0.0 else (2 if V[i][0] >= 4.0 else 1))))
# A fin: a third triangle on an edge of the bar, with its own new vertex.
e = T[0]
write("mesh_nonmanifold_edge.off", off(V + [(-1.0, -1.0, -1.0)], T + [[e[0], e[1], n]]))
# Two bars touching at one vertex (bowtie): the second bar's corner is vertex 0.
V3, Q3 = bar(offset=(-4.0, -1.0, -1.0))
corner = V3.index((0.0, 0.0, 0.0))
remap = lambda i: 0 if i == corner else n + i - (1 if i > corner else 0)
V3b = [v for i, v in enumerate(V3) if i != corner]
write("mesh_nonmanifold_vertex.off",
      off(V + V3b, T + [[remap(a), remap(b), remap(c)] for a, b, c in tris(Q3)]))
write("mesh_nonmanifold_vertex.sel",
      sel(n + len(V3b), lambda i: 2 if i < n and V[i][0] >= 4.0 else (0 if i >= n and V3b[i - n][0] <= -4.0 else 1)))
write("mesh_single_triangle.off", off([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [[0, 1, 2]]))
write("mesh_single_triangle.sel", sel(3, lambda i: [0, 2, 1][i]))
flat = [(i * 0.25, j * 0.25, 0.0) for j in range(5) for i in range(9)]
flat_faces = []
for j in range(4):
    for i in range(8):
        a = j * 9 + i
        flat_faces += [[a, a + 1, a + 10], [a, a + 10, a + 9]]
write("mesh_flat.off", off(flat, flat_faces))
write("mesh_flat.sel", sel(len(flat), lambda i: 0 if flat[i][0] == 0 else (2 if flat[i][0] == 2.0 else 1)))
write("mesh_only_vertices.off", off(V, []))
# NOFF whose vertex lines lack the normals: OpenMesh would read the next
# line's coordinates as normals (found by tests/fuzz/off_fuzzer); the normals
# are not used, so this reads as plain OFF.
write("mesh_noff_without_normals.off", off(V, T, header="NOFF"))
write("mesh_huge_counts.off", "OFF\n1000000000 2000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
write("mesh_negative_counts.off", "OFF\n-3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
write("mesh_binary_garbage.off", b"OFF BINARY\n" + struct.pack("<3I", 5, 7, 0) + b"\x01\x02", binary=True)
# Binary OFF whose face announces 2^31-1 vertices: OpenMesh allocated that
# many ids (found by tests/fuzz/off_fuzzer).
write("mesh_binary_face_count.off", b"OFF BINARY\n" + struct.pack("<3i", 3, 1, 0) +
      struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<4i", 2147483647, 0, 1, 2),
      binary=True)
write("mesh_bad_coord.obj", obj(V[:3] + [(0, "x", 0)] + V[4:], T))
write("mesh_face_out_of_range.obj", obj(V, T + [[0, 1, n + 10]]))
write("mesh_quads.obj", obj(V, Q))
# A face corner without its vertex number: OpenMesh's OBJ reader asserts on
# it (found by tests/fuzz/obj_fuzzer).
write("mesh_face_corner_without_vertex.obj", obj(V, T) + "f /1/1 2/1/1 3/1/1\n")
write("mesh_face_tabs_and_slashes.obj", obj(V, []) + "".join(
    "f\t%d//1\t%d//1\t%d//1\n" % (a + 1, b + 1, c + 1) for a, b, c in T))
write("mesh_truncated.ply", "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\n"
      "property float y\nproperty float z\nelement face 12\nproperty list uchar int vertex_indices\n"
      "end_header\n0 0 0\n1 0 0\n")
write("mesh_unknown_format.xyz", "0 0 0\n")
write("mesh_is_folder.off/.keep", "") if os.path.isdir(os.path.join(HERE, "mesh_is_folder.off")) else (
    os.makedirs(os.path.join(HERE, "mesh_is_folder.off")), write("mesh_is_folder.off/.keep", ""))

# Handles (for bar.off).
write("sel_too_few.sel", sel(n - 3, lambda i: 2 if i == 0 else 1))
write("sel_too_many.sel", sel(n + 1, lambda i: 2 if i == 0 else 1))
write("sel_status_3.sel", sel(n, lambda i: 3 if i == 7 else (2 if i == 0 else 1)))
write("sel_negative.sel", sel(n, lambda i: -1 if i == 7 else (2 if i == 0 else 1)))
write("sel_not_integer.sel", sel(n, lambda i: 2 if i == 0 else 1).replace("\n1\n", "\n1.5\n", 1))
write("sel_two_per_line.sel", sel(n, lambda i: 2 if i == 0 else 1).replace("\n1\n", "\n1 1\n", 1))
write("sel_no_handle.sel", sel(n, lambda i: 0 if i < 5 else 1))
write("sel_empty.sel", "")
write("def_3x4.def", "1 0 0 0\n0 1 0 0\n0 0 1 0\n")
write("def_17_numbers.def", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1 5\n")
write("def_nan.def", "1 0 0 nan\n0 1 0 0\n0 0 1 0\n0 0 0 1\n")
write("def_inf.def", "1 0 0 0\n0 1 0 inf\n0 0 1 0\n0 0 0 1\n")
write("def_last_row.def", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 1 1\n")
write("def_text.def", "1 0 0 zero\n0 1 0 0\n0 0 1 0\n0 0 0 1\n")
write("def_huge.def", "1 0 0 1e300\n0 1 0 1e300\n0 0 1 0\n0 0 0 1\n")

# Scenarios (mesh bar.off).
def scenario(name, body):
    write(name, body)

scenario("scn_not_json.json", '{"mesh": "bar.off",\n "handle": {"vertices": [1]}\n')
scenario("scn_empty.json", "")
scenario("scn_missing_handle.json", '{"mesh": "bar.off"}\n')
scenario("scn_missing_mesh.json", '{"handle": {"vertices": [1]}}\n')
scenario("scn_handle_number.json", '{"mesh": "bar.off", "handle": 5}\n')
scenario("scn_frames_string.json", '{"mesh": "bar.off", "handle": {"vertices": [1]}, "frames": "ten"}\n')
scenario("scn_frames_huge.json", '{"mesh": "bar.off", "handle": {"vertices": [1]}, "frames": 2000000000}\n')
scenario("scn_frames_zero.json", '{"mesh": "bar.off", "handle": {"vertices": [1]}, "frames": 0}\n')
scenario("scn_unknown_field.json", '{"mesh": "bar.off", "handle": {"vertices": [1]}, "handel": 1}\n')
scenario("scn_region_selects_nothing.json",
         '{"mesh": "bar.off", "handle": {"vertices": [1]},\n'
         ' "fixed": [{"sphere": {"center": [100, 100, 100], "radius": 0.1}}]}\n')
scenario("scn_all_empty_intersection.json",
         '{"mesh": "bar.off", "handle": {"all": [{"slab": {"axis": "x", "from": 0, "to": 0.1}},'
         ' {"slab": {"axis": "x", "from": 0.9, "to": 1}}]}}\n')
scenario("scn_overlap.json",
         '{"mesh": "bar.off", "handle": {"vertices": [1, 2]}, "fixed": [{"vertices": [2, 3]}]}\n')
scenario("scn_vertex_out_of_range.json", '{"mesh": "bar.off", "handle": {"vertices": [100000]}}\n')
scenario("scn_slab_axis_w.json", '{"mesh": "bar.off", "handle": {"slab": {"axis": "w", "from": 0, "to": 1}}}\n')
scenario("scn_translation_two.json",
         '{"mesh": "bar.off", "handle": {"vertices": [1]}, "transform": {"translation": [1, 2]}}\n')
scenario("scn_mesh_missing_file.json", '{"mesh": "no_such_mesh.off", "handle": {"vertices": [1]}}\n')
scenario("scn_negative_radius.json",
         '{"mesh": "bar.off", "handle": {"sphere": {"center_vertex": 0, "radius": -1}}}\n')
scenario("scn_region_too_deep.json",
         '{"mesh": "bar.off", "fixed": [{"slab": {"axis": "x", "from": 0, "to": 0.1}}], '
         '"handle": ' + '{"not": ' * 100 + '{"vertices": [0]}' + '}' * 100 + '}\n')
scenario("scn_rotation_axis_huge.json",
         '{"mesh": "bar.off", "fixed": [{"slab": {"axis": "x", "from": 0, "to": 0.1}}],\n'
         ' "handle": {"slab": {"axis": "x", "from": 0.9, "to": 1}},\n'
         ' "transform": {"rotation": {"axis": [1e300, 1e300, 1e300], "angle_deg": 30}}}\n')
# --rerun reports with the wrong types or a flag that is not msdeform's.
write("rerun_inputs_string.json", '{"flags": {}, "inputs": "x"}\n')
write("rerun_input_path_number.json", '{"flags": {}, "inputs": [{"path": 5}]}\n')
write("rerun_flagfile.json", '{"flags": {"flagfile": "/etc/passwd"}, "inputs": []}\n')
