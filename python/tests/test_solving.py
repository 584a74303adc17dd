"""The GIL is released while gdp solves, progress is reported, and callbacks can stop a solve."""
import os
import signal
import threading
import time

import numpy as np
import pytest

import gdp
from conftest import scene


def test_python_thread_runs_while_gdp_solves():
    image = scene(768, 768, 3).astype(np.float32)
    labels = np.zeros((768, 768), np.uint8)
    labels[:, 384:] = 1
    count = [0]
    stop = threading.Event()

    def spin():
        while not stop.is_set():
            count[0] += 1

    worker = threading.Thread(target=spin)
    worker.start()
    try:
        stats = {}
        before = count[0]
        gdp.stitch(image, labels, vcycles=3, stats=stats)
        during = count[0] - before
    finally:
        stop.set()
        worker.join()
    # Holding the GIL for the whole solve would leave the loop at most one switch interval (5 ms).
    assert during > 100000, (during, stats["seconds_solve"])


def test_progress_fractions_increase_to_one():
    image = scene(300, 200, 2)
    for keywords in ({}, {"in_core": True}, {"bands": 2}, {"vcycles": 3}):
        fractions = []
        gdp.smooth(image, progress=fractions.append, **keywords)
        assert fractions, keywords
        assert all(b >= a for a, b in zip(fractions, fractions[1:])), (keywords, fractions)
        assert 0.0 <= fractions[0] and fractions[-1] == 1.0, (keywords, fractions)


def test_exception_in_progress_stops_the_solve(tmp_path):
    class Stop(Exception):
        pass

    def stop(fraction):
        raise Stop(fraction)

    image = scene(300, 200, 1)
    with pytest.raises(Stop):
        gdp.sharpen(image, progress=stop)
    gdp.write_image(tmp_path / "in.png", (image * 255).astype(np.uint8))
    with pytest.raises(Stop):
        gdp.sharpen_file(tmp_path / "in.png", tmp_path / "out.png", progress=stop)
    assert not (tmp_path / "out.png").exists()  # no partial output


def test_log_and_stats():
    lines, stats = [], {}
    gdp.reconstruct(scene(64, 64, 1), log=lines.append, stats=stats, vcycles=2)
    assert lines and all(isinstance(line, str) for line in lines)
    assert stats["vcycles"] == 2 and len(stats["relative_residuals"]) == 3
    assert stats["relative_residuals"][-1] < stats["relative_residuals"][0]


def test_residuals_only_when_asked_for():
    image, plain, asked = scene(96, 64, 3), {}, {}
    a = gdp.sharpen(image, vcycles=2, stats=plain)
    b = gdp.sharpen(image, vcycles=2, stats=asked, residuals=True)
    assert plain["vcycles"] == 2 and plain["relative_residuals"] is None
    assert len(asked["relative_residuals"]) == 3 and asked["relative_residuals"][-1] < asked["relative_residuals"][0]
    assert np.array_equal(a, b)  # measuring reads, never changes the result


def test_ctrl_c_stops_a_solve():
    image = scene(256, 256, 1).astype(np.float32)
    stats = {}
    gdp.sharpen(image, in_core=True, vcycles=4, stats=stats)
    one_cycle = stats["seconds_solve"] / 4
    cycles = max(40, int(4.0 / max(one_cycle, 1e-3)))  # a solve of several seconds
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    started = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            gdp.sharpen(image, in_core=True, vcycles=cycles, threads=1)
    finally:
        timer.cancel()
    assert time.monotonic() - started < 0.5 * cycles * one_cycle


def test_scratch_memory_budget_changes_no_bit():
    image = scene(96, 64, 3)
    files = gdp.sharpen(image, vcycles=2, memory=0)  # every scratch store a file
    held = gdp.sharpen(image, vcycles=2, memory=1 << 30)  # a named budget: every store in memory
    assert np.array_equal(files, held)
    with pytest.raises(TypeError):
        gdp.sharpen(image, memory="lots")
