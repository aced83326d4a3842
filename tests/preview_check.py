"""Checks for tests/preview_test.sh: images and cubes read with OpenImageIO, compared with numpy.

  same A B [--tolerance N] [--crop X,Y,W,H]   A (or its crop) equals B within N counts (default 1)
  pair IMG (match|differ) [--counts N]        the metameric pair's patches (centres of the left and
                                              right quarters) match within N counts, or differ by
                                              more than N in some channel
  differ A B [--counts N]                     the base patch differs by more than N between A and B
  cube A B                                    two spectral cubes are equal to float rounding
  tagged A B                                  PNG A carries B's colour tag: the same sRGB or iCCP
                                              chunk (OpenImageIO calls untagged PNGs sRGB too, so
                                              the chunks are read from the bytes)
"""
import argparse
import os
import sys

import numpy as np
import OpenImageIO as oiio

# The script tests' one PNG chunk reader.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "python"))
from check_ordinary_tools import png_chunks  # noqa: E402


def read(path):
    """The pixels as stored: counts for PNGs (8 or 16 bits), floats for EXRs."""
    buf = oiio.ImageBuf(path)
    if buf.has_error or buf.spec().width == 0:
        sys.exit(f"FAIL: cannot read {path}: {buf.geterror()}")
    return buf.get_pixels(buf.spec().format).astype(np.float64), buf.spec()


def counts(path):
    return read(path)[0]


def colour_chunks(path):
    """The colour-space chunks of a PNG (sRGB, iCCP, gAMA, cHRM) with their data."""
    return {k: v for k, v in png_chunks(path).items() if k in ("sRGB", "iCCP", "gAMA", "cHRM")}


def patch(img, fx):
    h, w = img.shape[:2]
    y, x = h // 2, int(w * fx)
    return img[y - 4:y + 5, x - 4:x + 5, :3].reshape(-1, 3).mean(axis=0)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("what")
    ap.add_argument("a")
    ap.add_argument("b", nargs="?")
    ap.add_argument("--tolerance", type=float, default=1.0)
    ap.add_argument("--crop")
    ap.add_argument("--counts", type=float, default=1.0)
    args = ap.parse_args()
    if args.what == "same":
        a, b = counts(args.a), counts(args.b)
        if args.crop:
            x, y, w, h = (int(v) for v in args.crop.split(","))
            a = a[y:y + h, x:x + w]
        if a.shape != b.shape:
            sys.exit(f"FAIL: {args.a} is {a.shape}, {args.b} is {b.shape}")
        d = np.abs(a - b)
        print(f"{args.a} vs {args.b}: max difference {d.max():g} counts, {int((d > 0).sum())} values differ")
        if d.max() > args.tolerance:
            sys.exit(f"FAIL: more than {args.tolerance:g} counts apart")
    elif args.what == "pair":
        img = counts(args.a)
        base, metamer = patch(img, 0.25), patch(img, 0.75)
        d = np.abs(base - metamer).max()
        print(f"{args.a}: base {base.round(1)}, metamer {metamer.round(1)}, largest difference {d:.1f} counts")
        if args.b == "match" and d > args.counts:
            sys.exit(f"FAIL: the pair should match within {args.counts:g} counts")
        if args.b == "differ" and d <= args.counts:
            sys.exit(f"FAIL: the pair should differ by more than {args.counts:g} counts")
    elif args.what == "differ":
        a, b = patch(counts(args.a), 0.25), patch(counts(args.b), 0.25)
        d = np.abs(a - b).max()
        print(f"base patch: {a.round(1)} vs {b.round(1)}, largest difference {d:.1f} counts")
        if d <= args.counts:
            sys.exit(f"FAIL: the base patch should change by more than {args.counts:g} counts")
    elif args.what == "cube":
        a, sa = read(args.a)
        b, sb = read(args.b)
        if a.shape != b.shape or list(sa.channelnames) != list(sb.channelnames):
            sys.exit(f"FAIL: {args.a} and {args.b} differ in size or channels")
        d = np.abs(a - b).max()
        scale = np.abs(b).max()
        print(f"cubes: {a.shape[2]} channels, max abs difference {d:g} (largest value {scale:g})")
        if d > 1e-6 * scale:
            sys.exit("FAIL: the cubes differ")
    elif args.what == "tagged":
        a, b = colour_chunks(args.a), colour_chunks(args.b)
        print(f"{args.a}: {sorted(a)}; {args.b}: {sorted(b)}")
        if not b or a != b:
            sys.exit(f"FAIL: {args.a} should carry the same colour chunks as {args.b}")
    else:
        sys.exit(f"unknown check {args.what}")


main()
