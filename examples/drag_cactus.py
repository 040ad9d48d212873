"""Bend the cactus with msdeform from Python and compare the multi-scale method with a static graph.

    PYTHONPATH=build/python python3 examples/drag_cactus.py [OUT_DIR]

Reads the Botsch-Sorkine cactus benchmark (data/meshes/cactus.off, .sel, .def), drags its
handle to the .def transform in 10 frames with the multi-scale method and with one static
graph, prints what each did (scale, variables, time per frame, handle error, ARAP energy) and
writes both deformed meshes to OUT_DIR (default: examples_out/).
"""

import pathlib
import sys

import numpy as np

import msdeform

ROOT = pathlib.Path(__file__).resolve().parent.parent
MESHES = ROOT / "data" / "meshes"


def deform(V, F, status, M, method):
    """Drags the handle to M in 10 frames; returns the deformed vertices and the Method."""
    editor = msdeform.Method(V, F, method)
    editor.set_handles(status)
    return editor.drag_along(M, frames=10), editor  # a new array, as libigl returns


def main(out_dir):
    V, F = msdeform.read_mesh(MESHES / "cactus.off")
    status = msdeform.read_sel(MESHES / "cactus.sel", len(V))
    M = msdeform.read_def(MESHES / "cactus.def")
    handle = np.flatnonzero(status == 2)
    diagonal = msdeform.bounding_box_diagonal(V)
    out_dir.mkdir(parents=True, exist_ok=True)
    print(f"cactus: {len(V)} vertices, {np.count_nonzero(status == 0)} fixed, {len(handle)} handle")
    for method in ("multiscale", "static"):
        V2, editor = deform(V, F, status, M, method)
        frame_ms = np.median([frame["frame_ms"] for frame in editor.frame_stats])
        handle_error = msdeform.handle_rms_error(V, V2, handle, M) / diagonal
        energy = msdeform.normalised_arap_energy(*msdeform.arap_energy_per_vertex(V, F, V2))
        if method == "multiscale":
            graph = f"scale {editor.selected_scale} of {editor.num_scales}"
        else:
            graph = "one static graph"
        print(f"{method:>10}: {graph} ({len(editor.node_positions)} nodes), "
              f"{editor.num_variables} variables, {frame_ms:.2f} ms/frame, "
              f"handle error {handle_error:.2e} of the diagonal, ARAP energy {energy:.4f}")
        path = out_dir / f"cactus_{method}.off"
        msdeform.write_mesh(path, V2, F)
        print(f"{'':>10}  wrote {path}")


if __name__ == "__main__":
    main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path("examples_out"))
