"""sharpen/smooth identities, clone, tonemap, reconstruct and the sphere resampling on arrays."""
import numpy as np
import pytest

import gdp
from conftest import scene


def test_beta_one_returns_the_image():
    image = scene(96, 128, 3).astype(np.float32)
    for fn in (gdp.sharpen, gdp.smooth):
        out = fn(image, beta=1.0, tolerance=1e-7)
        assert np.abs(out - image).max() < 1e-4


def test_sharpen_is_affine_and_keeps_constants():
    image = scene(80, 100, 1)[:, :, 0]
    a = gdp.sharpen(image, beta=2.5, scale=8, double=True, vcycles=4)
    b = gdp.sharpen(0.5 * image + 0.25, beta=2.5, scale=8, double=True, vcycles=4)
    assert np.abs(b - (0.5 * a + 0.25)).max() < 1e-5
    flat = gdp.smooth(np.full((40, 60), 0.3, np.float32), beta=0.2)
    assert np.abs(flat - 0.3).max() < 1e-6


def test_smooth_reduces_detail_and_sharpen_adds_it():
    image = scene(128, 128, 1)[:, :, 0]
    detail = np.abs(np.diff(image, axis=1)).mean()
    assert np.abs(np.diff(gdp.smooth(image, beta=0.3), axis=1)).mean() < 0.6 * detail
    assert np.abs(np.diff(gdp.sharpen(image, beta=2.0), axis=1)).mean() > 1.5 * detail


def test_sharpen_array_equals_cli(tmp_path, cli):
    image = (scene(90, 110, 3) * 65535).astype(np.uint16)
    gdp.write_image(tmp_path / "in.tif", image)
    code, err = cli("sharpen", "--scratch", "float", tmp_path / "in.tif", "-o", tmp_path / "cli.tif", "--depth", "float", "--beta", "1.7",
                    "--scale", "12", "-q")
    assert code == 0, err
    assert np.array_equal(gdp.sharpen(image, beta=1.7, scale=12), gdp.read_image(tmp_path / "cli.tif"))


def test_clone_keeps_the_target_outside_the_mask():
    target = scene(80, 100, 3, seed=1).astype(np.float32)
    source = scene(40, 50, 3, seed=2).astype(np.float32) * 0.5
    mask = np.zeros((40, 50), np.uint8)
    mask[10:30, 10:40] = 255
    out = gdp.clone(target, source, mask, offset=(20, 15))
    outside = np.ones((80, 100), bool)
    outside[15 + 10:15 + 30, 20 + 10:20 + 40] = False
    assert np.abs(out[outside] - target[outside]).max() < 1e-4
    # Inside, the source's gradients rather than the target's.
    d_out = np.diff(out[27:43, 32:58], axis=1)
    d_src = np.diff(source[12:28, 12:38], axis=1)
    d_tgt = np.diff(target[27:43, 32:58], axis=1)
    assert np.abs(d_out - d_src).mean() < 0.2 * np.abs(d_out - d_tgt).mean()


def test_tonemap_gives_display_values():
    hdr = np.exp(6 * scene(96, 128, 3) - 3).astype(np.float32)
    out = gdp.tonemap(hdr)
    assert out.shape == hdr.shape and out.min() >= 0.0 and out.max() <= 1.0


def test_reconstruct_rebuilds_the_image():
    image = scene(100, 120, 2)
    out, rms, worst = gdp.reconstruct(image, vcycles=3)
    assert out.shape == image.shape
    assert rms < 1e-3 and worst < 1e-2
    assert abs(np.sqrt(np.mean((out - image) ** 2)) - rms) < 1e-4


def test_sphere_round_trip_and_shapes():
    y, x = np.mgrid[0:64, 0:128]
    lat, lon = np.pi / 2 - (y + 0.5) * np.pi / 64, (x + 0.5) * 2 * np.pi / 128 - np.pi
    equirect = (0.5 + 0.3 * np.cos(lat) * np.cos(lon) + 0.2 * np.sin(lat)).astype(np.float32)  # smooth on the sphere
    pq = gdp.to_pq(equirect, height=48)
    assert pq.shape == (48, 192)
    back = gdp.from_pq(pq, width=128)
    assert back.shape == (64, 128)
    assert np.abs(back - equirect).max() < 0.02
    with pytest.raises(gdp.InputError, match="already a PQ image"):
        gdp.to_pq(pq)


def test_sphere_solve_on_equirect_arrays():
    y, x = np.mgrid[0:64, 0:128]
    image = (0.5 + 0.2 * np.sin(x * 2 * np.pi / 128) * np.sin(y * np.pi / 64)).astype(np.float32)
    out = gdp.smooth(image, beta=1.0, sphere=True, tolerance=1e-6)
    assert out.shape == image.shape
    assert np.abs(out - image).max() < 0.02  # resampled to PQ and back


def test_sphere_arrays_equal_cli(tmp_path, cli):
    image = (scene(64, 128, 3) * 255).astype(np.uint8)  # equirectangular 2:1
    gdp.write_image(tmp_path / "in.png", image)
    code, err = cli("smooth", "--scratch", "float", tmp_path / "in.png", "-o", tmp_path / "cli.tif", "--sphere", "--depth", "float", "-q")
    assert code == 0, err
    assert np.array_equal(gdp.smooth(image, sphere=True), gdp.read_image(tmp_path / "cli.tif"))
    code, err = cli("sphere", "to-pq", tmp_path / "in.png", "-o", tmp_path / "pq.tif", "--depth", "float",
                    "--height", "40", "--map", "octahedral")
    assert code == 0, err
    expected = gdp.read_image(tmp_path / "pq.tif")
    assert np.array_equal(gdp.to_pq(image, height=40, map="octahedral"), expected)
    gdp.to_pq_file(tmp_path / "in.png", tmp_path / "py.tif", height=40, map="octahedral", depth="float")
    assert np.array_equal(gdp.read_image(tmp_path / "py.tif"), expected)


def test_everything_public_has_a_docstring():
    assert len(gdp.__doc__) > 200
    for name in gdp.__all__:
        doc = getattr(gdp, name).__doc__
        assert doc and len(doc) > 50, name
        if callable(getattr(gdp, name)) and not isinstance(getattr(gdp, name), type):
            assert doc.startswith(name + "("), name  # its own signature line
