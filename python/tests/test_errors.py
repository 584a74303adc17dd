"""Errors raise gdp's exception classes carrying the messages the gdp CLI prints."""
import numpy as np
import pytest

import gdp


def cli_message(cli, *args):
    code, err = cli(*args)
    assert code == 2, err
    assert err.startswith("gdp: ") and err.endswith("\n"), err
    return err[len("gdp: "):-1]


def test_classes():
    assert issubclass(gdp.InputError, gdp.Error) and issubclass(gdp.InputError, ValueError)
    assert issubclass(gdp.UsageError, gdp.Error) and issubclass(gdp.UsageError, ValueError)
    assert issubclass(gdp.OutputError, gdp.Error) and issubclass(gdp.OutputError, OSError)
    assert gdp.InputError.__module__ == "gdp"


def test_missing_input_has_the_cli_message(tmp_path, cli):
    missing, labels = tmp_path / "missing.png", tmp_path / "l.png"
    gdp.write_image(labels, np.zeros((8, 8), np.uint8))
    expected = cli_message(cli, "stitch", "-c", missing, "-l", labels, "-o", tmp_path / "o.png", "-q")
    with pytest.raises(gdp.InputError) as e:
        gdp.stitch_file(missing, labels, tmp_path / "o.png")
    assert str(e.value) == expected
    assert "missing.png" in expected


def test_size_mismatch_has_the_cli_message(tmp_path, cli):
    gdp.write_image(tmp_path / "c.png", np.zeros((8, 12, 3), np.uint8))
    gdp.write_image(tmp_path / "l.png", np.zeros((8, 10), np.uint8))
    args = ("stitch", "-c", tmp_path / "c.png", "-l", tmp_path / "l.png", "-o", tmp_path / "o.png", "-q")
    expected = cli_message(cli, *args)
    with pytest.raises(gdp.InputError) as e:
        gdp.stitch_file(tmp_path / "c.png", tmp_path / "l.png", tmp_path / "o.png")
    assert str(e.value) == expected
    with pytest.raises(gdp.InputError, match="^labels: label map of 10x8, but the composite is 12x8$"):
        gdp.stitch(np.zeros((8, 12, 3), np.uint8), np.zeros((8, 10), np.uint8))
    assert not (tmp_path / "o.png").exists()


def test_clone_mismatches_have_the_cli_messages(tmp_path, cli):
    t, s, m, o = (tmp_path / n for n in ("t.png", "s.png", "m.png", "o.png"))
    gdp.write_image(t, np.zeros((8, 12, 3), np.uint8))
    for source, mask, fragment in [((8, 12, 3), (8, 10), "m.png: 10x8, but the source"),
                                   ((8, 12), (8, 12), "s.png: 1 channel(s), but the target")]:
        gdp.write_image(s, np.zeros(source, np.uint8))
        gdp.write_image(m, np.zeros(mask, np.uint8))
        expected = cli_message(cli, "clone", "-t", t, "-s", s, "-m", m, "-o", o, "-q")
        assert fragment in expected
        with pytest.raises(gdp.InputError) as e:
            gdp.clone_file(t, s, m, o)
        assert str(e.value) == expected
        assert not o.exists()
    with pytest.raises(gdp.InputError, match="^the mask: 10x8, but the source is 12x8$"):
        gdp.clone(np.zeros((8, 12), np.float32), np.zeros((8, 12), np.float32), np.zeros((8, 10), np.float32))


def test_invalid_options_have_the_cli_messages(tmp_path, cli):
    gdp.write_image(tmp_path / "a.png", np.zeros((8, 8), np.uint8))
    image = np.zeros((8, 8), np.float32)
    cases = [
        (("--iters", "-1"), {"iters": -1}),
        (("--vcycles", "0"), {"vcycles": 0}),
        (("--domain", "torus"), {"domain": "torus"}),
        (("--bands", "2", "--in-core"), {"bands": 2, "in_core": True}),
        (("--scale", "-3"), {"scale": -3.0}),
        (("--scale-deg", "5"), {"scale_deg": 5.0}),
    ]
    for flags, keywords in cases:
        expected = cli_message(cli, "sharpen", tmp_path / "a.png", "-o", tmp_path / "b.png", "-q", *flags)
        with pytest.raises(gdp.UsageError) as e:
            gdp.sharpen(image, **keywords)
        assert str(e.value) == expected, flags


def test_unwritable_output_has_the_cli_message(tmp_path, cli):
    gdp.write_image(tmp_path / "a.png", np.zeros((8, 8), np.uint8))
    out = tmp_path / "no-such-dir" / "b.png"
    expected = cli_message(cli, "smooth", tmp_path / "a.png", "-o", out, "-q")
    with pytest.raises(gdp.OutputError) as e:
        gdp.smooth_file(tmp_path / "a.png", out)
    assert str(e.value) == expected


def test_wrong_argument_types():
    with pytest.raises(TypeError, match="stitch_file reads files"):
        gdp.stitch("c.png", "l.png")
    with pytest.raises(TypeError, match="file name"):
        gdp.smooth_file(np.zeros((4, 4)), "out.png")
    with pytest.raises(TypeError, match="complex"):
        gdp.smooth(np.zeros((4, 4), np.complex64))
    with pytest.raises(gdp.UsageError, match="dimension"):
        gdp.smooth(np.zeros(4))
    with pytest.raises(TypeError, match="iters='3': wrong type"):
        gdp.smooth(np.zeros((4, 4)), iters="3")
    with pytest.raises(TypeError, match="unexpected keyword argument 'itres'"):
        gdp.smooth(np.zeros((4, 4)), itres=2)
