"""gdp.stitch on arrays equals the gdp CLI's output bit for bit, and removes the seams it should."""
import numpy as np

import gdp


def test_stitch_array_equals_cli_bit_for_bit(tmp_path, cli, composite):
    image, labels = composite
    gdp.write_image(tmp_path / "c.png", image)
    gdp.write_image(tmp_path / "l.png", labels)
    code, err = cli("stitch", "--scratch", "float", "-c", tmp_path / "c.png", "-l", tmp_path / "l.png", "-o", tmp_path / "cli.tif",
                    "--depth", "float", "-q")
    assert code == 0, err
    expected = gdp.read_image(tmp_path / "cli.tif")
    result = gdp.stitch(image, labels)
    assert result.dtype == np.float32 and result.shape == image.shape
    assert np.array_equal(result, expected)
    # The file form streams the same files through the same solver.
    summary = gdp.stitch_file(tmp_path / "c.png", tmp_path / "l.png", tmp_path / "py.tif", depth="float")
    assert np.array_equal(gdp.read_image(tmp_path / "py.tif"), expected)
    assert summary["width"] == 180 and summary["height"] == 120 and summary["channels"] == 3


def test_stitch_file_to_8_bit_keeps_the_cli_sweeps(tmp_path, cli, composite):
    # Into an 8-bit file the CLI's stitch keeps the solver's 3/3 sweeps (only `gdp blend` takes 2/3
    # there, docs/blend.md "The solver's sweeps"; the module has no blend), and so does the module.
    image, labels = composite
    gdp.write_image(tmp_path / "c.png", image)
    gdp.write_image(tmp_path / "l.png", labels)
    files = ["-c", tmp_path / "c.png", "-l", tmp_path / "l.png"]
    for name, iters in (("cli.png", []), ("two.png", ["--iters", "2/3"])):
        code, err = cli("stitch", "--scratch", "float", *files, "-o", tmp_path / name, "-q", *iters)
        assert code == 0, err
    gdp.stitch_file(tmp_path / "c.png", tmp_path / "l.png", tmp_path / "py.png")
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    # The sweeps show in these 8 bits, so the equality above is the sweeps' too.
    assert (tmp_path / "two.png").read_bytes() != (tmp_path / "cli.png").read_bytes()
    assert not hasattr(gdp, "blend")


def test_stitch_options_match_cli(tmp_path, cli, composite):
    image, labels = composite
    gdp.write_image(tmp_path / "c.png", image)
    gdp.write_image(tmp_path / "l.png", labels)
    flags = ["--unknown", "black", "--deramp", "--vcycles", "2", "--iters", "2", "--in-core", "--double"]
    code, err = cli("stitch", "--scratch", "float", "-c", tmp_path / "c.png", "-l", tmp_path / "l.png", "-o", tmp_path / "cli.tif",
                    "--depth", "float", "-q", *flags)
    assert code == 0, err
    result = gdp.stitch(image, labels, unknown="black", deramp=True, vcycles=2, iters=2, in_core=True, double=True)
    assert np.array_equal(result, gdp.read_image(tmp_path / "cli.tif"))


def test_stitch_keeps_gradients_inside_labels_and_removes_seams(composite):
    image, labels = composite
    c = image.astype(np.float32) / 255
    out = gdp.stitch(image, labels, vcycles=3)
    dx_in, dx_out = np.diff(c, axis=1), np.diff(out, axis=1)
    inside = np.ones(dx_in.shape[1], bool)
    inside[[59, 129]] = False  # the edges across the seams
    # Away from the seams the gradients are the composite's ...
    assert np.abs(dx_out[:, inside] - dx_in[:, inside]).mean() < 2e-3
    # ... and across them the jump of the exposures is gone (seam 59|60: gain 1 -> 0.7).
    assert np.abs(dx_in[:, 59]).mean() > 0.1
    assert np.abs(dx_out[:, 59]).mean() < 0.03


def test_two_dimensional_arrays_stay_two_dimensional(composite):
    image, labels = composite
    out = gdp.stitch(image[:, :, 0], labels[:, :, 2])
    assert out.shape == image.shape[:2]
