"""msdeform: the multi-scale mesh editing method of Liu & Su (ICVGIP 2008) from Python.

The C++ library (the extension ``msdeform._msdeform``) on NumPy arrays::

    import msdeform
    V, F = msdeform.read_mesh("data/meshes/cactus.off")          # (#V, 3), (#F, 3)
    status = msdeform.read_sel("data/meshes/cactus.sel", len(V))  # 0 fixed, 1 free, 2 handle
    M = msdeform.read_def("data/meshes/cactus.def")               # 4 x 4
    e = msdeform.Method(V, F, method="multiscale")                # any name in msdeform.METHODS
    e.set_handles(status)
    V2 = e.drag_along(M, frames=30)   # or e.drag(M): one frame

``Method`` is the one class for every editing method; the deformation-graph methods
(``GRAPH_METHODS``) also give their intermediate results (``node_classes``,
``relative_extent``, ``selected_scale``, ...), which raise AttributeError for the others.

Arrays: vertices float64 (#V, 3), faces int32 (#F, 3) (any integer dtype is accepted),
vertex id lists 1-D integer arrays, transforms 4x4 with last row 0 0 0 1 (or 3x4).
``Method.drag`` and ``Method.drag_along`` return a new array that later drags leave as it
is (as libigl's functions do); ``Method.deformed_vertices`` is a read-only view of the
method's own storage that follows the current frame.

Errors carry the C++ message: TypeError for a wrong type or dtype (or an unknown option
keyword, with the nearest one), ValueError for a wrong shape or value (arrays, options, handle
layouts, method names), OSError for a file that cannot be read or written, RuntimeError for a
failed solve or a drag before set_handles.
"""

import inspect as _inspect

from ._msdeform import (
    COMMIT,
    GRAPH_METHODS,
    NODE_CLASSES,
    RESULT_COLUMNS,
    CeresOptions,
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


def deform(V, F, status, M, frames=1, method=None, options=None, **kwargs):
    """Deforms a mesh in one call and returns the deformed vertices as a new (#V, 3) array.

    The one-off form of ``Method(V, F, method, options, **kwargs)``, ``set_handles(status)``
    and ``drag_along(M, frames=frames)``: ``status`` is a per-vertex array (0 fixed, 1 free,
    2 handle) or a .sel path, ``M`` the handle's final 4x4 transform, reached in ``frames``
    equal steps about the handle's rest centroid (as ``msdeform --sel --def --frames``).
    Use a Method to drag the same layout more than once.
    """
    editor = Method(V, F, method, options, **kwargs)
    editor.set_handles(status)
    return editor.drag_along(M, frames=frames)


def __getattr__(name):
    # The graph methods had a class of their own before Method took every method.
    if name == "Deformer":
        raise AttributeError(
            "msdeform.Deformer is msdeform.Method now: Method(V, F, method='multiscale', "
            "options=None, **options) takes every name in msdeform.METHODS")
    raise AttributeError(f"module 'msdeform' has no attribute {name!r}")
