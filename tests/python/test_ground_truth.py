"""The ground truth beside the cube (issue 49, item 1; docs/io.md, "Ground truth"): the loader a learner
pastes from docs/io.md runs on `metamer render --write` files, read by h5py and OpenEXR's own binding;
the Python module's keywords keep the same maps as arrays, equal to the files; pickling keeps them.
Run by CTest (tests/CMakeLists.txt, test `python_ground_truth`)."""

from __future__ import annotations

import json
import os
import pickle
import re
import subprocess
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
BINARY = os.environ.get("METAMER_BINARY", str(REPO / "build" / "metamer"))
MAPS = ["cube", "reflectance", "illumination", "ids", "depth", "normal"]
SIZE = ["--set", "camera.width=64", "--set", "camera.height=48"]


def docs_loader() -> str:
    """The block docs/io.md marks as the ground truth's loader."""
    text = (REPO / "docs" / "io.md").read_text()
    m = re.search(r"<!-- ground-truth loader[^>]*-->\s*```python\n(.*?)```", text, re.S)
    assert m, "docs/io.md has no ground-truth loader block"
    return m.group(1)


def render_files(tmp_path: Path, scene: str = "spheres.json") -> Path:
    p = subprocess.run([BINARY, "render", str(REPO / "scenes" / scene), "--out", str(tmp_path), *SIZE,
                        "--write", ",".join(MAPS), "--format", "exr,hdf5"], capture_output=True, text=True)
    assert p.returncode == 0, p.stdout + p.stderr
    return tmp_path / Path(scene).stem


def test_the_docs_loader_reads_every_map_and_radiance_is_reflectance_times_illumination(tmp_path):
    stem = render_files(tmp_path, "colorchecker.json")  # matte: the identity to float rounding
    code = docs_loader().replace('STEM = "out/scene"', f'STEM = "{stem}"')
    v: dict = {}
    exec(compile(code, "docs/io.md", "exec"), v)  # noqa: S102 — the documented snippet, as a learner runs it
    radiance, reflectance, illumination = v["radiance"], v["reflectance"], v["illumination"]
    assert radiance.shape == reflectance.shape == illumination.shape == (48, 64, radiance.shape[2])
    assert v["wavelengths"].shape == (radiance.shape[2],)
    clean = v["clean"]
    assert clean.sum() > 0.2 * clean.size
    product = reflectance * illumination
    np.testing.assert_allclose(radiance[clean], product[clean], rtol=1e-5, atol=1e-30)
    mask = v["mask"]
    assert np.all(reflectance[(mask & 1) != 0] == 0) and np.all(v["depth"][(mask & 1) != 0] == 0)
    # ids through the legend; depth positive and normals unit length on surfaces; they face the camera.
    objects, materials, legend = v["objects"], v["materials"], v["legend"]
    seen = objects >= 0
    assert set(np.unique(objects[seen])) <= {o["id"] for o in legend["objects"]}
    by_id = {o["id"]: o["material"] for o in legend["objects"]}
    assert all(materials[i] == by_id[objects[i]] for i in zip(*np.nonzero(seen)))
    assert np.all(v["depth"][seen] > 0)
    n = v["normal"][seen]
    np.testing.assert_allclose(np.linalg.norm(n, axis=-1), 1.0, atol=1e-5)
    assert np.all(n[:, 2] > -1e-6)


def test_the_module_keeps_the_same_maps_as_the_files_and_pickles_them(tmp_path):
    import metamer
    r = metamer.render(REPO / "scenes" / "spheres.json", overrides=["camera.width=64", "camera.height=48"],
                       write=MAPS)
    stem = render_files(tmp_path)
    import h5py
    import OpenEXR
    with h5py.File(f"{stem}.reflectance.h5") as f:
        np.testing.assert_array_equal(r.reflectance, f["cube"][...])
        assert f["cube"].attrs["quantity"] == b"reflectance" or f["cube"].attrs["quantity"] == "reflectance"
    with h5py.File(f"{stem}.illumination.h5") as f:
        np.testing.assert_array_equal(r.illumination, f["cube"][...])
    with OpenEXR.File(f"{stem}.ids.exr") as f:
        np.testing.assert_array_equal(r.object_ids, f.channels()["object"].pixels.astype(np.int32))
        np.testing.assert_array_equal(r.material_ids, f.channels()["material"].pixels.astype(np.int32))
    with OpenEXR.File(f"{stem}.depth.exr") as f:
        np.testing.assert_array_equal(r.depth, f.channels()["Z"].pixels)
    assert r.object_ids.dtype == np.int32 and r.truth_mask.dtype == np.uint8
    assert r.normal.shape == (48, 64, 3)
    # The glossy spheres: clean pixels keep the lobe's remainder under 1 % of their radiance, and
    # the rest are masked (bit 4); the background too (bit 1).
    clean = r.truth_mask == 0
    share = np.abs(r.cube - r.reflectance * r.illumination).sum(-1)[clean] / r.cube.sum(-1)[clean]
    assert share.max() <= 0.0101
    assert (r.truth_mask & 4).any() and (r.truth_mask & 1).any()
    assert r.ids_legend == json.loads(Path(f"{stem}.ids.json").read_text())
    assert r.timings_ms["ground_truth"] > 0
    # Pickled (a worker's result), every map comes back.
    back = pickle.loads(pickle.dumps(r))
    for name in ("reflectance", "illumination", "object_ids", "material_ids", "depth", "normal", "truth_mask"):
        np.testing.assert_array_equal(getattr(back, name), getattr(r, name), err_msg=name)
    assert back.ids_legend == r.ids_legend
    # save() writes the files the CLI writes, the maps among them.
    saved = {Path(p).name for p in r.save(tmp_path / "saved")}
    assert {"spheres.reflectance.exr", "spheres.illumination.exr", "spheres.ids.exr", "spheres.ids.json", "spheres.depth.exr",
            "spheres.normal.exr", "spheres.mask.png"} <= saved, saved


def test_a_render_without_the_maps_has_none():
    import metamer
    r = metamer.render(REPO / "scenes" / "spheres.json", overrides=["camera.width=16", "camera.height=12"])
    assert r.reflectance is None and r.object_ids is None and r.truth_mask is None and r.ids_legend is None


def test_the_arad_layout_carries_the_spectral_maps_beside_the_cube(tmp_path):
    import mat73
    p = subprocess.run([BINARY, "render", str(REPO / "scenes" / "colorchecker.json"), "--out", str(tmp_path), *SIZE,
                        "--grid", "400:700:10", "--format", "arad", "--write", "cube,reflectance,illumination"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stdout + p.stderr

    def load(name):
        m = mat73.loadmat(str(tmp_path / name))
        assert m["cube"].shape == (48, 64, 31)
        return m["cube"] * m["norm_factor"]

    radiance, reflectance, illumination = (load(f"colorchecker{s}.mat") for s in ("", ".reflectance", ".illumination"))
    from PIL import Image
    clean = np.asarray(Image.open(tmp_path / "colorchecker.mask.png")) == 0
    assert clean.sum() > 0.2 * clean.size
    np.testing.assert_allclose(radiance[clean], (reflectance * illumination)[clean], rtol=1e-5)
    assert 0 < reflectance.max() <= 1
