"""gdp: gradient-domain processing of large planar and spherical images.

Seamless stitching, sharpening and smoothing, seamless cloning and tone mapping with the
streaming multigrid solver of Kazhdan, Surendran and Hoppe (ACM TOG 2010), on numpy arrays
(stitch, sharpen, smooth, clone, tonemap, reconstruct, to_pq, from_pq) or streamed from file to
file with the gdp command line tool's options (the same names with _file). Errors raise
gdp.InputError, gdp.UsageError (both ValueError) or gdp.OutputError (OSError), all gdp.Error,
carrying the messages the CLI prints. See docs/python.md in the repository.
"""

from gdp._gdp import (  # noqa: F401
    Error,
    InputError,
    OutputError,
    UsageError,
    clone,
    clone_file,
    from_pq,
    from_pq_file,
    read_image,
    reconstruct,
    reconstruct_file,
    sharpen,
    sharpen_file,
    smooth,
    smooth_file,
    stitch,
    stitch_file,
    to_pq,
    to_pq_file,
    tonemap,
    tonemap_file,
    write_image,
)

__all__ = [
    "Error", "InputError", "OutputError", "UsageError",
    "stitch", "stitch_file", "sharpen", "sharpen_file", "smooth", "smooth_file",
    "clone", "clone_file", "tonemap", "tonemap_file", "reconstruct", "reconstruct_file",
    "to_pq", "to_pq_file", "from_pq", "from_pq_file", "read_image", "write_image",
]
