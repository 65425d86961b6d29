"""Textures reach the simulators: a cube whose faces carry a four-colour image (an OBJ with `map_Kd`)
goes through `uniphys run`; MuJoCo renders our MJCF offscreen as it renders the source mesh with
the source image, PyBullet loads the texture with the URDF's visual, yourdfpy reads the image the
URDF names, and usd-core finds the stage valid (shading and subsets included) with the faces bound
to a preview surface that reads the image."""

import os
import struct
import subprocess
import zlib
from pathlib import Path

import numpy as np
import pytest

from conftest import uniphys_bin

# Quadrant colours of the source image (top-left, top-right, bottom-left, bottom-right).
QUADRANTS = {(0, 0): (230, 30, 30), (1, 0): (30, 200, 30), (0, 1): (30, 30, 230), (1, 1): (230, 200, 30)}
SIZE_PX = 64
HALF_M = 0.1


def write_png(path: Path, width: int, height: int, pixel) -> None:
    """An 8-bit RGB PNG (no image library needed)."""
    rows = b"".join(b"\x00" + bytes(c for x in range(width) for c in pixel(x, y)) for y in range(height))

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def write_cube(folder: Path) -> Path:
    """A cube standing on z = 0, centred in x and y, Z up, every face mapped onto the whole image."""
    write_png(folder / "quad.png", SIZE_PX, SIZE_PX, lambda x, y: QUADRANTS[(2 * x // SIZE_PX, 2 * y // SIZE_PX)])
    s = HALF_M
    corners = [(-s, -s, 0), (s, -s, 0), (s, s, 0), (-s, s, 0), (-s, -s, 2 * s), (s, -s, 2 * s), (s, s, 2 * s), (-s, s, 2 * s)]
    quads = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    lines = ["mtllib cube.mtl", "usemtl label"]
    lines += [f"v {x} {y} {z}" for x, y, z in corners]
    lines += ["vt 0 0", "vt 1 0", "vt 1 1", "vt 0 1"]
    for q in quads:
        a, b, c, d = (i + 1 for i in q)
        lines += [f"f {a}/1 {b}/2 {c}/3", f"f {a}/1 {c}/3 {d}/4"]
    (folder / "cube.obj").write_text("\n".join(lines) + "\n")
    (folder / "cube.mtl").write_text("newmtl label\nKd 1 1 1\nmap_Kd quad.png\n")
    return folder / "cube.obj"


@pytest.fixture(scope="module")
def cube(tmp_path_factory):
    folder = tmp_path_factory.mktemp("textured_cube")
    source = write_cube(folder)
    out = folder / "out"
    run = subprocess.run([uniphys_bin(), "run", "--up", "z", "--out", str(out), str(source)],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    return folder, out


def render(model) -> np.ndarray:
    """The visual geoms seen head-on from one side, 96 x 96 pixels, float RGB."""
    import mujoco

    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    camera = mujoco.MjvCamera()
    camera.lookat[:] = [0.0, 0.0, HALF_M]
    camera.distance = 5.5 * HALF_M
    camera.azimuth = 90.0
    camera.elevation = 0.0
    option = mujoco.MjvOption()
    option.geomgroup[:] = 0
    option.geomgroup[2] = 1
    with mujoco.Renderer(model, 96, 96) as renderer:
        renderer.update_scene(data, camera=camera, scene_option=option)
        return renderer.render().astype(float)


def quadrant_chromaticities(image: np.ndarray) -> list:
    """Mean colour of the middle of each quarter of the face in view, as shares of its sum (shading
    differs between meshes with shared and split vertices; the hue does not)."""
    means = [image[y:y + 16, x:x + 16].reshape(-1, 3).mean(0) for y, x in [(28, 28), (28, 52), (52, 28), (52, 52)]]
    return [m / max(m.sum(), 1e-9) for m in means]


def test_mujoco_draws_the_source_image_on_the_exported_part(cube):
    import mujoco

    folder, out = cube
    reference = mujoco.MjModel.from_xml_string(
        f'<mujoco><compiler meshdir="{folder}" texturedir="{folder}"/><asset>'
        '<texture name="t" type="2d" file="quad.png"/><material name="m" texture="t"/>'
        '<mesh name="c" file="cube.obj"/></asset><worldbody>'
        '<geom type="mesh" mesh="c" material="m" group="2" contype="0" conaffinity="0"/>'
        '</worldbody></mujoco>')
    expected = quadrant_chromaticities(render(reference))
    # The reference shows four different colours, each clearly coloured (not grey).
    assert all(np.abs(c - 1 / 3).max() > 0.15 for c in expected), expected
    ours = quadrant_chromaticities(render(mujoco.MjModel.from_xml_path(str(out / "model.xml"))))
    for quadrant, (want, got) in enumerate(zip(expected, ours)):
        assert np.abs(want - got).max() < 0.06, (quadrant, want, got)


def test_the_urdf_visual_carries_the_texture_to_pybullet_and_yourdfpy(cube):
    import pybullet
    import yourdfpy

    folder, out = cube
    urdf = out / "model.urdf"
    client = pybullet.connect(pybullet.DIRECT)
    try:
        body = pybullet.loadURDF(str(urdf), physicsClientId=client)
        shapes = pybullet.getVisualShapeData(body, flags=pybullet.VISUAL_SHAPE_DATA_TEXTURE_UNIQUE_IDS,
                                             physicsClientId=client)
        assert shapes and all(shape[-1] >= 0 for shape in shapes), shapes
    finally:
        pybullet.disconnect(client)
    model = yourdfpy.URDF.load(str(urdf))
    visuals = list(model.scene.geometry.values())
    assert len(visuals) == 1
    image = np.asarray(visuals[0].visual.material.image.convert("RGB"))
    quarter = SIZE_PX // 4
    for (qx, qy), colour in QUADRANTS.items():
        y, x = (2 * qy + 1) * quarter, (2 * qx + 1) * quarter
        assert tuple(image[y, x]) == colour, ((qx, qy), image[y, x])


def test_the_usd_stage_binds_the_faces_to_a_surface_reading_the_image(cube):
    from PIL import Image
    from pxr import Usd, UsdGeom, UsdShade, UsdValidation

    _, out = cube
    stage = Usd.Stage.Open(str(out / "model.usda"))
    registry = UsdValidation.ValidationRegistry()
    prefixes = ("usdShadeValidators:", "usdGeomValidators:", "usdPhysicsValidators:", "usdValidation:")
    names = [v.GetMetadata().name for v in registry.GetOrLoadAllValidators()]
    chosen = [registry.GetOrLoadValidatorByName(n) for n in names if n.startswith(prefixes)]
    assert any(n.startswith("usdShadeValidators:") for n in names)
    errors = [f"{e.GetName()}: {e.GetMessage()}" for e in UsdValidation.ValidationContext(chosen).Validate(stage)]
    assert errors == []
    visual = next(p for p in stage.Traverse() if p.GetName() == "visual")
    mesh = UsdGeom.Mesh(visual)
    st = UsdGeom.PrimvarsAPI(visual).GetPrimvar("st")
    assert len(st.Get()) == len(mesh.GetPointsAttr().Get())
    subsets = UsdGeom.Subset.GetAllGeomSubsets(UsdGeom.Imageable(visual))
    assert len(subsets) == 1
    assert len(subsets[0].GetIndicesAttr().Get()) == len(mesh.GetFaceVertexCountsAttr().Get())
    material, _ = UsdShade.MaterialBindingAPI(subsets[0].GetPrim()).ComputeBoundMaterial()
    surface = material.ComputeSurfaceSource()[0]
    assert surface.GetIdAttr().Get() == "UsdPreviewSurface"
    texture = UsdShade.Shader(surface.GetInput("diffuseColor").GetConnectedSources()[0][0].source.GetPrim())
    assert texture.GetIdAttr().Get() == "UsdUVTexture"
    image = np.asarray(Image.open(texture.GetInput("file").Get().resolvedPath).convert("RGB"))
    quarter = SIZE_PX // 4
    for (qx, qy), colour in QUADRANTS.items():
        assert tuple(image[(2 * qy + 1) * quarter, (2 * qx + 1) * quarter]) == colour


def test_a_result_exported_again_keeps_its_textures(cube, tmp_path):
    import mujoco

    _, out = cube
    again = tmp_path / "again"
    run = subprocess.run([uniphys_bin(), "export", str(out), "--format", "mjcf", "--out", str(again)],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert (again / "meshes" / "texture_0.png").read_bytes() == (out / "meshes" / "texture_0.png").read_bytes()
    first = quadrant_chromaticities(render(mujoco.MjModel.from_xml_path(str(out / "model.xml"))))
    second = quadrant_chromaticities(render(mujoco.MjModel.from_xml_path(str(again / "model.xml"))))
    for want, got in zip(first, second):
        assert np.abs(want - got).max() < 0.01, (want, got)
