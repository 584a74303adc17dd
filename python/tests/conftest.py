"""Fixtures for the gdp module's tests: the gdp CLI to compare with, and test images made here."""
import os
import pathlib
import subprocess

import numpy as np
import pytest


DATA = pathlib.Path(__file__).resolve().parents[2] / "tests" / "data"  # real images (tests/data/README.md)


@pytest.fixture(scope="session")
def cli():
    """Runs the gdp CLI (GDP_CLI, set by CTest) and returns (exit code, stderr)."""
    path = os.environ.get("GDP_CLI")
    if not path or not os.path.exists(path):
        pytest.fail("GDP_CLI must name the gdp executable (CTest sets it)")

    def run(*args):
        r = subprocess.run([path, *map(str, args)], capture_output=True, text=True, timeout=300)
        return r.returncode, r.stderr

    return run


def scene(height, width, channels=3, seed=0):
    """A smooth image with some texture: a few sinusoids plus mild noise, values in (0, 1)."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:height, 0:width].astype(np.float64)
    planes = []
    for c in range(channels):
        v = 0.5 + 0.2 * np.sin(x / (9.0 + 3 * c)) * np.cos(y / 13.0) + 0.1 * np.sin((x + 2 * y) / 31.0)
        planes.append(v + 0.03 * rng.standard_normal((height, width)))
    return np.clip(np.stack(planes, axis=-1), 0.0, 1.0)


@pytest.fixture()
def composite():
    """An 8-bit composite of three exposures of one scene (seams at columns 60 and 130) and its labels."""
    base = scene(120, 180)
    labels = np.zeros((120, 180, 3), np.uint8)
    labels[:, 60:130] = (255, 0, 0)
    labels[:, 130:] = (0, 0, 255)
    gain = np.ones((120, 180, 1))
    gain[:, 60:130] = 0.7
    gain[:, 130:] = 1.2
    image = np.clip(base * gain, 0, 1)
    return np.round(image * 255).astype(np.uint8), labels
