"""mesohex: all-hex meshes guided by meso-skeletons, from Python.

A thin layer over the C++ library (the compiled extension ``mesohex._mesohex``): the same calls the ``mesohex`` CLI
makes, keyword options named like its flags, reports as dicts with the keys of ``--report``, and errors as
exceptions (``mesohex.Error`` and its subclasses ``InvalidInput``, ``UnsupportedConfiguration``, ``IoError``,
``NumericalFailure``; ``.code`` is the CLI's exit status). See docs/python.md.
"""
from ._mesohex import (  # noqa: F401
    Error,
    HexMesh,
    InvalidInput,
    IoError,
    MeshResult,
    NumericalFailure,
    Skeleton,
    Surface,
    UnsupportedConfiguration,
    auto,
    generate,
    generator_names,
    medial,
    mesh,
    partition,
    quality,
    read_hex_mesh,
    read_skeleton,
    read_surface,
    scaled_jacobians,
    thicken,
    write_hex_mesh,
    write_skeleton,
    write_surface,
)
from .meshio_helper import from_meshio, to_meshio  # noqa: F401
