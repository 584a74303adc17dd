#!/usr/bin/env python3
"""Remakes the stitching sample weir_composite.png and weir_labels.png from a real photo.

The photo (weir_1.jpg, see LICENSE-weir.txt) is cut to 3:2 and shrunk to 640x426, then split into
seven regions with wavy and polygonal boundaries. Each region gets its own exposure change
(gain and offset), so the seams between regions are plainly visible in weir_composite.png.
weir_labels.png paints every region in one flat colour (never white, which means "unknown"),
computed from the same region function, so labels and regions match pixel for pixel.

Needs only python3 and oiiotool (Debian package openimageio-tools).

Usage: make_sample.py [SOURCE_JPG [OUTPUT_DIR]]
"""

import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_SOURCE = os.path.join(HERE, "..", "..", "..", "shared", "data", "panorama",
                              "opencv-stitching-tutorial", "weir_1.jpg")
WIDTH, HEIGHT = 640, 426
CUT = "1125x749+104+0"  # the centre 3:2 part of the 1333x750 original

# Per region: (gain, offset) applied to 0..1 values, and the flat label colour.
REGIONS = [
    ((1.00, 0.00), (230, 25, 75)),    # top left: unchanged
    ((0.75, -0.05), (60, 180, 75)),   # bottom left: darker
    ((0.80, -0.05), (255, 225, 25)),  # top middle (bright wall): darker
    ((1.30, 0.05), (0, 130, 200)),    # bottom middle (water): brighter
    ((1.20, 0.08), (245, 130, 48)),   # right: brighter
    ((0.75, -0.08), (145, 30, 180)),  # polygon (walkway, steps): darker
    ((0.85, -0.06), (70, 240, 240)),  # ellipse (weir): darker than its surroundings
]

# A quadrilateral on the right (the walkway and the steps), region 5.
POLYGON = [(470, 20), (630, 60), (610, 250), (455, 205)]


def inside_polygon(x, y, polygon):
    """Even-odd rule point-in-polygon test."""
    inside = False
    n = len(polygon)
    for i in range(n):
        x0, y0 = polygon[i]
        x1, y1 = polygon[(i + 1) % n]
        if (y0 > y) != (y1 > y):
            if x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
                inside = not inside
    return inside


def region_of(x, y):
    """Region index of pixel (x, y), taking the pixel centre."""
    px, py = x + 0.5, y + 0.5
    if inside_polygon(px, py, POLYGON):
        return 5
    # A round patch over the weir, region 6.
    if (px - 330) ** 2 / 70.0 ** 2 + (py - 330) ** 2 / 45.0 ** 2 < 1.0:
        return 6
    left = 0.34 * WIDTH + 22.0 * math.sin(2.0 * math.pi * py / 150.0)
    right = 0.66 * WIDTH + 18.0 * math.sin(2.0 * math.pi * py / 110.0 + 1.0)
    middle = 0.52 * HEIGHT + 20.0 * math.sin(2.0 * math.pi * px / 170.0)
    if px < left:
        return 0 if py < middle + 30.0 else 1
    if px < right:
        return 2 if py < middle else 3
    return 4


def read_ppm(path):
    """Reads a binary 8-bit PPM (P6) as (width, height, bytes)."""
    with open(path, "rb") as f:
        data = f.read()
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos) + 1
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    if fields[0] != b"P6" or int(fields[3]) != 255:
        raise SystemExit(f"{path}: not an 8-bit binary PPM")
    width, height = int(fields[1]), int(fields[2])
    pixels = data[pos + 1:pos + 1 + width * height * 3]
    if len(pixels) != width * height * 3:
        raise SystemExit(f"{path}: truncated PPM")
    return width, height, pixels


def write_ppm(path, width, height, pixels):
    with open(path, "wb") as f:
        f.write(b"P6\n%d %d\n255\n" % (width, height))
        f.write(bytes(pixels))


def oiiotool(*args):
    subprocess.run(["oiiotool", *args], check=True)


def main():
    source = sys.argv[1] if len(sys.argv) > 1 else DEFAULT_SOURCE
    if not os.path.isfile(source):
        print(f"make_sample.py: missing {os.path.normpath(source)} (the shared data folder beside the "
              "repository; give the photo's path as the first argument)", file=sys.stderr)
        sys.exit(2)
    out_dir = sys.argv[2] if len(sys.argv) > 2 else HERE
    with tempfile.TemporaryDirectory() as tmp:
        base_ppm = os.path.join(tmp, "base.ppm")
        oiiotool(source, "--cut", CUT, "--resize", f"{WIDTH}x{HEIGHT}", "-d", "uint8", "-o", base_ppm)
        width, height, base = read_ppm(base_ppm)
        if (width, height) != (WIDTH, HEIGHT):
            raise SystemExit(f"unexpected size {width}x{height}")

        composite = bytearray(len(base))
        labels = bytearray(len(base))
        for y in range(height):
            for x in range(width):
                (gain, offset), colour = REGIONS[region_of(x, y)]
                i = (y * width + x) * 3
                for c in range(3):
                    v = gain * (base[i + c] / 255.0) + offset
                    composite[i + c] = int(round(min(max(v, 0.0), 1.0) * 255.0))
                    labels[i + c] = colour[c]

        for name, pixels in (("weir_composite", composite), ("weir_labels", labels)):
            ppm = os.path.join(tmp, name + ".ppm")
            write_ppm(ppm, width, height, pixels)
            oiiotool("--nosoftwareattrib", ppm, "--iscolorspace", "sRGB", "-d", "uint8",
                     "-o", os.path.join(out_dir, name + ".png"))


if __name__ == "__main__":
    main()
