"""A user's script, type-checked by mypy --strict against the package's types (test_typing.py);
never run."""

import numpy as np
import numpy.typing as npt

import metamer

r = metamer.render("scenes/spheres.json", grid="380:780:5", backend="cpu", write=["cube", "xyz"], bits=16,
                   readback="copy", strict_coverage=True)
cube = r.cube
assert cube is not None
band: npt.NDArray[np.float32] = cube[..., 3]
stats = metamer.compare(r, "out/spheres.exr", wavelengths=None)
pixels: int = r.width * r.height
total_ms: float = r.timings_ms["total"]
cube_file = metamer.load_cube("out/spheres.h5")
print(band.mean(), stats["max_abs"], pixels, total_ms, r.grid.split(":"), cube_file["grid"])
