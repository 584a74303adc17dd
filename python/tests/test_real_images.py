"""Real photographs (tests/data): stitch and clone on arrays equal the gdp CLI's output bit for bit."""
import numpy as np

import gdp
from conftest import DATA


def as_uint8(image):
    return np.round(image * 255).astype(np.uint8)  # exact: 8-bit files are read as k/255


def test_stitch_of_a_photo_equals_cli(tmp_path, cli):
    photo = as_uint8(gdp.read_image(DATA / "opencv" / "weir_1_crop.jpg"))[:240, :320]
    labels = np.zeros((240, 320), np.uint8)
    labels[:, 110:] = 1
    labels[150:, 220:] = 2
    gain = np.choose(labels, [1.0, 0.75, 1.15])[:, :, None]  # three exposures of one scene
    composite = np.clip(np.round(photo * gain), 0, 255).astype(np.uint8)
    gdp.write_image(tmp_path / "c.png", composite)
    gdp.write_image(tmp_path / "l.png", labels)
    code, err = cli("stitch", "--scratch", "float", "-c", tmp_path / "c.png", "-l", tmp_path / "l.png", "-o", tmp_path / "cli.tif",
                    "--depth", "float", "--vcycles", "2", "-q")
    assert code == 0, err
    assert np.array_equal(gdp.stitch(composite, labels, vcycles=2), gdp.read_image(tmp_path / "cli.tif"))


def test_clone_of_photos_equals_cli(tmp_path, cli):
    files = [DATA / "dip2018" / n for n in ("test2_target_crop.png", "test2_src.png", "test2_mask.png")]
    code, err = cli("clone", "--scratch", "float", "-t", files[0], "-s", files[1], "-m", files[2], "--offset", "4,14", "-o",
                    tmp_path / "cli.tif", "--depth", "float", "-q")
    assert code == 0, err
    target, source, mask = (gdp.read_image(f) for f in files)
    result = gdp.clone(target, source, mask, offset=(4, 14))
    assert np.array_equal(result, gdp.read_image(tmp_path / "cli.tif"))
    gdp.clone_file(*files, tmp_path / "py.tif", offset=(4, 14), depth="float")
    assert np.array_equal(gdp.read_image(tmp_path / "py.tif"), result)
