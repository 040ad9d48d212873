"""msdeform: the multi-scale mesh editing method of Liu & Su (ICVGIP 2008) from Python.

The C++ library (the extension ``msdeform._msdeform``) on NumPy arrays::

    import msdeform
    V, F = msdeform.read_mesh("data/meshes/cactus.off")          # (#V, 3), (#F, 3)
    status = msdeform.read_sel("data/meshes/cactus.sel", len(V))  # 0 fixed, 1 free, 2 handle
    M = msdeform.read_def("data/meshes/cactus.def")               # 4 x 4
    d = msdeform.Deformer(V, F, method="multiscale")
    d.set_handles(status)
    V2 = d.drag_along(M, frames=30)   # or d.drag(M): one frame

Arrays: vertices float64 (#V, 3), faces int32 (#F, 3) (any integer dtype is accepted),
vertex id lists 1-D integer arrays, transforms 4x4 with last row 0 0 0 1 (or 3x4).
``Deformer.drag`` returns a read-only view of the Deformer's own storage that the next drag
updates in place; ``.copy()`` keeps a frame.

Errors carry the C++ message: TypeError for a wrong type or dtype (or an unknown option
keyword), ValueError for a wrong shape or value (arrays, options, handle layouts), OSError for
a file that cannot be read or written, RuntimeError for a failed solve or a drag before
set_handles.
"""

import inspect as _inspect

from ._msdeform import (
    COMMIT,
    GRAPH_METHODS,
    NODE_CLASSES,
    RESULT_COLUMNS,
    CeresOptions,
    Deformer,
    DeformerOptions,
    GaussNewtonOptions,
    GraphOptions,
    LatticeOptions,
    MAX_SCENARIO_FRAMES,
    METHODS,
    Method,
    RigidityOptions,
    ScaleSelectionOptions,
    Scenario,
    StoppingRule,
    __version__,
    arap_energy_per_vertex,
    bounding_box_diagonal,
    describe_method_options,
    describe_options,
    drag_path,
    handle_rms_error,
    leakage,
    load_scenario,
    mean_edge_strain,
    normalised_arap_energy,
    option_flags,
    option_rows,
    options_from_flags,
    orthogonality_error,
    paper_procedure,
    read_def,
    read_mesh,
    read_sel,
    run_cgal_arap,
    run_deformer,
    run_method,
    vertex_displacement,
    vertices_near,
    write_def,
    write_mesh,
    write_sel,
)

OPTIONS_CLASSES = (
    LatticeOptions,
    GraphOptions,
    RigidityOptions,
    ScaleSelectionOptions,
    StoppingRule,
    GaussNewtonOptions,
    CeresOptions,
    DeformerOptions,
)

__all__ = [
    "COMMIT",
    "GRAPH_METHODS",
    "NODE_CLASSES",
    "OPTIONS_CLASSES",
    "RESULT_COLUMNS",
    "CeresOptions",
    "Deformer",
    "DeformerOptions",
    "GaussNewtonOptions",
    "GraphOptions",
    "LatticeOptions",
    "METHODS",
    "Method",
    "RigidityOptions",
    "ScaleSelectionOptions",
    "Scenario",
    "StoppingRule",
    "__version__",
    "arap_energy_per_vertex",
    "bounding_box_diagonal",
    "deform",
    "describe_method_options",
    "describe_options",
    "drag_path",
    "handle_rms_error",
    "leakage",
    "load_scenario",
    "mean_edge_strain",
    "normalised_arap_energy",
    "option_flags",
    "option_rows",
    "options_from_flags",
    "orthogonality_error",
    "paper_procedure",
    "read_def",
    "read_mesh",
    "read_sel",
    "run_cgal_arap",
    "run_deformer",
    "run_method",
    "vertex_displacement",
    "vertices_near",
    "write_def",
    "write_mesh",
    "write_sel",
]


def _keyword_signature(cls):
    """The keyword-only signature of an options class, defaults from a default instance."""
    defaults = cls()
    return _inspect.Signature(
        [
            _inspect.Parameter(name, _inspect.Parameter.KEYWORD_ONLY, default=getattr(defaults, name))
            for name in cls.fields
        ]
    )


for _cls in OPTIONS_CLASSES:
    # help() and inspect.signature() show every field with its C++ default.
    _cls.__signature__ = _keyword_signature(_cls)
del _cls


def deform(V, F, status, M, frames=1, options=None, **kwargs):
    """Deforms a mesh in one call and returns the deformed vertices as a new (#V, 3) array.

    The one-off form of ``Deformer(V, F, options, **kwargs)``, ``set_handles(status)`` and
    ``drag_along(M, frames=frames)``: ``status`` is a per-vertex array (0 fixed, 1 free,
    2 handle) or a .sel path, ``M`` the handle's final 4x4 transform, reached in ``frames``
    equal steps about the handle's rest centroid (as ``msdeform --sel --def --frames``).
    Use a Deformer to drag the same layout more than once.
    """
    deformer = Deformer(V, F, options, **kwargs)
    deformer.set_handles(status)
    return deformer.drag_along(M, frames=frames).copy()
